// geotex surfels IN -o OUT.ply: surfel reconstruction of a point cloud (thesis ch. 7 with k-nearest-neighbour
// neighbourhoods); writes oriented points (x y z nx ny nz).

#include <cctype>

#include <fmt/format.h>

#include "cli.h"
#include "geotex/denoise/surfel.h"
#include "geotex/core/user_files.h"

namespace geotex::cli {
namespace {

struct Args {
  std::string input, output, points = "centers";
  int neighbors = 10, normal_neighbors = 10;
  bool ascii = false;
  SurfelOptions opt;
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

void run(Args a) {
  check_output(a.input, a.output);
  if (lower_ext(a.output) != ".ply") throw InvalidInput(fmt::format("{}: the output must be a .ply file", a.output));
  const MatrixX3d X = read_points(a.input);
  info(fmt::format("{} points", X.rows()));
  const Neighborhoods N = knn_neighborhoods(X, a.neighbors);
  const Surfels S0 = surfels_from_normals(X, pca_normals(X, a.normal_neighbors));
  if (a.opt.unit_length == 0) a.opt.unit_length = mean_neighbor_spacing(X);
  a.opt.progress = progress_printer("surfels");
  const SurfelResult r = optimize_surfels(X, N, S0, a.opt);
  info(fmt::format("energy {:.4g} -> {:.4g} in {} sweeps (unit length {:.4g})", r.initial_energy,
                   r.energy.empty() ? r.initial_energy : r.energy.back(), r.energy.size(), r.unit_length));
  const MatrixX3d P = a.points == "centers" ? surfel_centers(X, r.surfels) : X;
  Mesh cloud;
  for (Eigen::Index i = 0; i < P.rows(); ++i) cloud.add_vertex(to_point(P.row(i).transpose()));
  PlyExtras extras;
  for (int k = 0; k < 3; ++k) {
    auto& col = extras.vertex_scalars[std::string("n") + "xyz"[k]];
    col.resize(P.rows());
    for (Eigen::Index i = 0; i < P.rows(); ++i) col[i] = r.surfels.normals(i, k);
  }
  write_ply(cloud, a.output, extras, !a.ascii);
  info(fmt::format("wrote {} ({} oriented points)", a.output, P.rows()));
}

Registrar reg{55, "surfels", "Surfel reconstruction of a point cloud (thesis ch. 7, kNN neighbourhoods): oriented points out",
              [](CLI::App& app) {
  auto a = std::make_shared<Args>();
  app.add_option("IN", a->input, "points: PLY, OBJ (faces ignored), XYZ/PTS/TXT (x y z per line), or another mesh format")
      ->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", a->output, "output PLY with vertex x y z nx ny nz")->required();
  app.add_option("--neighbors", a->neighbors, "k nearest neighbours forming each surfel's neighbourhood")
      ->check(CLI::Range(1, 1000))->capture_default_str();
  app.add_option("--normal-neighbors", a->normal_neighbors, "k nearest neighbours for the initial PCA normals")
      ->check(CLI::Range(2, 1000))->capture_default_str();
  app.add_option("--alpha", a->opt.alpha, "data weight alpha (Eq. 7.16)")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--beta", a->opt.beta, "parallelism weight beta (Eq. 7.14)")->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--t-start", a->opt.t_start_deg, "first angle threshold, degrees")->check(CLI::Range(1e-6, 180.0))->capture_default_str();
  app.add_option("--t-end", a->opt.t_end_deg, "last angle threshold, degrees")->check(CLI::Range(1e-6, 180.0))->capture_default_str();
  app.add_option("--iterations", a->opt.iterations, "number of threshold values (ICM sweeps)")
      ->check(CLI::Range(0, 100000))->capture_default_str();
  app.add_option("--unit", a->opt.unit_length, "unit length; 0 = mean spacing to the 6 nearest neighbours")
      ->check(CLI::NonNegativeNumber)->capture_default_str();
  app.add_option("--points", a->points, "output positions: centers (surfel centres, Eq. 7.6) or input")
      ->check(CLI::IsMember({"centers", "input"}))->capture_default_str();
  app.add_flag("--ascii", a->ascii, "ascii PLY output");
  app.callback([a] { run(*a); });
}};

}  // namespace
}  // namespace geotex::cli
