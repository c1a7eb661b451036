// geotex surfels IN -o OUT.ply: surfel reconstruction of a point cloud (thesis ch. 7 with k-nearest-neighbour
// neighbourhoods); writes oriented points (x y z nx ny nz).

#include <cctype>

#include <fmt/format.h>

#include "cli.h"
#include "option_flags.h"
#include "geotex/denoise/point_surfels.h"
#include "geotex/core/user_files.h"

namespace geotex::cli {
namespace cmd_surfels {  // named, not anonymous: a unity build compiles several commands in one unit

struct Args {
  std::string input, output, points = "centers";
  bool ascii = false;
};

std::string lower_ext(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// Points of a PLY (vertex x y z), an OBJ (`v` lines; faces ignored), an XYZ/PTS/TXT (three numbers
// per line, extra columns ignored): geotex::read_point_file(); or any other mesh format geotex reads.
MatrixX3d read_points(const std::string& path) {
  if (is_point_file(path)) return read_point_file(path);
  const MatrixX3d P = positions(load_mesh(path));
  if (P.rows() == 0) throw InvalidInput(fmt::format("{}: no points", path));
  if (!P.allFinite()) throw InvalidInput(fmt::format("{}: non-finite coordinate", path));
  return P;
}

void run(const Args& a, PointSurfelOptions o) {
  Outputs out({a.input}, {{a.output, "-o"}});
  if (lower_ext(a.output) != ".ply") throw InvalidInput(fmt::format("{}: the output must be a .ply file", a.output));
  const MatrixX3d X = read_points(a.input);
  info(fmt::format("{} points", X.rows()));
  o.progress = progress_printer("surfels");
  const PointSurfelResult ps = point_surfels(X, o);
  const SurfelResult& r = ps.surfels;
  info(fmt::format("energy {:.4g} -> {:.4g} in {} sweeps (unit length {:.4g})", r.initial_energy,
                   r.energy.empty() ? r.initial_energy : r.energy.back(), r.energy.size(), r.unit_length));
  const MatrixX3d P = a.points == "centers" ? ps.centers : X;
  Mesh cloud;
  for (Eigen::Index i = 0; i < P.rows(); ++i) cloud.add_vertex(to_point(P.row(i).transpose()));
  PlyExtras extras;
  for (int k = 0; k < 3; ++k) {
    auto& col = extras.vertex_scalars[std::string("n") + "xyz"[k]];
    col.resize(P.rows());
    for (Eigen::Index i = 0; i < P.rows(); ++i) col[i] = r.surfels.normals(i, k);
  }
  write_ply(cloud, a.output, extras, !a.ascii);
  out.commit();
  info(fmt::format("wrote {} ({} oriented points)", a.output, P.rows()));
}

Registrar reg{55, "surfels", "Surfel reconstruction of a point cloud (thesis ch. 7, kNN neighbourhoods): oriented points out",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "points: PLY, OBJ (faces ignored), XYZ/PTS/TXT (x y z per line), or another mesh format")
      ->required()->check(ExistingFile);
  app.add_option("-o,--output", a->output, "output PLY with vertex x y z nx ny nz")->required();
  auto flags = std::make_shared<FlagSet>(app);
  flags->add("surfels", PointSurfelOptions::table());
  app.add_option("--points", a->points, "output positions: centers (surfel centres, Eq. 7.6) or input")
      ->check(CLI::IsMember({"centers", "input"}))->capture_default_str();
  app.add_flag("--ascii", a->ascii, "ascii PLY output");
  app.callback([a, flags] { run(*a, flags->resolve<PointSurfelOptions>("surfels")); });
}};

}  // namespace cmd_surfels
}  // namespace geotex::cli
