#pragma once
//! \file surfel.h Surfel-based reconstruction of piecewise-smooth surfaces from noisy meshes and
//! point clouds (thesis ch. 7, Andersen et al., TPCG 2010).
//!
//! Every data point x_i carries a small plane, a surfel s_i = (n_i, a_i) (Eq. 7.4) whose points r
//! satisfy n_i·r = a_i (Eq. 7.5) and whose centre is c_i = x_i − (n_i·x_i − a_i) n_i (Eq. 7.6).
//! An MRF energy (Eq. 7.8–7.16) of likelihood, parallelism and overlap, weighted by a sigmoid of
//! the normal difference with a decreasing threshold (Sec. 7.4.3.4), is minimised by ICM with
//! simultaneous (Jacobi) updates (Sec. 7.4.3.5). The surface is retrieved as the dual mesh whose
//! vertices are quadric-error-metric intersections of surfel planes (Sec. 7.4.4), or by moving
//! each vertex to its surfel centre (primal retrieval).
//!
//! Lengths inside the energy are measured in the unit length of Sec. 7.4.3.4: the mean edge length
//! of the input mesh, or the mean neighbour spacing of a point cloud.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"

namespace geotex {

//! One surfel: unit normal n and offset a of its plane n·r = a (Eq. 7.4–7.5).
struct Surfel {
  Vec3 n = Vec3::UnitZ();
  double a = 0;
};

//! A set of surfels, one per data point.
struct Surfels {
  MatrixX3d normals;        //!< #P by 3 unit normals n_i
  Eigen::VectorXd offsets;  //!< #P plane offsets a_i
  Eigen::Index size() const { return offsets.size(); }
  Surfel operator[](Eigen::Index i) const { return {normals.row(i).transpose(), offsets[i]}; }
};

//! Neighbourhoods N_i in compressed rows: the neighbours of i are indices[offsets[i] .. offsets[i+1]).
struct Neighborhoods {
  std::vector<int> offsets{0};
  std::vector<int> indices;
  Eigen::Index size() const { return static_cast<Eigen::Index>(offsets.size()) - 1; }
};

//! The one-ring of every vertex (Sec. 7.4.3.2: "the summation covers a one-ring").
Neighborhoods one_ring_neighborhoods(const Mesh& mesh);

//! The \p k nearest other points of every point (nanoflann kd-tree); the neighbourhood for point clouds.
//! \param P #P by 3 points. \throw InvalidInput if k < 1 or #P <= k.
Neighborhoods knn_neighborhoods(const MatrixX3d& P, int k);

//! Unit length of a point cloud: the mean distance from each point to its \p k nearest neighbours
//! (k = 6 matches a mesh one-ring, whose mean edge length is the unit for meshes).
double mean_neighbor_spacing(const MatrixX3d& P, int k = 6);

//! Normals of a point cloud by PCA over the \p k nearest neighbours (smallest-eigenvalue direction
//! of the covariance), oriented consistently by propagation along a minimum spanning tree of the kNN
//! graph weighted by 1 − |n_i·n_j| (Hoppe et al. 1992); each connected part is then flipped so its
//! normals point away from its centroid on average (outward for closed shapes).
//! \return #P by 3 unit normals.
MatrixX3d pca_normals(const MatrixX3d& P, int k = 10);

//! Initial surfels s_i = (n_i, n_i·x_i) (Eq. 7.7). \param X #P by 3 data points, \param N #P by 3 normals.
Surfels surfels_from_normals(const MatrixX3d& X, const MatrixX3d& N);

//! Initial surfels of a mesh from area-weighted vertex normals (Sec. 7.4.2).
Surfels initial_surfels(const Mesh& mesh);

//! Surfel centres c_i = x_i − (n_i·x_i − a_i) n_i (Eq. 7.6). \return #P by 3.
MatrixX3d surfel_centers(const MatrixX3d& X, const Surfels& S);

//! Sigmoid angle weight w(Δn) = 1 / (1 + (Δn/t)²) (Eq. 7.12) with Δn = ‖n_i − n_j‖ (Eq. 7.13).
//! \param t_chord the threshold as a normal difference: an angle θ gives 2 sin(θ/2) (see threshold_chord()).
double surfel_weight(const Vec3& ni, const Vec3& nj, double t_chord);

//! The normal difference ‖n_i − n_j‖ of two unit normals at angle \p degrees: 2 sin(θ/2) (Fig. 7.3:
//! √2 is the right angle).
double threshold_chord(double degrees);

//! The pairwise terms between surfel i and its neighbour j, and their gradients with respect to
//! (n_i, a_i) as a free 4-vector (n_i not constrained to unit length; the order is nx, ny, nz, a).
struct SurfelPairTerms {
  double parallelism = 0;     //!< ‖n_i − n_j‖² (Eq. 7.9)
  double overlap_ij = 0;      //!< d(s_i, s_j)² with d(s_i, s_j) = n_j·c_i − a_j (Eq. 7.10)
  double overlap_ji = 0;      //!< d(s_j, s_i)² (c_j held fixed: it belongs to surfel j)
  Eigen::Vector4d grad_parallelism = Eigen::Vector4d::Zero();
  Eigen::Vector4d grad_overlap_ij = Eigen::Vector4d::Zero();
  Eigen::Vector4d grad_overlap_ji = Eigen::Vector4d::Zero();
};
SurfelPairTerms surfel_pair_terms(const Vec3& xi, const Surfel& si, const Vec3& xj, const Surfel& sj);

//! Likelihood (n_i·x_i − a_i)² (Eq. 7.8) and its gradient with respect to (n_i, a_i).
double surfel_likelihood(const Vec3& xi, const Surfel& si, Eigen::Vector4d* gradient = nullptr);

//! The energy of one surfel against fixed neighbours: the ICM site problem (Eq. 7.14–7.16)
//!   U_i = (1/W) Σ_j w_j (β‖n_i − n_j‖² + d(s_i,s_j)² + d(s_j,s_i)²) + α (n_i·x_i − a_i)²,  W = Σ_j w_j.
//! The weights w_j are computed from the previous configuration and held fixed during the local
//! minimisation (the normalisation by W keeps the optimiser from lowering the weights themselves).
struct SurfelSite {
  Vec3 x = Vec3::Zero();           //!< the data point x_i
  std::vector<Vec3> neighbor_x;    //!< x_j
  std::vector<Surfel> neighbors;   //!< s_j (previous configuration)
  std::vector<double> weights;     //!< w_j (Eq. 7.13), any positive scale (normalised by W)
  double alpha = 0.1;              //!< data weight α
  double beta = 100;               //!< parallelism weight β
};
//! U_i at surfel \p s (Eq. 7.16).
double surfel_site_energy(const SurfelSite& site, const Surfel& s);

//! Exact local minimiser of U_i under ‖n‖ = 1, started from \p start. Writing a = n·x − ρ, the energy
//! is quadratic in ρ for fixed n (solved in closed form) and a quadratic form in n for fixed ρ,
//! minimised on the unit sphere exactly (eigen-decomposition + secular equation, the trust-region
//! subproblem); the two exact block minimisations alternate until the surfel stops moving.
//! The energy never increases. \param sweeps the maximum number of alternations.
Surfel minimize_surfel_site(const SurfelSite& site, const Surfel& start, int sweeps = 30, double tolerance = 1e-12);

enum class SurfelNeighborhood {
  OneRing,  //!< mesh one-ring (the thesis)
  Knn       //!< k nearest data points, ignoring connectivity (point clouds)
};

struct SurfelOptions {
  double alpha = 0.1;             //!< data weight α (Eq. 7.16); the thesis used 0.1 and 0.01
  double beta = 100;              //!< parallelism weight β (Eq. 7.14); the thesis' typical value
  double t_start_deg = 45;        //!< first angle threshold t (Sec. 7.4.3.4: 45–60°)
  double t_end_deg = 10;          //!< last angle threshold t (Sec. 7.4.3.4: 10–20°), reached exponentially
  int iterations = 10;            //!< number of threshold values (ICM iterations; the thesis' "10 iterations")
  int iterations_per_threshold = 1;  //!< ICM sweeps at each threshold value
  double unit_length = 0;         //!< unit length; 0 = mean edge length / mean neighbour spacing
  int local_sweeps = 30;          //!< max alternations of the exact block minimisations per site
  bool record_energy = true;      //!< compute Σ_i U_i after each sweep (SurfelResult::energy; a pass of its own)
  //! Not in the thesis: also try the weights of each distinct neighbouring orientation and keep the
  //! surfel of least site energy with its own weights (Eq. 7.13); false = the current surfel's weights
  //! only (the thesis' single local minimisation).
  bool candidates = false;
  //! Not in the thesis: compute the weights (Eq. 7.12) from guidance normals, the mean normal of the most
  //! consistent one-ring patch each surfel belongs to (after guided mesh normal filtering), instead of
  //! from the surfels' own normals. The site energy then has fixed weights and candidates are not needed.
  bool guided = false;
  //! Not in the thesis: hold the weights at w² instead of w during each local minimisation. With
  //! lagged weights w (the thesis' scheme) the sweep is iteratively reweighted least squares for a
  //! Cauchy-type penalty log(1 + Δ²/t²), whose pull across a 90° edge at t = 20° is ~18× that of
  //! the stated parallelism energy βΔ²/(1 + Δ²/t²) (Eq. 7.12–7.14); w² are that energy's own IRLS
  //! weights, d/dΔ[Δ²/(1 + Δ²/t²)] = 2Δ w². Edges stay sharp over more sweeps: on Block0.4 the flat
  //! faces' surfel normals go from 22° (lagged) to 3.8° after 40 sweeps at t = 20° (bench/surfel.md).
  bool irls_weights = false;
  //! Not in the thesis: after the last sweep, move whole clusters of exactly parallel surfels to a
  //! neighbouring orientation where that lowers the summed site energy (Eq. 7.16) of the cluster and
  //! its neighbours. ICM moves one surfel at a time and cannot leave the zero-width chamfer that a
  //! noiseless cube's edges keep (each edge surfel at the bisector of its faces); a chain can.
  bool cluster_moves = false;
  ProgressFn progress;            //!< optional progress callback
};

struct SurfelResult {
  Surfels surfels;                     //!< optimised surfels (in the input's coordinates)
  std::vector<double> thresholds_deg;  //!< t used at each ICM sweep
  std::vector<double> energy;          //!< Σ_i U_i after each sweep (weights from that configuration), in unit lengths
  double initial_energy = 0;           //!< Σ_i U_i of the initial configuration at the first threshold
  double unit_length = 0;              //!< the unit length used
  int cluster_moves = 0;               //!< cluster moves made (SurfelOptions::cluster_moves)
};

//! Median angle (degrees) between the normals of neighbouring surfels: a robust measure of the normal
//! noise (sharp edges are a small fraction of the pairs). Used for an automatic first threshold.
double median_neighbor_angle_deg(const Surfels& S, const Neighborhoods& N);

//! The automatic first threshold (not in the thesis; bench/surfel.md): 0.85 × median_neighbor_angle_deg(\p initial,
//! \p N), clamped to [\p t_end_deg, 60°]: the threshold starts just below the typical normal noise.
double automatic_t_start_deg(const Surfels& initial, const Neighborhoods& N, double t_end_deg);

//! The tuned settings on \p base: IRLS weights, cluster moves, 30 iterations, automatic_t_start_deg().
//! Kept for the front ends until they call surfel_denoise(), whose defaults these are.
SurfelOptions tuned_surfel_options(const Surfels& initial, const Neighborhoods& N, SurfelOptions base = {});

//! Optimise surfels by ICM with simultaneous updates (Sec. 7.4.3.5) and the decreasing threshold
//! schedule t_k = t_start (t_end / t_start)^(k/(K−1)) (Sec. 7.4.3.4). OpenMP-parallel per sweep.
//! \param X #P by 3 data points, \param N their neighbourhoods, \param initial the starting surfels.
//! \throw InvalidInput on size mismatches, non-positive weights or thresholds, or no data.
SurfelResult optimize_surfels(const MatrixX3d& X, const Neighborhoods& N, const Surfels& initial,
                              const SurfelOptions& options = {});

//! A polygon mesh (the dual mesh before triangulation).
struct PolygonMesh {
  MatrixX3d vertices;                    //!< #V by 3
  std::vector<std::vector<int>> faces;   //!< vertex indices of each polygon, counter-clockwise
  std::vector<int> sites;                //!< surfel_dual_polygons(): the input vertex of each polygon
};

struct DualOptions {
  //! Eigenvalues of the plane quadric below this fraction of the largest are treated as zero: along
  //! those directions the planes (nearly) agree, and the vertex stays at the mean of the surfel centres.
  double eigen_threshold = 0.05;
  //! A dual vertex further than this (in mean edge lengths) from the mean of its surfel centres falls back to that mean.
  double max_shift = 3.0;
};

//! Dual-mesh retrieval (Sec. 7.4.4): one dual vertex per face, at the quadric-error-metric intersection
//! of the planes of its three vertices' surfels; one dual polygon per vertex (its faces in order;
//! a boundary vertex also gets its surfel centre and the boundary edges' plane intersections).
//! \param mesh the connectivity, \param X #V by 3 data points (usually the mesh's own positions).
PolygonMesh surfel_dual_polygons(const Mesh& mesh, const MatrixX3d& X, const Surfels& S, const DualOptions& options = {});

//! Triangulate a polygon mesh: each polygon as the fan (from one of its corners) whose triangles
//! face the polygon's mean normal best (among at most 32 evenly spaced corners: cost linear in the
//! polygon's size). \param face_polygon if given, receives the polygon of each triangle.
//! \throw InvalidInput if the result has no faces.
Mesh triangulate_polygons(const PolygonMesh& poly, std::vector<int>* face_polygon = nullptr);

//! Quadric-error-metric point for a set of planes (Garland & Heckbert): minimises Σ (n_k·p − a_k)²,
//! with directions whose eigenvalue is below \p eigen_threshold × the largest kept at \p p0.
Vec3 plane_quadric_point(const std::vector<Surfel>& planes, const Vec3& p0, double eigen_threshold = 0.05);

//! Primal retrieval: the mesh with every vertex moved to its surfel centre (Eq. 7.6); same connectivity.
Mesh surfel_primal_mesh(const Mesh& mesh, const MatrixX3d& X, const Surfels& S);

//! A target normal per face from the surfels: of its three corners' surfels, the one whose plane the
//! face's three surfel centres fit best (a face beside a sharp edge takes the plane of its own side,
//! not a corner's on the edge). \return #F by 3 unit normals.
MatrixX3d surfel_face_normals(const Mesh& mesh, const MatrixX3d& X, const Surfels& S);

//! Fitted retrieval (not in the thesis): from the data points, fit the vertices to the surfel face
//! normals (surfel_face_normals()) by the vertex update of Sun et al. 2007, \p iterations times; same
//! connectivity. Vertices beside a sharp edge move onto the intersection of the two sides' planes.
//! Each update also moves a vertex by \p tangential × (mean of its faces' centroids − vertex) along the
//! directions its faces' normals leave free (tangent plane, edge line, none at a corner): noise that
//! turned triangles over is untangled (10^6-face noisy cube: 8117 faces turned over → 2, mean normal
//! error 1.74° → 0.51°; 0 gives the plain update).
Mesh surfel_fitted_mesh(const Mesh& mesh, const MatrixX3d& X, const Surfels& S, int iterations = 20,
                        double tangential = 0.25);

//! Write a polygon mesh as OBJ, atomically. \throw IoError on failure.
void write_polygon_obj(const PolygonMesh& poly, const std::string& path);

// ---------------------------------------------------------------------------------------------
// The whole pipeline: neighbourhoods, initial surfels, optimisation, retrieval, edge labels.

enum class SurfelRetrieval {
  Dual,    //!< the dual mesh at surfel-plane intersections, triangulated (Sec. 7.4.4); new connectivity
  Primal,  //!< every vertex moved to its surfel centre (Eq. 7.6); same connectivity
  Fit      //!< vertices fitted to the surfel planes of their faces (surfel_fitted_mesh(), not in the thesis)
};
//! Weights held during each local minimisation (SurfelOptions::irls_weights).
enum class SurfelWeights {
  Lagged,  //!< w of Eq. (7.12), the thesis' scheme
  Irls     //!< w², the stated energy's own reweighting (keeps edges sharp over more sweeps)
};
//! Names: "ring|knn", "dual|primal|fit", "lagged|irls".
const EnumNames<SurfelNeighborhood>& surfel_neighborhood_names();
const EnumNames<SurfelRetrieval>& surfel_retrieval_names();
const EnumNames<SurfelWeights>& surfel_weight_names();

//! Options of surfel_denoise(). Defaults: the best measured settings (bench/surfel.md, bench/denoise.md);
//! preset "thesis": the thesis' own runs (Sec. 7.4.3.4–7.4.4: α 0.1, β 100, t 45° → 10° over 10
//! iterations, lagged weights, dual-mesh retrieval, nothing else).
struct SurfelDenoiseOptions {
  double alpha = 0.1;              //!< data weight α (Eq. 7.16)
  double beta = 100;               //!< parallelism weight β (Eq. 7.14)
  //! First angle threshold t, degrees; unset = automatic_t_start_deg() (from the normal noise).
  std::optional<double> t_start_deg;
  double t_end_deg = 10;           //!< last angle threshold t, degrees (Sec. 7.4.3.4: 10–20°)
  int iterations = 30;             //!< threshold values from t_start down to t_end (exponentially)
  int per_threshold = 1;           //!< ICM sweeps at each threshold
  bool candidates = false;         //!< SurfelOptions::candidates (not in the thesis)
  bool guided = false;             //!< SurfelOptions::guided (not in the thesis)
  SurfelWeights weights = SurfelWeights::Irls;  //!< lagged (thesis) or IRLS weights
  bool cluster_moves = true;       //!< SurfelOptions::cluster_moves (not in the thesis)
  SurfelRetrieval retrieval = SurfelRetrieval::Fit;  //!< how the surface is retrieved
  SurfelNeighborhood neighborhood = SurfelNeighborhood::OneRing;  //!< one-ring (thesis) or kNN
  int neighbors = 10;              //!< k with the kNN neighbourhood (and its PCA normals)
  int fit_iterations = 20;         //!< fit retrieval: vertex updates (Sun et al. 2007)
  double eigen_threshold = 0.05;   //!< dual retrieval: DualOptions::eigen_threshold
  ProgressFn progress;             //!< optional progress callback
  static const OptionTable<SurfelDenoiseOptions>& table();
};

struct SurfelDenoiseResult {
  //! The denoised mesh: the input's connectivity (primal, fit) or the triangulated dual mesh (dual).
  Mesh mesh;
  //! Per edge of \c mesh: 1 − w(‖n − n'‖) at the last threshold (Eq. 7.12; ½ at the threshold angle) between
  //! the planes of the edge's two sides: of its two faces (surfel_face_normals(); primal, fit), or of the
  //! surfels of its two dual polygons (dual); 0 on boundary edges and on the dual polygons' diagonals.
  Eigen::VectorXd edge_labels;
  PolygonMesh polygons;            //!< dual retrieval: the dual polygons (empty otherwise)
  SurfelResult surfels;            //!< optimised surfels, energies, thresholds, unit length
  double t_start_deg = 0;          //!< the first threshold used
  double median_angle_deg = 0;     //!< median angle between neighbouring initial surfels (the noise measure)
};

//! Surfel denoising of a mesh (thesis ch. 7): neighbourhoods, initial surfels, ICM, retrieval, labels.
//! \throw InvalidInput for an invalid mesh; InvalidOption for options out of range.
SurfelDenoiseResult surfel_denoise(const Mesh& mesh, const SurfelDenoiseOptions& options = {});

}  // namespace geotex
