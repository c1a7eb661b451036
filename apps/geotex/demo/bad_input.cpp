// Demo step for the bad-input catalogue (docs/bad-input.md): a broken copy of a sphere (flipped faces,
// a duplicate, a degenerate face, a pinched second sphere, a stray vertex) is read back repaired.

#include <fmt/format.h>

#include "cli.h"
#include "geotex/core/geometry.h"
#include "geotex/core/results.h"
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
  // The figures as `geotex info --json` names them (results.h: figures()).
  const std::string read = mesh_summary_results().figures(s, {"faces", "components", "closed"});
  const std::string repairs = read_report_results().figures(
      rep, {"flipped_faces", "split_vertices", "dropped_duplicate_faces", "dropped_degenerate_faces"});
  r["summary"].push_back(fmt::format("broken.obj ({} faces in the file) read as {}", rep.file_polygons, read));
  for (const auto& w : rep.warnings) r["summary"].push_back("  " + w);
  add_figure(ctx, {.mesh = "broken-repaired.ply",
                   .caption = fmt::format("broken.obj: two spheres touching at a vertex, 4 flipped faces, a duplicate, "
                                          "a degenerate face, a stray vertex; read as {} ({}).", read, repairs)});
  r["build"] = read_report_results().report(rep);
}};

}  // namespace demo_bad_input
}  // namespace geotex::cli
