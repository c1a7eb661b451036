// The surfel denoising pipeline (thesis ch. 7): neighbourhoods, initial surfels, the unit length,
// ICM, surface retrieval and edge labels, as one library call for the CLI and Python alike.

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

const EnumNames<SurfelNeighborhood>& surfel_neighborhood_names() {
  static const EnumNames<SurfelNeighborhood> n = {{"ring", SurfelNeighborhood::OneRing}, {"knn", SurfelNeighborhood::Knn}};
  return n;
}
const EnumNames<SurfelRetrieval>& surfel_retrieval_names() {
  static const EnumNames<SurfelRetrieval> n = {
      {"dual", SurfelRetrieval::Dual}, {"primal", SurfelRetrieval::Primal}, {"fit", SurfelRetrieval::Fit}};
  return n;
}
const EnumNames<SurfelWeights>& surfel_weight_names() {
  static const EnumNames<SurfelWeights> n = {{"lagged", SurfelWeights::Lagged}, {"irls", SurfelWeights::Irls}};
  return n;
}

const OptionTable<SurfelDenoiseOptions>& SurfelDenoiseOptions::table() {
  using O = SurfelDenoiseOptions;
  static const auto t = OptionTable<O>()
      .add("alpha", &O::alpha, "data weight alpha", non_negative(), "Eq. (7.16)")
      .add("beta", &O::beta, "parallelism weight beta", non_negative(), "Eq. (7.14)")
      .add("t_start", &O::t_start_deg,
           "first angle threshold t, degrees; auto: 0.85 x the median angle between neighbouring initial surfels",
           {0, 180, true, false}, "Sec. 7.4.3.4")
      .add("t_end", &O::t_end_deg, "last angle threshold t, degrees (reached exponentially)", {0, 180, true, false},
           "Sec. 7.4.3.4")
      .add("iterations", &O::iterations, "threshold values (ICM iterations) from t_start down to t_end", between(0, 100000),
           "Sec. 7.4.3.5")
      .add("per_threshold", &O::per_threshold, "ICM sweeps at each threshold", between(1, 1000))
      .alias("surfel_per_threshold")
      .add("candidates", &O::candidates,
           "also try the weights of each neighbouring orientation, keep the surfel of least energy (not in the thesis)")
      .alias("surfel_candidates")
      .add("guided", &O::guided, "weights from guidance normals of the most consistent one-ring patch (not in the thesis)")
      .alias("surfel_guided")
      .choice("weights", &O::weights, surfel_weight_names(),
              "weights held in each local minimisation: lagged (thesis, w) or irls (w^2, keeps edges sharp)", "Eq. (7.12-7.14)")
      .alias("surfel_weights")
      .add("cluster_moves", &O::cluster_moves,
           "move whole clusters of parallel surfels where that lowers the energy (not in the thesis)")
      .choice("retrieval", &O::retrieval, surfel_retrieval_names(),
              "dual: dual mesh at plane intersections (thesis; new connectivity); primal: vertices to surfel centres; "
              "fit: vertices fitted to the surfel planes of their faces",
              "Sec. 7.4.4")
      .choice("neighborhood", &O::neighborhood, surfel_neighborhood_names(),
              "ring: mesh one-ring (thesis); knn: k nearest vertices, connectivity ignored", "Sec. 7.4.3.2")
      .alias("surfel_neighborhood")
      .add("neighbors", &O::neighbors, "k of the knn neighbourhood (and of its PCA normals)", between(1, 1000))
      .add("fit_iterations", &O::fit_iterations, "fit retrieval: vertex updates (Sun et al. 2007)", between(0, 100000))
      .alias("surfel_fit_iterations")
      .add("eigen_threshold", &O::eigen_threshold,
           "dual retrieval: relative eigenvalue below which plane intersections are ill-determined", unit_interval())
      .alias("surfel_eigen_threshold")
      .preset("thesis", "the thesis' runs: alpha 0.1, beta 100, t 45 -> 10 deg over 10 iterations, lagged weights, dual mesh",
              [](O& o) {
                o.alpha = 0.1;  // Sec. 7.4.3.4 ("0.1 and 0.01 were typically used"; Fig. 7.5, fandisk: 0.1)
                o.beta = 100;   // "Typically used value is beta = 100"
                o.t_start_deg = 45;  // "start with ... 45-60 degrees", Fig. 7.4: 45
                o.t_end_deg = 10;    // "down to values of 10-20 degrees", Fig. 7.4: 10
                o.iterations = 10;   // Sec. 7.4.3.5: "a fixed number of iterations, usually 10"
                o.per_threshold = 1;
                o.candidates = false;
                o.guided = false;
                o.weights = SurfelWeights::Lagged;
                o.cluster_moves = false;
                o.retrieval = SurfelRetrieval::Dual;  // Sec. 7.4.4
                o.neighborhood = SurfelNeighborhood::OneRing;  // Sec. 7.4.3.2: "a one-ring"
              })
      .preset("tuned", "the defaults (the name of the tuned settings before they became the defaults)", [](O&) {});
  return t;
}

namespace {

// 1 − w(‖n_i − n_j‖) of surfels i and j at threshold chord \p chord (Eq. 7.12): ½ at the threshold angle.
double edge_label(const Surfels& S, int i, int j, double chord) {
  return 1.0 - surfel_weight(S.normals.row(i).transpose(), S.normals.row(j).transpose(), chord);
}

}  // namespace

SurfelDenoiseResult surfel_denoise(const Mesh& mesh, const SurfelDenoiseOptions& o) {
  SurfelDenoiseOptions::table().check(o);
  require_valid(mesh, "surfel input");
  if (o.t_start_deg && !(*o.t_start_deg > 0)) throw InvalidOption("t_start must be > 0 degrees");
  const MatrixX3d X = positions(mesh);

  // Neighbourhoods, initial surfels (Sec. 7.4.2) and the unit length (Sec. 7.4.3.4).
  SurfelOptions so;
  Neighborhoods N;
  Surfels S0;
  if (o.neighborhood == SurfelNeighborhood::OneRing) {
    N = one_ring_neighborhoods(mesh);
    S0 = initial_surfels(mesh);
    so.unit_length = mean_edge_length(mesh);
  } else {
    N = knn_neighborhoods(X, o.neighbors);
    S0 = surfels_from_normals(X, pca_normals(X, o.neighbors));
    so.unit_length = mean_neighbor_spacing(X);
  }

  SurfelDenoiseResult r;
  r.median_angle_deg = median_neighbor_angle_deg(S0, N);
  r.t_start_deg = o.t_start_deg ? *o.t_start_deg : automatic_t_start_deg(S0, N, o.t_end_deg);
  so.alpha = o.alpha;
  so.beta = o.beta;
  so.t_start_deg = r.t_start_deg;
  so.t_end_deg = o.t_end_deg;
  so.iterations = o.iterations;
  so.iterations_per_threshold = o.per_threshold;
  so.candidates = o.candidates;
  so.guided = o.guided;
  so.irls_weights = o.weights == SurfelWeights::Irls;
  so.cluster_moves = o.cluster_moves;
  so.progress = o.progress;
  r.surfels = optimize_surfels(X, N, S0, so);
  const Surfels& S = r.surfels.surfels;

  // Retrieval (Sec. 7.4.4) and edge labels at the last threshold.
  const double chord = threshold_chord(o.t_end_deg);
  if (o.retrieval == SurfelRetrieval::Dual) {
    DualOptions dual;
    dual.eigen_threshold = o.eigen_threshold;
    r.polygons = surfel_dual_polygons(mesh, X, S, dual);
    std::vector<int> face_polygon;
    r.mesh = triangulate_polygons(r.polygons, &face_polygon);
    // A dual edge between the polygons of input vertices i and j stands for the input edge (i, j).
    r.edge_labels = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(r.mesh.n_edges()));
    for (auto e : r.mesh.edges()) {
      if (r.mesh.is_boundary(e)) continue;
      const int p = face_polygon[r.mesh.face_handle(r.mesh.halfedge_handle(e, 0)).idx()];
      const int q = face_polygon[r.mesh.face_handle(r.mesh.halfedge_handle(e, 1)).idx()];
      if (p != q) r.edge_labels[e.idx()] = edge_label(S, r.polygons.sites[p], r.polygons.sites[q], chord);
    }
  } else {
    r.mesh = o.retrieval == SurfelRetrieval::Fit ? surfel_fitted_mesh(mesh, X, S, o.fit_iterations)
                                                 : surfel_primal_mesh(mesh, X, S);
    // An edge between faces that took different sides' planes (surfel_face_normals()) is on the crease;
    // an edge between two vertices' surfels would be beside it (both ends of a crease edge lie on both sides).
    const MatrixX3d FN = surfel_face_normals(mesh, X, S);
    r.edge_labels = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(r.mesh.n_edges()));
    for (auto e : r.mesh.edges()) {
      if (r.mesh.is_boundary(e)) continue;
      const int f = r.mesh.face_handle(r.mesh.halfedge_handle(e, 0)).idx();
      const int g = r.mesh.face_handle(r.mesh.halfedge_handle(e, 1)).idx();
      r.edge_labels[e.idx()] = 1.0 - surfel_weight(FN.row(f).transpose(), FN.row(g).transpose(), chord);
    }
  }
  return r;
}

}  // namespace geotex
