// Demo step for the bad-input catalogue (docs/bad-input.md): a broken copy of a sphere (flipped faces,
// a duplicate, a degenerate face, a pinched second sphere, a stray vertex) is read back repaired.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/shapes.h"

namespace geotex::cli {
namespace demo_bad_input {  // named, not anonymous: a unity build compiles several commands in one unit

DemoRegistrar step{15, "bad input", [](const DemoContext& ctx) {
  nlohmann::json& r = *ctx.report;
  const Mesh a = icosphere(2);
  const MatrixX3d Va = positions(a);
  MatrixX3i Fa = faces(a);
  for (int f : {3, 40, 41, 200}) std::swap(Fa(f, 1), Fa(f, 2));  // inconsistent orientation
  // A second sphere, the first mirrored through one of its vertices: they touch at that vertex, which
  // the file shares (a non-manifold vertex).
  const int touch = 0;
  const MatrixX3d Vb = (-Va).rowwise() + 2 * Va.row(touch);
  const int nv = static_cast<int>(Va.rows());
  std::string obj = "# a broken mesh written by geotex demo\n";
  for (Eigen::Index i = 0; i < Va.rows(); ++i) obj += fmt::format("v {} {} {}\n", Va(i, 0), Va(i, 1), Va(i, 2));
  for (Eigen::Index i = 0; i < Vb.rows(); ++i)
    if (i != touch) obj += fmt::format("v {} {} {}\n", Vb(i, 0), Vb(i, 1), Vb(i, 2));
  obj += "v 9 9 9\n";  // isolated
  auto vb = [&](int i) { return i == touch ? touch + 1 : nv + i - (i > touch ? 1 : 0) + 1; };  // 1-based
  for (Eigen::Index f = 0; f < Fa.rows(); ++f) obj += fmt::format("f {} {} {}\n", Fa(f, 0) + 1, Fa(f, 1) + 1, Fa(f, 2) + 1);
  const MatrixX3i Fb = faces(a);
  for (Eigen::Index f = 0; f < Fb.rows(); ++f) obj += fmt::format("f {} {} {}\n", vb(Fb(f, 0)), vb(Fb(f, 2)), vb(Fb(f, 1)));  // mirrored: reversed
  obj += fmt::format("f {} {} {}\n", Fa(0, 0) + 1, Fa(0, 1) + 1, Fa(0, 2) + 1);  // duplicate
  obj += "f 1 1 2\n";                                                              // degenerate
  const auto broken = ctx.dir / "broken.obj";
  write_text_atomic(broken, obj);
  ReadReport rep;
  const Mesh m = read_mesh(broken, {}, &rep);
  save_mesh(m, (ctx.dir / "broken-repaired.ply").string());
  const MeshSummary s = summarize(m);
  r["files"].push_back(broken.string());
  r["summary"].push_back(fmt::format("broken.obj ({} faces in the file) read as {} faces, {} components, closed: {}",
                                     rep.file_polygons, s.faces, s.components, s.closed ? "yes" : "no"));
  for (const auto& w : rep.warnings) r["summary"].push_back("  " + w);
  add_figure(ctx, {.mesh = "broken-repaired.ply",
                   .caption = fmt::format("broken.obj: two spheres touching at a vertex, 4 flipped faces, a duplicate, "
                                          "a degenerate face, a stray vertex; read as {} faces in {} components "
                                          "({} flipped faces turned, {} vertices split, {} duplicate and {} degenerate "
                                          "faces dropped).",
                                          s.faces, s.components, rep.build.flipped_faces, rep.build.split_vertices,
                                          rep.build.duplicate_faces, rep.build.degenerate_faces)});
  r["build"] = {{"flipped_faces", rep.build.flipped_faces},     {"split_vertices", rep.build.split_vertices},
                {"duplicate_faces", rep.build.duplicate_faces}, {"degenerate_faces", rep.build.degenerate_faces},
                {"isolated_vertices", rep.build.isolated_vertices}};
}};

}  // namespace demo_bad_input
}  // namespace geotex::cli
