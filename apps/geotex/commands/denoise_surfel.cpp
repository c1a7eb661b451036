// `geotex denoise --method surfel`: surfel-based reconstruction of piecewise-smooth surfaces (thesis ch. 7).

#include <algorithm>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "cli.h"
#include "denoise_methods.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/surfel.h"

namespace geotex::cli {
namespace {

struct SurfelArgs {
  double beta = 100, t_start = 45, t_end = 10;
  std::string retrieval = "dual", neighborhood = "ring", polygons;
  int neighbors = 10, per_threshold = 1, fit_iterations = 20;
  bool candidates = false, guided = false;
  std::string weights = "lagged", preset = "thesis";
  DualOptions dual;
  CLI::Option *t_start_opt = nullptr, *retrieval_opt = nullptr, *weights_opt = nullptr;
  std::optional<double> alpha;
  std::optional<int> iterations;
};


SurfelArgs& args() {
  static SurfelArgs a;
  return a;
}

void add_options(CLI::App& app) {
  SurfelArgs& a = args();
  const std::string g = "surfel";
  app.add_option("--beta", a.beta, "parallelism weight beta (Eq. 7.14)")->check(CLI::NonNegativeNumber)
      ->capture_default_str()->group(g);
  a.t_start_opt = app.add_option("--t-start", a.t_start, "first angle threshold t, degrees (Eq. 7.12, Sec. 7.4.3.4)")
      ->check(CLI::Range(1e-6, 180.0))->capture_default_str()->group(g);
  app.add_option("--t-end", a.t_end, "last angle threshold t, degrees (exponential decrease)")
      ->check(CLI::Range(1e-6, 180.0))->capture_default_str()->group(g);
  a.retrieval_opt = app.add_option("--retrieval", a.retrieval,
                 "dual: dual mesh at surfel-plane intersections (Sec. 7.4.4); primal: vertices moved to surfel centres; "
                 "fit: vertices fitted to the surfel planes of their faces (not in the thesis; same connectivity)")
      ->check(CLI::IsMember({"dual", "primal", "fit"}))->capture_default_str()->group(g);
  app.add_option("--neighbors", a.neighbors, "k nearest neighbours with --surfel-neighborhood knn")
      ->check(CLI::Range(1, 1000))->capture_default_str()->group(g);
  app.add_option("--surfel-neighborhood", a.neighborhood,
                 "ring: mesh one-ring (thesis); knn: k nearest vertices, connectivity ignored (point-cloud mode)")
      ->check(CLI::IsMember({"ring", "knn"}))->capture_default_str()->group(g);
  app.add_option("--surfel-per-threshold", a.per_threshold, "ICM sweeps at each threshold value")
      ->check(CLI::Range(1, 1000))->capture_default_str()->group(g);
  app.add_option("--surfel-candidates", a.candidates,
                 "also try the weights of each neighbouring orientation and keep the surfel of least energy "
                 "(false = the thesis' single local minimisation)")
      ->capture_default_str()->group(g);
  app.add_flag("--surfel-guided", a.guided,
               "not in the thesis: weights from guidance normals (mean normal of the most consistent one-ring patch)")
      ->group(g);
  a.weights_opt = app.add_option("--surfel-weights", a.weights,
                 "weights held during each local minimisation: lagged (the thesis: w of Eq. 7.12) or irls (w², the "
                 "stated energy's own reweighting; keeps edges sharp over more sweeps)")
      ->check(CLI::IsMember({"lagged", "irls"}))->capture_default_str()->group(g);
  app.add_option("--surfel-fit-iterations", a.fit_iterations, "fit retrieval: vertex updates (Sun et al. 2007)")
      ->check(CLI::Range(0, 100000))->capture_default_str()->group(g);
  app.add_option("--surfel-preset", a.preset,
                 "thesis: the thesis' defaults (alpha 0.1, beta 100, t 45 -> 10 deg, 10 iterations, lagged weights, "
                 "dual mesh); tuned (not in the thesis): irls weights, cluster moves, fit retrieval, 30 iterations and t from "
                 "0.85 x the median angle between neighbouring initial surfels down to 10 deg. Explicit flags override either")
      ->check(CLI::IsMember({"thesis", "tuned"}))->capture_default_str()->group(g);
  app.add_option("--surfel-eigen-threshold", a.dual.eigen_threshold,
                 "dual retrieval: relative eigenvalue below which plane intersections are ill-determined")
      ->check(CLI::Range(0.0, 1.0))->capture_default_str()->group(g);
  app.add_option("--polygons", a.polygons, "dual retrieval: also write the dual polygon mesh as OBJ")->group(g);
}

struct DenoiseCommon {  // interim, until the surfel pipeline has its library entry point and option table
  std::optional<double> alpha;
  std::optional<int> iterations;
  ProgressFn progress;
};

DenoiseOutput run(const Mesh& input, const DenoiseCommon& common) {
  const SurfelArgs& a = args();
  require_valid(input, "denoise input");
  const MatrixX3d X = positions(input);
  const bool tuned = a.preset == "tuned";
  const std::string retrieval = tuned && !a.retrieval_opt->count() ? "fit" : a.retrieval;
  SurfelOptions o;
  o.alpha = common.alpha.value_or(0.1);
  o.iterations = common.iterations.value_or(10);
  o.beta = a.beta;
  o.t_start_deg = a.t_start;
  o.t_end_deg = a.t_end;
  o.iterations_per_threshold = a.per_threshold;
  o.candidates = a.candidates;
  o.guided = a.guided;
  o.irls_weights = a.weights == "irls";
  o.progress = common.progress;
  Neighborhoods N;
  Surfels S0;
  if (a.neighborhood == "ring") {
    N = one_ring_neighborhoods(input);
    S0 = initial_surfels(input);
    o.unit_length = mean_edge_length(input);
  } else {
    N = knn_neighborhoods(X, a.neighbors);
    S0 = surfels_from_normals(X, pca_normals(X, a.neighbors));
    o.unit_length = mean_neighbor_spacing(X);
  }
  if (tuned) {  // the preset, under any flag given explicitly
    const SurfelOptions t = tuned_surfel_options(S0, N, o);
    if (!common.iterations) o.iterations = t.iterations;
    if (!a.t_start_opt->count()) o.t_start_deg = t.t_start_deg;
    if (!a.weights_opt->count()) o.irls_weights = t.irls_weights;
    o.cluster_moves = t.cluster_moves;
    info(fmt::format("surfel: median angle between neighbouring surfels {:.1f} deg: t from {:.1f} to {:.1f} deg",
                     median_neighbor_angle_deg(S0, N), o.t_start_deg, o.t_end_deg));
  }
  const SurfelResult r = optimize_surfels(X, N, S0, o);
  DenoiseOutput out;
  if (retrieval == "primal" || retrieval == "fit") {
    out.mesh = retrieval == "fit" ? surfel_fitted_mesh(input, X, r.surfels, a.fit_iterations) : surfel_primal_mesh(input, X, r.surfels);
    // Edge label: 1 − w at the last threshold (w = 1/2 at the threshold angle, Eq. 7.12).
    const double chord = threshold_chord(o.t_end_deg);
    out.edge_labels.resize(out.mesh.n_edges());
    for (auto e : out.mesh.edges()) {
      const auto h = out.mesh.halfedge_handle(e, 0);
      const int i = out.mesh.from_vertex_handle(h).idx(), j = out.mesh.to_vertex_handle(h).idx();
      out.edge_labels[e.idx()] = 1.0 - surfel_weight(r.surfels.normals.row(i).transpose(),
                                                     r.surfels.normals.row(j).transpose(), chord);
    }
  } else {
    const PolygonMesh poly = surfel_dual_polygons(input, X, r.surfels, a.dual);
    if (!a.polygons.empty()) {
      write_polygon_obj(poly, a.polygons);
      info(fmt::format("wrote {} ({} polygons)", a.polygons, poly.faces.size()));
    }
    out.mesh = triangulate_polygons(poly);
  }
  out.report["parameters"] = {{"alpha", o.alpha},         {"beta", o.beta},
                              {"t_start_deg", o.t_start_deg}, {"t_end_deg", o.t_end_deg},
                              {"iterations", o.iterations}, {"iterations_per_threshold", o.iterations_per_threshold},
                              {"candidates", o.candidates}, {"guided", o.guided}, {"weights", o.irls_weights ? "irls" : "lagged"}, {"preset", a.preset}, {"cluster_moves", r.cluster_moves}, {"retrieval", retrieval},
                              {"neighborhood", a.neighborhood}, {"neighbors", a.neighbors},
                              {"unit_length", r.unit_length}};
  out.report["initial_energy"] = r.initial_energy;
  out.report["energy"] = r.energy;
  out.report["thresholds_deg"] = r.thresholds_deg;
  return out;
}

DenoiseRegistrar reg{"surfel",
                     "surfels (thesis ch. 7): ICM on planes per vertex, dual-mesh retrieval at plane intersections",
                     [](FlagSet& f) {
                       add_options(f.app());
                       CLI::App& app = f.app();
                       app.add_option("--surfel-alpha", args().alpha, "data weight alpha (Eq. 7.16); default 0.1")->group("surfel");
                       app.add_option("--surfel-iterations", args().iterations, "number of thresholds; default 10")->group("surfel");
                     },
                     [](const FlagSet&) -> DenoiseRun {
                       return [](const Mesh& mesh, const ProgressFn& progress) {
                         DenoiseCommon c;
                         c.alpha = args().alpha;
                         c.iterations = args().iterations;
                         c.progress = progress;
                         return run(mesh, c);
                       };
                     }};

}  // namespace
}  // namespace geotex::cli
