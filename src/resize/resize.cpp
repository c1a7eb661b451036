#include "geotex/resize/resize.h"

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/weld.h"
#include "geotex/core/spatial.h"
#include "geotex/toolkit/editing.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

SpaceMap scale_map(const Vec3& s, const Vec3& centre) {
  return [s, centre](const Vec3& x) -> Vec3 { return centre + s.cwiseProduct(x - centre); };
}

SpaceMap bend_map(double kappa, double x0) {
  return [kappa, x0](const Vec3& x) -> Vec3 { return {x.x(), x.y(), x.z() + 0.5 * kappa * (x.x() - x0) * (x.x() - x0)}; };
}

SpaceMap twist_map(double tau, double x0) {
  return [tau, x0](const Vec3& x) -> Vec3 {
    const double a = tau * (x.x() - x0), c = std::cos(a), s = std::sin(a);
    return {x.x(), c * x.y() - s * x.z(), s * x.y() + c * x.z()};
  };
}

SpaceMap arc_map(double radius, double x0, double z0) {
  return [radius, x0, z0](const Vec3& x) -> Vec3 {
    const double theta = (x.x() - x0) / radius, r = radius - (x.z() - z0);
    return {x0 + r * std::sin(theta), x.y(), z0 + radius - r * std::cos(theta)};
  };
}

const OptionTable<SpaceMapOptions>& SpaceMapOptions::table() {
  using O = SpaceMapOptions;
  static const auto t = OptionTable<O>()
      .add("scale", &O::scale, "anisotropic scale sx,sy,sz about the bounding-box centre", between(1e-6, 1e6))
      .add("twist", &O::twist, "twist about the x axis through the box centre, radians per unit length")
      .add("bend", &O::bend, "shear bend along x: z += K (x - x_centre)^2 / 2")
      .add("arc_radius", &O::arc_radius, "bend the x axis into an arc of this radius about the box centre (0: none)",
           non_negative());
  return t;
}

SpaceMap space_map(const SpaceMapOptions& o, const BoundingBox& box) {
  check_options(o);
  const Vec3 c = box.center();
  std::vector<SpaceMap> parts;
  if (o.scale != Vec3::Ones()) parts.push_back(scale_map(o.scale, c));
  if (o.twist != 0) {  // about the line through the centre along x
    const SpaceMap tw = twist_map(o.twist, c.x());
    parts.push_back([tw, c](const Vec3& x) -> Vec3 {
      const Vec3 off(0, c.y(), c.z());
      return tw(x - off) + off;
    });
  }
  if (o.bend != 0) parts.push_back(bend_map(o.bend, c.x()));
  if (o.arc_radius > 0) parts.push_back(arc_map(o.arc_radius, c.x(), c.z()));
  return [parts](const Vec3& x) -> Vec3 {
    Vec3 y = x;
    for (const SpaceMap& m : parts) y = m(y);
    return y;
  };
}

const EnumNames<ResizeMethod>& resize_method_names() {
  static const EnumNames<ResizeMethod> names = {
      {"auto", ResizeMethod::Auto}, {"similarity", ResizeMethod::Similarity}, {"sliding", ResizeMethod::Sliding},
      {"thesis", ResizeMethod::Thesis}, {"axis", ResizeMethod::Axis}, {"axis-similarity", ResizeMethod::AxisSimilarity}};
  return names;
}

const EnumNames<SimilaritySolver>& similarity_solver_names() {
  static const EnumNames<SimilaritySolver> names = {{"split", SimilaritySolver::Split}, {"coupled", SimilaritySolver::Coupled}};
  return names;
}

const OptionTable<ResizeOptions>& ResizeOptions::table() {
  using O = ResizeOptions;
  static const auto t = OptionTable<O>()
      .choice("method", &O::method, resize_method_names(),
              "auto (default: axis-similarity for a box scale, similarity for a bend, twist, arc or deformed copy), "
              "similarity (continuous weights: near-similarities where important), "
              "sliding (binary features rigid, background slides along the surface), thesis (Eq. 9.2-9.3), axis "
              "(box scales: a separable axis-aligned warp, Kraevoy et al. 2008) or axis-similarity (the axis warp, "
              "then similarity from it)", "Sec. 9.4")
      .add("position_weight", &O::position_weight, "w: weight of the position terms against the feature terms",
           positive(), "Eq. (9.2)")
      .alias("weight")
      .add("keep_feature_size", &O::keep_feature_size,
           "features keep their size (T_i rotations); false: T_i similarities, features scale with the map", {},
           "Sec. 9.4")
      .alias("scale_features", "false")
      .add("square_weights", &O::square_weights,
           "thesis: weigh the energy by f_i^2 and (w p_i)^2, as the least-squares system of Eq. (9.3) does", {},
           "Eq. (9.3)")
      .add("background_smoothness", &O::background_smoothness, "sliding: weight of the background's membrane term",
           positive())
      .alias("smoothness")
      .add("transition", &O::transition,
           "sliding: width of the band around features where the stretch passes to the space map's, in units of "
           "sqrt(area / 4 pi)", non_negative())
      .add("frame_weight", &O::frame_weight, "sliding: weight pinning the frame (boundary, box extremes) to the map",
           positive())
      .add("frame_band", &O::frame_band,
           "sliding: a feature this many mean edge lengths from a box face reaches it (and is pushed to keep the box)",
           non_negative())
      .add("refinements", &O::refinements, "sliding: extra re-projections onto the deformed surface", between(0, 10))
      .add("taper", &O::taper, "sliding: feature weights fall off linearly over this many vertex rings outside features",
           between(0, 10000))
      .add("bend_features", &O::bend_features,
           "sliding: elongated features (ridges) bend with their base; false: every feature turns as one rigid piece")
      .add("iterations", &O::iterations,
           "similarity: local-global rounds (rotations refitted to the solution, surface re-projected)", between(0, 20))
      .add("surface_weight", &O::surface_weight,
           "similarity: weight holding unimportant vertices to the plainly stretched surface (along its normal)",
           positive())
      .add("adapt_scale", &O::adapt_scale,
           "similarity: important regions scale uniformly as fits the solution best, between the map's smallest "
           "and largest local stretch (as similar as possible); false: the scale of keep_feature_size")
      .choice("solver", &O::solver, similarity_solver_names(),
              "similarity: split (the surface term by alternation, x, y, z solved apart: default, fast) or coupled "
              "(one 3#V system with the surface term in it)")
      .add("split_steps", &O::split_steps, "similarity, split solver: alternation steps per local-global round",
           between(1, 20))
      .add("flip_rounds", &O::flip_rounds,
           "similarity: rounds relaxing faces turned over against the plain map to it", between(0, 20))
      .add("flip_rings", &O::flip_rings, "similarity: vertex rings relaxed around a turned-over face", between(0, 100))
      .choice("laplacian", &O::laplacian, laplacian_names(), "Laplacian of the feature terms (Eq. 9.1: umbrella)",
              "Eq. (9.1)")
      .add("rigid_protrusions", &O::rigid_protrusions,
           "similarity, axis-similarity: protrusions (tentacles, ears, horns) placed as rigid pieces at their size on "
           "where their foot went, the rest of the model stretched to hold them in the box where it is mostly "
           "unimportant and that room settles (else the method's result stands); false: per-vertex similarities only")
      .add("untangle", &O::untangle,
           "axis-similarity: where the result crosses itself beyond the input's own, move the colliding parts apart, "
           "then blend what still crosses back towards the axis warp over a smooth bump until nothing does; false: "
           "only count them (every method counts them)")
      .add("weld", &O::weld,
           "similarity, axis, axis-similarity: solve on the mesh with coincident vertices welded (unwelded patches as "
           "one surface), parts touching at a point or resting with a rim on another part's faces held together (the "
           "teapot's handle), through the repairs too; false: the mesh as stored, each patch and part solved apart")
      .nest(&O::axis, AxisWarpOptions::table(), "axis_")
      .preset("thesis", "the thesis' method as written: Eq. (9.2) with Eq. (9.3)'s squared weights, T_i similarities "
              "(rotation and scale), umbrella Laplacian",
              [](O& o) {
                o.method = ResizeMethod::Thesis;
                o.square_weights = true;
                o.keep_feature_size = false;
                o.laplacian = LaplacianType::Umbrella;
              });
  return t;
}

namespace {

// Block-diagonal copy of a #V×#V matrix onto the x, y and z blocks of a 3#V×3#V one.
void add_blocks(std::vector<Triplet>& t, const SparseMatrix& A, int n) {
  for (int d = 0; d < 3; ++d)
    for (int col = 0; col < A.outerSize(); ++col)
      for (SparseMatrix::InnerIterator it(A, col); it; ++it)
        t.emplace_back(d * n + static_cast<int>(it.row()), d * n + static_cast<int>(it.col()), it.value());
}

Eigen::VectorXd stack(const MatrixX3d& X) {
  const Eigen::Index n = X.rows();
  Eigen::VectorXd v(3 * n);
  for (int d = 0; d < 3; ++d) v.segment(d * n, n) = X.col(d);
  return v;
}

MatrixX3d unstack(const Eigen::VectorXd& v) {
  const Eigen::Index n = v.size() / 3;
  MatrixX3d X(n, 3);
  for (int d = 0; d < 3; ++d) X.col(d) = v.segment(d * n, n);
  return X;
}

// Frame of the Sliding method: the mesh boundary (a plate's rim), pinned to the map. The box is kept
// by pinning single extreme vertices along their axis (and by pushing features at the extremes, see
// sliding_resize), not by pinning a band at the box's faces: extremes are often features' tips (ears,
// horns), which a pinned band would stretch.
struct Frame {
  std::vector<char> vertex;  // #V: 1 for boundary vertices
  Vec3 lo, hi;               // the box
  double band = 0;           // a feature within this distance of a box face reaches it
  std::array<bool, 3> axis{};  // axes the mesh really extends along
};

Frame frame_of(const Mesh& mesh, const MatrixX3d& X, double band_edges) {
  const int n = static_cast<int>(X.rows());
  Frame fr;
  fr.vertex.assign(n, 0);
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v)) fr.vertex[v.idx()] = 1;
  fr.lo = X.colwise().minCoeff();
  fr.hi = X.colwise().maxCoeff();
  const Vec3 ext = fr.hi - fr.lo;
  fr.band = band_edges * mean_edge_length(mesh);
  for (int a = 0; a < 3; ++a) fr.axis[a] = ext[a] >= 0.25 * ext.maxCoeff();
  return fr;
}

// Connected feature regions (vertices with f > 0) and their foot rings (the background vertices next
// to them).
struct Regions {
  std::vector<int> id;  // #V: region of each vertex, −1 for the background
  std::vector<std::vector<int>> members, foot;
};

Regions feature_regions(const Mesh& mesh, const Eigen::VectorXd& f) {
  const int n = static_cast<int>(mesh.n_vertices());
  Regions r;
  r.id.assign(n, -1);
  std::vector<int> stack, foot_mark(n, -1);
  for (int seed = 0; seed < n; ++seed) {
    if (f[seed] <= 0 || r.id[seed] >= 0) continue;
    const int k = static_cast<int>(r.members.size());
    r.members.emplace_back();
    r.foot.emplace_back();
    r.id[seed] = k;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      r.members[k].push_back(v);
      for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
        const int j = w.idx();
        if (f[j] > 0) {
          if (r.id[j] < 0) { r.id[j] = k; stack.push_back(j); }
        } else if (foot_mark[j] != k) {
          foot_mark[j] = k;
          r.foot[k].push_back(j);
        }
      }
    }
  }
  return r;
}

// The features with a taper: every vertex within \p rings rings of a feature region (ring distance d)
// gets weight (1 − d / (rings + 1)) f_s from its nearest feature vertex s and belongs to that vertex's
// region. Regions stay apart where their tapers meet (no rigid bridge between two features).
Regions tapered_regions(const Mesh& mesh, const Eigen::VectorXd& features, int rings, Eigen::VectorXd& f) {
  const int n = static_cast<int>(mesh.n_vertices());
  Regions r = feature_regions(mesh, features);
  f = features;
  std::vector<int> dist(n, -1), source(n, -1), queue;
  for (int i = 0; i < n; ++i)
    if (r.id[i] >= 0) {
      dist[i] = 0;
      source[i] = i;
      queue.push_back(i);
    }
  for (size_t q = 0; q < queue.size(); ++q) {
    const int v = queue[q];
    if (dist[v] >= rings) continue;
    for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
      const int j = w.idx();
      if (dist[j] >= 0) continue;
      dist[j] = dist[v] + 1;
      source[j] = source[v];
      r.id[j] = r.id[v];
      f[j] = (1.0 - dist[j] / (rings + 1.0)) * features[source[v]];
      queue.push_back(j);
    }
  }
  for (auto& m : r.members) m.clear();
  for (auto& ft : r.foot) ft.clear();
  std::vector<int> foot_mark(n, -1);
  for (int i = 0; i < n; ++i)
    if (r.id[i] >= 0) r.members[r.id[i]].push_back(i);
  for (size_t k = 0; k < r.members.size(); ++k)
    for (int v : r.members[k])
      for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
        const int j = w.idx();
        if (r.id[j] != static_cast<int>(k) && foot_mark[j] != static_cast<int>(k)) {
          foot_mark[j] = static_cast<int>(k);
          r.foot[k].push_back(j);
        }
      }
  return r;
}

Similarity fit_rows(const MatrixX3d& X, const MatrixX3d& C, const std::vector<int>& rows, bool allow_scale) {
  Eigen::MatrixX3d P(rows.size(), 3), Q(rows.size(), 3);
  for (size_t k = 0; k < rows.size(); ++k) {
    P.row(k) = X.row(rows[k]);
    Q.row(k) = C.row(rows[k]);
  }
  return fit_similarity(P, Q, allow_scale);
}

// The space map's local linear part J_i at every vertex: the least-squares linear map of the closed
// 1-ring's edge vectors (about its centroid) onto the deformed ones, with the vertex normal mapped to
// the deformed normal (a 1-ring is nearly planar and leaves the normal direction undetermined).
std::vector<Eigen::Matrix3d> local_jacobians(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C) {
  const int n = static_cast<int>(X.rows());
  Mesh deformed = mesh;
  set_positions(deformed, C);
  const MatrixX3d N0 = vertex_normals(mesh), N1 = vertex_normals(deformed);
  std::vector<Eigen::Matrix3d> J(n, Eigen::Matrix3d::Identity());
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < n; ++i) {
    const auto vh = mesh.vertex_handle(i);
    if (mesh.is_isolated(vh)) continue;
    Vec3 cx = X.row(i).transpose(), cc = C.row(i).transpose();
    int k = 1;
    for (auto w : mesh.vv_range(vh)) {
      cx += X.row(w.idx()).transpose();
      cc += C.row(w.idx()).transpose();
      ++k;
    }
    cx /= k;
    cc /= k;
    Eigen::Matrix3d XX = Eigen::Matrix3d::Zero(), CX = Eigen::Matrix3d::Zero();
    double len2 = 0;
    auto add = [&](int j) {
      const Vec3 dx = X.row(j).transpose() - cx, dc = C.row(j).transpose() - cc;
      XX += dx * dx.transpose();
      CX += dc * dx.transpose();
      len2 += dx.squaredNorm();
    };
    add(i);
    for (auto w : mesh.vv_range(vh)) add(w.idx());
    const double s2 = len2 / k;  // the normal weighs like a ring vertex; deformed normal scaled by the ring's stretch
    const Vec3 n0 = N0.row(i).transpose(), n1 = N1.row(i).transpose();
    const double stretch = std::sqrt(CX.squaredNorm() / std::max(XX.squaredNorm(), 1e-300));
    XX += s2 * n0 * n0.transpose();
    CX += s2 * std::max(stretch, 1e-12) * n1 * n0.transpose();
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(XX);
    if (lu.isInvertible()) J[i] = CX * lu.inverse();
  }
  return J;
}

// The nearest similarity's linear part s R to a 3×3 matrix (polar decomposition by SVD).
Eigen::Matrix3d nearest_similarity(const Eigen::Matrix3d& M, bool allow_scale) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d S(1, 1, (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1);
  const Eigen::Matrix3d R = svd.matrixU() * S.asDiagonal() * svd.matrixV().transpose();
  return allow_scale ? Eigen::Matrix3d(svd.singularValues().dot(S) / 3.0 * R) : R;
}

// Is a region much longer than wide (principal extents e1 > 2 e2), a ridge rather than a bump?
bool elongated(const MatrixX3d& X, const std::vector<int>& rows) {
  if (rows.size() < 3) return false;
  Vec3 mean = Vec3::Zero();
  for (int v : rows) mean += X.row(v).transpose();
  mean /= static_cast<double>(rows.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int v : rows) {
    const Vec3 d = X.row(v).transpose() - mean;
    cov += d * d.transpose();
  }
  const Vec3 ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvalues();  // ascending
  return ev[2] > 4 * ev[1];
}

// The linear part T_i (rotation, or similarity with allow_scale) that turns each feature vertex's
// edges; identity for the background.
//  - rigid (compact features, and every feature without bend): one fit per region over its foot ring
//    (or over the region itself if it has none);
//  - bend (elongated features, a ridge): each foot vertex gets the rotation of the space map's local linear part J there (polar
//    decomposition: the base's own rotation, well defined under any stretch), and the feature vertices
//    the harmonic (umbrella) interpolation of those 3×3 matrices, projected back to rotations. Linear in the position along a uniformly bent base, so a wide
//    feature follows the base's bending; near-constant along a protrusion's shaft, so a protrusion turns
//    with the mean rotation of its foot.
std::vector<Eigen::Matrix3d> feature_transforms(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C,
                                                const std::vector<Eigen::Matrix3d>& J, const Regions& reg,
                                                bool allow_scale, bool bend) {
  const int n = static_cast<int>(X.rows());
  std::vector<Eigen::Matrix3d> T(n, Eigen::Matrix3d::Identity());
  std::vector<int> unknown(n, -1);
  int m = 0;
  for (size_t k = 0; k < reg.members.size(); ++k) {
    const bool has_foot = reg.foot[k].size() >= 3;
    if (!bend || !has_foot || !elongated(X, reg.members[k])) {
      const Eigen::Matrix3d L = fit_rows(X, C, has_foot ? reg.foot[k] : reg.members[k], allow_scale).linear();
      for (int v : reg.members[k]) T[v] = L;
      continue;
    }
    for (int v : reg.members[k]) unknown[v] = m++;
  }
  if (m == 0) return T;
  // Dirichlet values on the foot rings of the regions solved for.
  std::vector<int> foot_vertices;
  for (size_t k = 0; k < reg.members.size(); ++k)
    if (!reg.members[k].empty() && unknown[reg.members[k][0]] >= 0)
      foot_vertices.insert(foot_vertices.end(), reg.foot[k].begin(), reg.foot[k].end());
  std::sort(foot_vertices.begin(), foot_vertices.end());
  foot_vertices.erase(std::unique(foot_vertices.begin(), foot_vertices.end()), foot_vertices.end());
  for (int v : foot_vertices) T[v] = nearest_similarity(J[v], allow_scale);
  std::vector<Triplet> t;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(m, 9);
  for (int i = 0; i < n; ++i) {
    const int r = unknown[i];
    if (r < 0) continue;
    double d = 0;
    for (auto w : mesh.vv_range(mesh.vertex_handle(i))) {
      const int j = w.idx();
      d += 1;
      if (unknown[j] >= 0) t.emplace_back(r, unknown[j], -1.0);
      else B.row(r) += Eigen::Map<const Eigen::Matrix<double, 1, 9>>(T[j].data());
    }
    t.emplace_back(r, r, d);
  }
  SparseMatrix A(m, m);
  A.setFromTriplets(t.begin(), t.end());
  SpdSolver solver;
  solver.compute(A);
  const Eigen::MatrixXd Mx = solver.solve(B);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i)
    if (unknown[i] >= 0) {
      Eigen::Matrix3d M;
      Eigen::Map<Eigen::Matrix<double, 1, 9>>(M.data()) = Mx.row(unknown[i]);
      T[i] = nearest_similarity(M, allow_scale);
    }
  return T;
}

// Screened Poisson over the background with values fixed on the features (f > 0):
//   Σ_edges |v_i − v_j|² + μ Σ_background |v_i − v⁰_i|²,  μ = (h / ℓ)², ℓ = transition · R,
// R = √(area / 4π). Near a feature the solution takes the feature's values, beyond ~ℓ its own v⁰.
// It spreads T from the features' rotations to the space map's J (so the stretch the features refuse
// is spread over a band of width ~ℓ instead of piling up at their rims), and the push U that moves
// the surroundings of a feature at the box's extremes along with it. One factor serves both.
class BackgroundSpread {
 public:
  BackgroundSpread(const Mesh& mesh, const Eigen::VectorXd& f, double transition) : mesh_(mesh) {
    const int n = static_cast<int>(mesh.n_vertices());
    index_.assign(n, -1);
    bool any_feature = false;
    for (int i = 0; i < n; ++i) {
      if (f[i] <= 0) index_[i] = m_++;
      else any_feature = true;
    }
    if (!any_feature || !(transition > 0) || m_ == 0) return;  // nothing to spread: v = v⁰
    const double ell = transition * std::sqrt(surface_area(mesh) / (4 * M_PI)) / mean_edge_length(mesh);
    mu_ = 1.0 / (ell * ell);
    std::vector<Triplet> t;
    for (int i = 0; i < n; ++i) {
      const int r = index_[i];
      if (r < 0) continue;
      double d = mu_;
      for (auto w : mesh.vv_range(mesh.vertex_handle(i))) {
        d += 1;
        if (index_[w.idx()] >= 0) t.emplace_back(r, index_[w.idx()], -1.0);
      }
      t.emplace_back(r, r, d);
    }
    SparseMatrix A(m_, m_);
    A.setFromTriplets(t.begin(), t.end());
    solver_.compute(A);
    active_ = true;
  }

  //! \p V: #V by k; the rows of feature vertices are fixed, those of background vertices are v⁰.
  //! \return V with the background rows replaced by the solution.
  Eigen::MatrixXd operator()(const Eigen::MatrixXd& V) const {
    if (!active_) return V;
    Eigen::MatrixXd B(m_, V.cols());
    for (int i = 0; i < static_cast<int>(index_.size()); ++i) {
      const int r = index_[i];
      if (r < 0) continue;
      B.row(r) = mu_ * V.row(i);
      for (auto w : mesh_.vv_range(mesh_.vertex_handle(i)))
        if (index_[w.idx()] < 0) B.row(r) += V.row(w.idx());
    }
    const Eigen::MatrixXd S = solver_.solve(B);
    Eigen::MatrixXd out = V;
    for (int i = 0; i < static_cast<int>(index_.size()); ++i)
      if (index_[i] >= 0) out.row(i) = S.row(index_[i]);
    return out;
  }

 private:
  const Mesh& mesh_;
  std::vector<int> index_;
  int m_ = 0;
  double mu_ = 0;
  bool active_ = false;
  SpdSolver solver_;
};

// Eq. (9.2–9.3): feature vertices keep their Laplacian coordinates turned by T_i, every vertex is
// pulled to c_i with weight w p_i.
MatrixX3d thesis_resize(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C, const Eigen::VectorXd& f,
                        const ResizeOptions& o) {
  const int n = static_cast<int>(X.rows());
  const double w = o.position_weight;
  const double eps = 1e-6 * w;  // keeps the system definite when every vertex is a feature
  const Eigen::VectorXd p = Eigen::VectorXd::Ones(n) - f;  // p_i = 1 − f_i
  const SparseMatrix L = editing_laplacian(mesh, o.laplacian);
  const MatrixX3d D = L * X;  // Eq. (9.1)
  // T_i by SVD between the original and the deformed 1-rings; δ^t_i = T_i δ_i (Eq. 9.3's D^t).
  const std::vector<Similarity> T = one_ring_similarities(mesh, X, C, !o.keep_feature_size);
  MatrixX3d Dt(n, 3);
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) Dt.row(i) = (T[i].linear() * D.row(i).transpose()).transpose();
  // Eq. (9.2) in normal-equation form: (Lᵀ F L + w P) X = Lᵀ F D^t + w P C. Eq. (9.3) as written,
  // W [L; I] X = W [D^t; C] solved in the least-squares sense, squares the weights: F², (w P)².
  report(o.progress, 0.3, "factor");
  const Eigen::VectorXd fw = o.square_weights ? Eigen::VectorXd(f.cwiseAbs2()) : f;
  const Eigen::VectorXd pw =
      (o.square_weights ? Eigen::VectorXd((w * p).cwiseAbs2()) : Eigen::VectorXd(w * p)).array() + eps;
  // As least squares with G = √F L: LᵀFL of a vertex of valence k holds a dense k × k block (a fan of
  // 10^5: 3.7 GB and minutes), which LeastSquaresSolver keeps out of its factor (issue 30).
  SparseMatrix G = L;
  for (int c = 0; c < G.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(G, c); it; ++it) it.valueRef() *= std::sqrt(fw[it.row()]);
  LeastSquaresSolver solver;
  solver.compute(G, pw);
  report(o.progress, 0.7, "solve");
  const MatrixX3d rhs = L.transpose() * (fw.asDiagonal() * Dt) + pw.asDiagonal() * C;
  return solver.solve(rhs);
}

// A feature at the box's extreme along one axis: it must put its outermost vertex where the map
// puts it, or the box is not scaled as asked.
struct Push {
  int region = -1;   // tapered region
  int axis = 0;
  int extreme = -1;  // outermost vertex
  double delta = 0;  // how far the region and its surroundings are pushed along the axis
};

// The sliding method's base: faces whose vertices are all background (feature weight < ½), and
// vertex normals of the deformed (\p C) base's own faces (the plain vertex normal where a vertex has none).
struct SlidingBase {
  MatrixX3i faces;
  MatrixX3d normals;
};

SlidingBase sliding_base(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& features) {
  const int n = static_cast<int>(C.rows());
  MatrixX3i Fb;
  MatrixX3d Nv;
  Mesh deformed = mesh;
  set_positions(deformed, C);
  Nv = vertex_normals(deformed);
  const MatrixX3i F = faces(mesh);
  const MatrixX3d Fn = face_normals(deformed);
  const Eigen::VectorXd area = face_areas(deformed);
  std::vector<int> base_faces;
  MatrixX3d acc = MatrixX3d::Zero(n, 3);
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    if (features[F(k, 0)] >= 0.5 || features[F(k, 1)] >= 0.5 || features[F(k, 2)] >= 0.5) continue;
    base_faces.push_back(static_cast<int>(k));
    for (int j = 0; j < 3; ++j) acc.row(F(k, j)) += area[k] * Fn.row(k);
  }
  Fb.resize(static_cast<Eigen::Index>(base_faces.size()), 3);
  for (size_t k = 0; k < base_faces.size(); ++k) Fb.row(k) = F.row(base_faces[k]);
  for (int i = 0; i < n; ++i)
    if (acc.row(i).norm() > 0) Nv.row(i) = acc.row(i).normalized();
  return {std::move(Fb), std::move(Nv)};
}

// T spread from the features (f > 0) to the map's J over the background.
void spread_transforms(std::vector<Eigen::Matrix3d>& T, const std::vector<Eigen::Matrix3d>& J, const Eigen::VectorXd& f,
                       const BackgroundSpread& spread) {
  const int n = static_cast<int>(f.size());
  Eigen::MatrixXd V(n, 9);
  for (int i = 0; i < n; ++i) V.row(i) = Eigen::Map<const Eigen::Matrix<double, 1, 9>>((f[i] > 0 ? T[i] : J[i]).data());
  V = spread(V);
  for (int i = 0; i < n; ++i) Eigen::Map<Eigen::Matrix<double, 1, 9>>(T[i].data()) = V.row(i);
}

// The features to push so that the box is scaled as asked (see Push), and in \p pin_w (#V by 3, zero
// on entry) the weight pulling extreme background vertices to the map along their axis.
std::vector<Push> extreme_pushes(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& features,
                                 const Regions& regions, const Frame& frame, double frame_weight, MatrixX3d& pin_w) {
  const int n = static_cast<int>(X.rows());
  std::vector<Push> pushes;
  const Regions cores = feature_regions(mesh, features);
  for (size_t k = 0; k < cores.members.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      if (!frame.axis[a]) continue;
      int lo = -1, hi = -1;
      for (int v : cores.members[k]) {
        if (X(v, a) <= frame.lo[a] + frame.band && (lo < 0 || X(v, a) < X(lo, a))) lo = v;
        if (X(v, a) >= frame.hi[a] - frame.band && (hi < 0 || X(v, a) > X(hi, a))) hi = v;
      }
      if ((lo >= 0) != (hi >= 0)) {
        const int e = lo >= 0 ? lo : hi;
        pushes.push_back({regions.id[e], a, e, 0.0});
      }
    }
  for (int a = 0; a < 3; ++a) {
    if (!frame.axis[a]) continue;
    int lo = -1, hi = -1;
    for (int i = 0; i < n; ++i) {
      if (mesh.is_isolated(mesh.vertex_handle(i))) continue;
      if (lo < 0 || X(i, a) < X(lo, a)) lo = i;
      if (hi < 0 || X(i, a) > X(hi, a)) hi = i;
    }
    for (int v : {lo, hi}) {
      if (v < 0) continue;
      const int r = regions.id[v];  // a feature's taper reaches the extreme: push the feature
      if (r >= 0) {
        const int other = v == lo ? hi : lo;
        if (regions.id[other] == r) continue;  // spans the model
        auto q = std::find_if(pushes.begin(), pushes.end(), [&](const Push& q) { return q.region == r && q.axis == a; });
        if (q == pushes.end()) pushes.push_back({r, a, v, 0.0});
        else q->extreme = v;  // the region's outermost vertex is the model's
      } else {
        pin_w(v, a) = frame_weight;
      }
    }
  }
  return pushes;
}

// The sliding energy's edge terms: their weights as an #V by #V Laplacian \p G, their right-hand
// side (per coordinate) in \p lap_rhs (#V by 3, zero on entry).
void sliding_edge_terms(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C, const std::vector<Eigen::Matrix3d>& T,
                        const std::vector<Eigen::Matrix3d>& J, const Regions& regions, const Eigen::VectorXd& f,
                        const Eigen::VectorXd& p, double beta, SparseMatrix& G, MatrixX3d& lap_rhs) {
  std::vector<Triplet> t;
  t.reserve(4 * mesh.n_edges());
  for (auto e : mesh.edges()) {
    const int a = e.v0().idx(), b = e.v1().idx();
    const double fe = regions.id[a] == regions.id[b] ? std::min(f[a], f[b]) : 0.0;
    const double be = beta * std::max(p[a], p[b]);
    const double we = fe + be;
    if (we <= 0) continue;
    // Feature edges: T Δx. Background edges: the deformed edge Δc corrected by (T − J) Δx, which
    // is T Δx plus the map's own curvature, and exactly Δc where T = J (far from features).
    const Vec3 dx = (X.row(a) - X.row(b)).transpose();
    const Vec3 tdx = 0.5 * (T[a] + T[b]) * dx;
    const Vec3 bg = (C.row(a) - C.row(b)).transpose() + tdx - 0.5 * (J[a] + J[b]) * dx;
    const Eigen::RowVector3d r = (fe * tdx + be * bg).transpose();
    t.emplace_back(a, a, we);
    t.emplace_back(b, b, we);
    t.emplace_back(a, b, -we);
    t.emplace_back(b, a, -we);
    lap_rhs.row(a) += r;
    lap_rhs.row(b) -= r;
  }
  G.setFromTriplets(t.begin(), t.end());
}

// The isotropic pull of each vertex to c'_i: ε, plus frame_weight on the frame where it is background.
Eigen::VectorXd sliding_frame_weights(const Frame& frame, const Eigen::VectorXd& f, const Eigen::VectorXd& p,
                                      const BackgroundSpread& spread, double eps, double frame_weight) {
  const int n = static_cast<int>(f.size());
  Eigen::VectorXd diag_w(n);
  // The frame yields near features as the background does (1 − s, s the features' indicator spread
  // over the transition band): a boundary next to a feature (a scan's hole beside a foot) would
  // otherwise hold the feature's surroundings to the plain map and stretch the feature.
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(n, 1);
  for (int i = 0; i < n; ++i) V(i, 0) = f[i] > 0 ? 1.0 : 0.0;
  const Eigen::VectorXd s = spread(V).col(0);
  for (int i = 0; i < n; ++i)
    diag_w[i] = eps + (frame.vertex[i] ? frame_weight * p[i] * std::clamp(1.0 - s[i], 0.0, 1.0) : 0.0);
  return diag_w;
}

// One refinement of the sliding method's constraint planes: q_i and n_i of every background vertex
// re-taken at the closest point of the deformed base (\p Cp, \p Fb, its normals \p Nv) to the solution
// \p out. \return the largest change of a plane (1 − cos of its turn, or its shift in mean edges \p h_mean).
double retake_planes(const MatrixX3d& Cp, const MatrixX3i& Fb, const MatrixX3d& Nv, const Eigen::VectorXd& p,
                     const MatrixX3d& out, double h_mean, MatrixX3d& Q, MatrixX3d& Nrm) {
  const int n = static_cast<int>(p.size());
  const TriangleTree tree(Cp, Fb);
  std::vector<int> rows;
  for (int i = 0; i < n; ++i)
    if (p[i] > 0) rows.push_back(i);
  const std::vector<TriangleTree::Hit> hits = tree.closest(out, rows);
  double change = 0;
#pragma omp parallel for schedule(static) reduction(max : change)
  for (int k = 0; k < static_cast<int>(rows.size()); ++k) {
    const int i = rows[k];
    const TriangleTree::Hit& hit = hits[k];
    const Eigen::Vector3i F = Fb.row(hit.face);
    Vec3 nv = hit.bary[0] * Vec3(Nv.row(F[0])) + hit.bary[1] * Vec3(Nv.row(F[1])) + hit.bary[2] * Vec3(Nv.row(F[2]));
    if (nv.norm() < 1e-12) continue;
    nv.normalize();
    const Vec3 n_old = Nrm.row(i).transpose();
    change = std::max({change, 1.0 - nv.dot(n_old),
                       std::abs(nv.dot(hit.point) - n_old.dot(Vec3(Q.row(i).transpose()))) / h_mean});
    Q.row(i) = hit.point.transpose();
    Nrm.row(i) = nv.transpose();
  }
  return change;
}

// The sliding system's matrix: the fixed terms \p base plus w p_i n_i n_iᵀ per vertex (\p Nrm: n_i).
SparseMatrix sliding_matrix(const std::vector<Triplet>& base, const Eigen::VectorXd& p, double w, const MatrixX3d& Nrm) {
  const int n = static_cast<int>(p.size());
  std::vector<Triplet> t = base;
  t.reserve(base.size() + 9 * n);
  for (int i = 0; i < n; ++i) {
    const double wi = w * p[i];
    for (int d = 0; d < 3; ++d)
      for (int e = 0; e < 3; ++e) t.emplace_back(d * n + i, e * n + i, wi * Nrm(i, d) * Nrm(i, e));
  }
  SparseMatrix A(3 * n, 3 * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// Sliding. Unknowns stacked [x; y; z]. Energy:
//   Σ_edges f_ij |(x'_i − x'_j) − T_ij (x_i − x_j)|²   features keep their shape, turned by T (see
//                                                       feature_transforms), T_ij = (T_i + T_j) / 2
// + β Σ_edges p_ij |(x'_i − x'_j) − (c_i − c_j) − (T_ij − J_ij)(x_i − x_j)|²
//                                                       the background follows the map, its stretch
//                                                       passing from the features' T to the map's own J
//                                                       (BackgroundSpread)
// + w Σ p_i (n_iᵀ (x'_i − q_i))²                  background held to the deformed surface along its normal
// + w_F Σ_{frame} p_i |x'_i − c'_i|²              the outer frame follows the space map
// + w_F Σ_{extremes} (x'_i − c'_i)_a²             closed meshes: extreme background vertices along a
// + ε Σ |x'_i − c'_i|²
// with c' = c + U (U: pushes, below), q_i = c'_i and n_i the deformed base's vertex normal; then q_i,
// n_i re-taken at the closest point of the deformed base and the system re-solved (refinements) while
// a plane changes. f_ij = min(f_i, f_j) within one region (0 between two), p_ij = max(p_i, p_j).
MatrixX3d sliding_resize(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C, const Eigen::VectorXd& features,
                         const ResizeOptions& o) {
  const int n = static_cast<int>(X.rows());
  const double w = o.position_weight, beta = o.background_smoothness;
  const double eps = 1e-6 * w;  // keeps the system definite when every vertex is a feature
  // A feature's weight falls off over a few rings outside it, so that its rim passes from rigid to
  // held-to-the-base gradually instead of in one crease.
  Eigen::VectorXd f;
  const Regions regions = tapered_regions(mesh, features, o.taper, f);
  const Eigen::VectorXd p = Eigen::VectorXd::Ones(n) - f;
  const Frame frame = frame_of(mesh, X, o.frame_band);
  const double h_mean = mean_edge_length(mesh);

  // The base: faces whose vertices are all background (f < ½ before the taper). The background slides along the
  // deformed base, not along a feature's deformed (e.g. stretched) surface, and its normals are the
  // base's own: a vertex normal averaged with a feature's faces would tilt toward the feature and
  // drag the feature's foot along it. Vertices without a base face keep their vertex normal.
  const SlidingBase sb = sliding_base(mesh, C, features);
  const MatrixX3i& Fb = sb.faces;
  const MatrixX3d& Nv = sb.normals;

  // T: features by feature_transforms, the background spread from them to the map's J.
  report(o.progress, 0.05, "transforms");
  const std::vector<Eigen::Matrix3d> J = local_jacobians(mesh, X, C);
  std::vector<Eigen::Matrix3d> T = feature_transforms(mesh, X, C, J, regions, !o.keep_feature_size, o.bend_features);
  const BackgroundSpread spread(mesh, f, o.transition);
  spread_transforms(T, J, f, spread);

  // Features at the box's extremes: a feature region (as given, before the taper) reaching one box
  // face along axis a (within the band), or whose taper holds the extreme vertex along a. A region
  // reaching both faces spans the model and is left free (a rigid copy is what its weights ask for).
  // Extreme background vertices are pulled to c along a.
  MatrixX3d pin_w = MatrixX3d::Zero(n, 3);
  std::vector<Push> pushes = extreme_pushes(mesh, X, features, regions, frame, o.frame_weight, pin_w);

  // Edge terms, one 1-ring stencil.
  SparseMatrix G(n, n);
  MatrixX3d lap_rhs = MatrixX3d::Zero(n, 3);
  sliding_edge_terms(mesh, X, C, T, J, regions, f, p, beta, G, lap_rhs);
  const Eigen::VectorXd diag_w = sliding_frame_weights(frame, f, p, spread, eps, o.frame_weight);  // pull to c'_i
  std::vector<Triplet> base;
  add_blocks(base, G, n);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) base.emplace_back(d * n + i, d * n + i, diag_w[i] + pin_w(i, d));

  MatrixX3d Cp = C;  // c' = c + U
  MatrixX3d Nrm = Nv, Q = C;  // normals and points of the background's constraint planes
  SpdSolver solver;
  auto assemble = [&] { return sliding_matrix(base, p, w, Nrm); };  // the normal terms change with Nrm
  auto solve = [&] {
    Eigen::VectorXd b = stack(lap_rhs + diag_w.asDiagonal() * Cp + MatrixX3d(pin_w.cwiseProduct(Cp)));
    for (int i = 0; i < n; ++i) {
      const double wi = w * p[i] * Nrm.row(i).dot(Q.row(i));
      for (int d = 0; d < 3; ++d) b[d * n + i] += wi * Nrm(i, d);
    }
    return unstack(solver.solve(b).col(0));
  };

  // Pushes: a feature at an extreme is moved, with its surroundings fading over the transition band,
  // until its outermost vertex lands where the map puts it: δ += c_e − x'_e along the axis, U spread
  // from the pushed regions, c' = c + U (and q moved along), solve again with the same factor. The
  // response to δ is a little below 1 (the region is partly held by what is not pushed), so a few
  // rounds close the gap.
  MatrixX3d U = MatrixX3d::Zero(n, 3), out;
  const Vec3 c_lo = C.colwise().minCoeff(), c_hi = C.colwise().maxCoeff();
  auto push = [&] {
    for (int round = 0; round < 6 && !pushes.empty(); ++round) {
      double worst = 0;
      for (Push& q : pushes) {
        const double gap = C(q.extreme, q.axis) - out(q.extreme, q.axis);
        q.delta += gap;
        worst = std::max(worst, std::abs(gap));
      }
      if (worst < 1e-3 * h_mean) break;
      Eigen::MatrixXd V = Eigen::MatrixXd::Zero(n, 3);
      for (const Push& q : pushes)
        for (int v : regions.members[q.region]) V(v, q.axis) = q.delta;
      MatrixX3d U_new = spread(V);
      // The push fades over the band around a feature, whose surroundings may hold the model's true
      // extreme: keep the pushed surface within the map's box.
      for (const Push& q : pushes) {
        const int a = q.axis;
        for (int i = 0; i < n; ++i) U_new(i, a) = std::clamp(C(i, a) + U_new(i, a), c_lo[a], c_hi[a]) - C(i, a);
      }
      Q += U_new - U;
      U = U_new;
      Cp = C + U;
      out = solve();
    }
  };
  report(o.progress, 0.2, "factor");
  {
    const SparseMatrix A = assemble();
    solver.analyze(A, 3);  // x, y, z of a vertex together (see SpdSolver::analyze)
    solver.factorize(A);
  }
  report(o.progress, 0.5, "solve");
  out = solve();
  push();
  // Refinements: re-take q_i and n_i at the closest point of the deformed (pushed) base (curved
  // bases); stop when no constraint plane changes (flat bases: the solution would be the same).
  for (int round = 0; round < o.refinements && Fb.rows() > 0; ++round) {
    const double change = retake_planes(Cp, Fb, Nv, p, out, h_mean, Q, Nrm);
    if (change < 1e-9) break;
    report(o.progress, 0.6 + 0.3 * round / std::max(1, o.refinements), "refine");
    solver.factorize(assemble());
    out = solve();
    push();
  }
  return out;
}

// The similarity method's first T_i = s_i R_i from the map's local linear parts \p J: R_i the nearest
// rotation, s_i between the map's smallest and largest stretch in the tangent plane of normal \p N0
// (\p s_lo, \p s_hi): the smallest when \p keep_feature_size, their geometric mean otherwise.
void similarity_transforms(const std::vector<Eigen::Matrix3d>& J, const MatrixX3d& N0, bool keep_feature_size,
                           std::vector<Eigen::Matrix3d>& T, Eigen::VectorXd& scale, Eigen::VectorXd& s_lo,
                           Eigen::VectorXd& s_hi) {
  const int n = static_cast<int>(N0.rows());
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n; ++i) {
    const Vec3 nrm = N0.row(i).transpose();
    Vec3 t1 = nrm.unitOrthogonal(), t2 = nrm.cross(t1);
    Eigen::Matrix<double, 3, 2> B;
    B << J[i] * t1, J[i] * t2;
    const Eigen::Vector2d sv = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(B).singularValues();
    const bool ok = nrm.squaredNorm() > 0.5;
    s_lo[i] = ok ? sv[1] : std::cbrt(std::abs(J[i].determinant()));
    s_hi[i] = ok ? sv[0] : s_lo[i];
    scale[i] = keep_feature_size ? s_lo[i] : std::sqrt(s_lo[i] * s_hi[i]);
    T[i] = scale[i] * nearest_similarity(J[i], false);
  }
}

// The vertices within \p frame_band mean edge lengths of a box face, along that axis, that are local
// extremes of the band, as (vertex, axis).
std::vector<std::array<int, 2>> box_extremes(const Mesh& mesh, const MatrixX3d& X, double frame_band) {
  const int n = static_cast<int>(X.rows());
  std::vector<std::array<int, 2>> extremes;
  const Vec3 lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  const double band = std::max(frame_band, 1e-3) * mean_edge_length(mesh);
  // Only the band's local extremes (no neighbour further out): a hoof's tip, every vertex of a flat
  // bottom, not the rows of a wall rising from it.
  for (int a = 0; a < 3; ++a) {
    if (!(hi[a] - lo[a] > 2 * band)) continue;  // a flat model's thickness: its vertices follow the map
    for (int i = 0; i < n; ++i) {
      const auto vh = mesh.vertex_handle(i);
      if (mesh.is_isolated(vh)) continue;
      const bool low = X(i, a) <= lo[a] + band, high = X(i, a) >= hi[a] - band;
      if (!low && !high) continue;
      bool extreme = true;
      for (auto u : mesh.vv_range(vh))
        if ((low && X(u.idx(), a) < X(i, a)) || (high && X(u.idx(), a) > X(i, a))) extreme = false;
      if (extreme) extremes.push_back({i, a});
    }
  }
  return extremes;
}

// The similarity method's local step: T_i = s_i R_i of every important vertex (f_i > 0) refitted to
// the solution \p Y, R_i the rotation that best turns its 1-ring edges into the solution's and, when
// \p adapt_scale, s_i the scale that fits best within [s_lo, s_hi].
void refit_similarities(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y, const Eigen::VectorXd& f,
                        bool adapt_scale, const Eigen::VectorXd& s_lo, const Eigen::VectorXd& s_hi,
                        Eigen::VectorXd& scale, std::vector<Eigen::Matrix3d>& T) {
  const int n = static_cast<int>(X.rows());
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < n; ++i) {
    if (f[i] <= 0) continue;
    const auto vh = mesh.vertex_handle(i);
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    double len2 = 0;
    for (auto u : mesh.vv_range(vh)) {
      const int j = u.idx();
      S += (Y.row(j) - Y.row(i)).transpose() * (X.row(j) - X.row(i));
      len2 += (X.row(j) - X.row(i)).squaredNorm();
    }
    if (!(S.squaredNorm() > 0) || !(len2 > 0)) continue;
    const Eigen::Matrix3d R = nearest_similarity(S, false);
    // As similar as possible: the scale that fits best, within the map's own local stretches.
    if (adapt_scale) scale[i] = std::clamp((R.transpose() * S).trace() / len2, s_lo[i], s_hi[i]);
    T[i] = scale[i] * R;
  }
}

// The connected wholly important regions (f_i ≥ 1: a painted core) of \p f, as vertex lists (single vertices left out).
std::vector<std::vector<int>> wholly_important_regions(const Mesh& mesh, const Eigen::VectorXd& f) {
  const Eigen::VectorXd core = (f.array() >= 1.0).cast<double>().matrix();
  std::vector<std::vector<int>> out;
  for (std::vector<int>& members : feature_regions(mesh, core).members)
    if (members.size() > 1) out.push_back(std::move(members));
  return out;
}

// The largest scale s at which the region \p members of \p X turned by \p R spans at most \p extent along each axis.
double box_scale_limit(const MatrixX3d& X, const std::vector<int>& members, const Eigen::Matrix3d& R, const Vec3& extent) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int i : members) {
    const Vec3 p = R * X.row(i).transpose();
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  double s = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a)
    if (hi[a] - lo[a] > 0) s = std::min(s, extent[a] / (hi[a] - lo[a]));
  return s;
}

// A wholly important region of \p cores that the box cannot hold at its similarity s R x + t fitted to the solution
// \p Y (Umeyama over the region, Eq. 5.24; s within the region's smallest s_lo and largest s_hi when \p adapt_scale,
// else the mean of its vertices' scales): turned by R and scaled by s it spans more than the asked \p extent along
// an axis, so the final box fit would squeeze it along that axis (the painted plate's bumps, which make its height:
// grown ×1.15 by the rounds, squeezed back in z, 6.8 % from a similarity on a 32 × 32 plate; bench/resize.md,
// thirteenth session). Such a region is anchored at the largest similarity the box holds (centroid where \p Y has
// it): \p weight in \p anchor on its vertices, their places in \p place; the rest, solved again, takes up the
// difference. Regions the box holds are left to the rounds. \return whether any region was anchored.
bool anchor_cores_in_box(const MatrixX3d& X, const MatrixX3d& Y, const std::vector<std::vector<int>>& cores,
                         bool adapt_scale, const Eigen::VectorXd& s_lo, const Eigen::VectorXd& s_hi,
                         const Eigen::VectorXd& scale, const Vec3& extent, double weight, Eigen::VectorXd& anchor,
                         MatrixX3d& place) {
  bool any = false;
  for (const std::vector<int>& members : cores) {
    Similarity fit = fit_rows(X, Y, members, true);
    double lo = std::numeric_limits<double>::infinity(), hi = 0, mean = 0;
    for (int i : members) lo = std::min(lo, s_lo[i]), hi = std::max(hi, s_hi[i]), mean += scale[i];
    const double s = adapt_scale ? std::clamp(fit.s, lo, hi) : mean / static_cast<double>(members.size());
    const double s_box = box_scale_limit(X, members, fit.R, extent);
    if (!(s_box < s)) continue;
    Vec3 cx = Vec3::Zero(), cy = Vec3::Zero();
    for (int i : members) cx += X.row(i).transpose(), cy += Y.row(i).transpose();
    cx /= static_cast<double>(members.size()), cy /= static_cast<double>(members.size());
    fit.s = s_box;
    fit.t = cy - s_box * (fit.R * cx);
    for (int i : members) anchor[i] = weight, place.row(i) = fit(X.row(i).transpose()).transpose();
    any = true;
  }
  return any;
}

// The similarity method's constraint planes: q_i and n_i of every vertex not wholly important
// (f_i < 1) taken at the closest point to the solution \p Y of the plainly stretched surface (\p tree
// over its faces \p F, its vertex normals \p Nc).
void project_planes(const Mesh& mesh, const TriangleTree& tree, const MatrixX3i& F, const MatrixX3d& Nc,
                    const Eigen::VectorXd& f, const MatrixX3d& Y, MatrixX3d& Q, MatrixX3d& Nrm) {
  const int n = static_cast<int>(Nc.rows());
  std::vector<int> rows;
  for (int i = 0; i < n; ++i)
    if (f[i] < 1 && !mesh.is_isolated(mesh.vertex_handle(i))) rows.push_back(i);
  const std::vector<TriangleTree::Hit> hits = tree.closest(Y, rows);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < static_cast<int>(rows.size()); ++k) {
    const int i = rows[k];
    const TriangleTree::Hit& hit = hits[k];
    const Eigen::Vector3i tri = F.row(hit.face);
    Vec3 nv = hit.bary[0] * Vec3(Nc.row(tri[0])) + hit.bary[1] * Vec3(Nc.row(tri[1])) + hit.bary[2] * Vec3(Nc.row(tri[2]));
    if (nv.norm() < 1e-12) continue;
    Q.row(i) = hit.point.transpose();
    Nrm.row(i) = nv.normalized().transpose();
  }
}

// The faces of \p F that \p Y turns over against the normals \p Fn, or against \p Fn2 when given (the
// plain stretch's, when the similarity method starts from the axis warp: the reference).
std::vector<int> turned_faces(const MatrixX3i& F, const MatrixX3d& Fn, const MatrixX3d& Y, const MatrixX3d* Fn2 = nullptr) {
  std::vector<int> out;
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    const Vec3 a = Y.row(F(k, 0)).transpose(), b = Y.row(F(k, 1)).transpose(), c = Y.row(F(k, 2)).transpose();
    const Vec3 nk = (b - a).cross(c - a);
    if (nk.dot(Vec3(Fn.row(k).transpose())) < 0 || (Fn2 && nk.dot(Vec3(Fn2->row(k).transpose())) < 0))
      out.push_back(static_cast<int>(k));
  }
  return out;
}

// What the similarity method takes besides the map C: the weight β of the edges following C
// (ResizeOptions::background_smoothness; AxisWarpOptions::follow_weight when C is the axis warp), its falloff
// with importance (AxisWarpOptions::follow_falloff after the warp; 0, every edge β, for the plain map) and,
// when C is not the plain stretch, the plain stretch's face normals (a face is then turned against either).
struct SimilarityBase {
  double beta;
  double follow_falloff = 0;
  const MatrixX3d* plain_normals = nullptr;
  bool hold_cores_in_box = false;  // a box scale: anchor_cores_in_box() after the rounds (the split solver)
  const std::vector<SurfaceTie>* ties = nullptr;  // vertices kept at points of the surface (solve_ties())
  int pin_rings = 0;  // the box's lone pins pull this many vertex rings softly along (soft_pins(), the split solver)
};

// Stiff springs holding each tie's vertex at its point, x_v − Σ_k w_k x_{c_k} = its offset in the input X (0 for the
// copies of a point contact, the teapot's handle on its body; a rim's offset from the face it rests on, the chord
// error of that face: kept as it is, not stretched), as an #V by #V matrix Σ kTie a aᵀ with a = e_v − Σ_k w_k e_{c_k}
// (a Laplacian: Σ_k w_k = 1). Added to the edge weights (≤ 1 + β, 10 relaxed), with the right-hand side (that
// matrix) · X, so the parts touching are not solved apart. (The offset as the map puts it, · C: the teapot's handle
// end ×2 y 0.137 mean edge lengths off its body against 0.081, the same detail ratios; bench/resize.md.)
SparseMatrix tie_springs(const std::vector<SurfaceTie>* ties, int n) {
  constexpr double kTie = 1e6;  // a tie ends within ~1e-6 of its forces' scale off its point
  SparseMatrix G(n, n);
  if (!ties) return G;
  std::vector<Triplet> g;
  for (const SurfaceTie& t : *ties) {
    std::array<std::pair<int, double>, 4> a{{{t.vertex, 1.0}}};
    int k = 1;
    for (int c = 0; c < 3; ++c)
      if (t.weights[c] != 0) a[k++] = {t.corners[c], -t.weights[c]};
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k; ++j) g.emplace_back(a[i].first, a[j].first, kTie * a[i].second * a[j].second);
  }
  G.setFromTriplets(g.begin(), g.end());
  return G;
}

// Marks in \p marked the vertices of the faces \p bad and \p rings vertex rings around them.
void mark_around(const Mesh& mesh, const MatrixX3i& F, const std::vector<int>& bad, int rings, std::vector<char>& marked) {
  std::vector<int> front;
  for (int k : bad)
    for (int j = 0; j < 3; ++j)
      if (!marked[F(k, j)]) marked[F(k, j)] = 1, front.push_back(F(k, j));
  for (int r = 0; r < rings; ++r) {
    std::vector<int> next;
    for (int v : front)
      for (auto u : mesh.vv_range(mesh.vertex_handle(v)))
        if (!marked[u.idx()]) marked[u.idx()] = 1, next.push_back(u.idx());
    front.swap(next);
  }
}

// The box's pins spread softly: the vertices of the \p rings rings around a side's lone extreme (a side held by
// one vertex), each pulled along the extreme's axis by the extreme's push (its pin target's move), with a weight
// w_F g exp(−(r/σ)²) at ring r, σ = rings / 2, g = the rings' importance ((mean f − 0.75) / 0.2, clamped: the
// cheburashka's back of the head, f 0.69, is left alone) × their roundness (1 − largest dihedral angle / 30°, clamped): an important round end moves as a soft piece instead of being drawn into a
// cone by its tip (the teapot ×2 z's prow), a flat or unimportant side stays held by its extreme alone.
struct SoftPins {
  std::vector<int> vertex, leader, axis;
  MatrixX3d weight;  // per mesh vertex, along each axis (0 off the spread)
};
SoftPins soft_pins(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f,
                   const std::vector<std::array<int, 2>>& pins, int rings, double pin_weight) {
  const std::size_t n = mesh.n_vertices();
  SoftPins soft{{}, {}, {}, MatrixX3d::Zero(static_cast<Eigen::Index>(n), 3)};
  if (rings <= 0) return soft;
  const MatrixX3d Fn = face_normals(mesh);
  const Vec3 mid = 0.5 * (X.colwise().minCoeff() + X.colwise().maxCoeff()).transpose();
  auto side = [&](int v, int a) { return 2 * a + (X(v, a) > mid[a] ? 1 : 0); };
  std::array<int, 6> on_side{};
  for (const auto& [v, a] : pins) ++on_side[side(v, a)];
  std::vector<int> ring(n, -1);
  const double sigma = 0.5 * rings, kRound = 30.0 * M_PI / 180, kLow = 0.75;
  for (const auto& [v0, a] : pins) {
    if (on_side[side(v0, a)] != 1) continue;  // a side held at several vertices (a flat bottom, four hooves)
    std::vector<int> near{v0};  // breadth first, ring[] the ring index
    ring[v0] = 0;
    for (std::size_t k = 0; k < near.size(); ++k)
      if (ring[near[k]] < rings)
        for (auto u : mesh.vv_range(mesh.vertex_handle(near[k])))
          if (ring[u.idx()] < 0) ring[u.idx()] = ring[near[k]] + 1, near.push_back(u.idx());
    double fsum = 0, flat = 1;  // the importance; the least cosine between two faces on an edge of the rings
    for (int u : near) {
      fsum += f[u];
      for (auto h : mesh.voh_range(mesh.vertex_handle(u)))
        if (h.face().is_valid() && h.opp().face().is_valid())
          flat = std::min(flat, Fn.row(h.face().idx()).dot(Fn.row(h.opp().face().idx())));
    }
    const double bend = std::acos(std::clamp(flat, -1.0, 1.0));
    const double important = std::clamp((fsum / static_cast<double>(near.size()) - kLow) / (1 - kLow - 0.05), 0.0, 1.0);
    const double g = important * std::clamp(1 - bend / kRound, 0.0, 1.0);
    for (int u : near) {
      const double r = ring[u];
      ring[u] = -1;
      if (u == v0 || g <= 0 || soft.weight(u, a) > 0) continue;
      soft.vertex.push_back(u), soft.leader.push_back(v0), soft.axis.push_back(a);
      soft.weight(u, a) = pin_weight * g * std::exp(-(r / sigma) * (r / sigma));
    }
  }
  return soft;
}

// The weight of an edge following the map C: β (1 − f_ij)^p, p = \p falloff (SimilarityBase::follow_falloff;
// 0: β on every edge), or \p relaxed_weight at a relaxed vertex.
double follow_weight(double fe, bool relaxed, double beta, double falloff, double relaxed_weight) {
  if (relaxed) return relaxed_weight;
  return falloff > 0 ? beta * std::pow(1 - fe, falloff) : beta;
}

// The similarity method's edge weights as an #V by #V Laplacian: f_ij² + the follow weight (follow_weight()),
// f_ij = (f_i + f_j) / 2.
SparseMatrix similarity_edge_weights(const std::vector<std::array<int, 2>>& edges, const Eigen::VectorXd& f,
                                     const std::vector<char>& relaxed, double beta, double falloff,
                                     double relaxed_weight) {
  const int n = static_cast<int>(f.size());
  SparseMatrix G(n, n);
  std::vector<Triplet> g;
  g.reserve(4 * edges.size());
  for (const auto& [a, b] : edges) {
    const double fe = 0.5 * (f[a] + f[b]);
    const double we = fe * fe + follow_weight(fe, relaxed[a] || relaxed[b], beta, falloff, relaxed_weight);
    g.emplace_back(a, a, we);
    g.emplace_back(b, b, we);
    g.emplace_back(a, b, -we);
    g.emplace_back(b, a, -we);
  }
  G.setFromTriplets(g.begin(), g.end());
  return G;
}

// The similarity energy's right-hand side without the surface term: the edges' Σ k_ij T_ij (x_i − x_j) +
// β_ij (c_i − c_j), the boundary's and ε's pull to c_i, and the box's pins to \p target.
MatrixX3d similarity_rhs(const std::vector<std::array<int, 2>>& edges, const MatrixX3d& X, const MatrixX3d& C,
                         const std::vector<Eigen::Matrix3d>& T, const Eigen::VectorXd& f,
                         const std::vector<char>& relaxed, const Eigen::VectorXd& pull,
                         const std::vector<std::array<int, 2>>& pins, const MatrixX3d& target, double beta,
                         double falloff, double relaxed_weight, double pin_weight) {
  const Eigen::Index n = X.rows();
  MatrixX3d R = MatrixX3d::Zero(n, 3);
  for (const auto& [a, b] : edges) {
    const double fe = 0.5 * (f[a] + f[b]), ke = fe * fe;
    const double be = follow_weight(fe, relaxed[a] || relaxed[b], beta, falloff, relaxed_weight);
    const Vec3 dx = (X.row(a) - X.row(b)).transpose();
    const Eigen::RowVector3d r =
        (ke * (0.5 * (T[a] + T[b]) * dx) + be * Vec3((C.row(a) - C.row(b)).transpose())).transpose();
    R.row(a) += r;
    R.row(b) -= r;
  }
  R += pull.asDiagonal() * C;
  for (const auto& [v, a] : pins) R(v, a) += pin_weight * target(v, a);
  return R;
}

// The isotropic pull of each vertex to c_i: ε, plus the frame weight on the mesh boundary where it is
// background ((1 − f_i)²).
Eigen::VectorXd similarity_pull(const std::vector<char>& boundary, const Eigen::VectorXd& f, double eps,
                                double frame_weight) {
  Eigen::VectorXd pull(f.size());
  for (Eigen::Index i = 0; i < f.size(); ++i)
    pull[i] = eps + (boundary[i] ? frame_weight * (1 - f[i]) * (1 - f[i]) : 0.0);
  return pull;
}

// Similarity (see resize.h). Unknowns stacked [x; y; z]. Energy:
//   Σ_edges k_ij |(x'_i − x'_j) − T_ij (x_i − x_j)|²   k_ij = f_ij², T_i = s_i R_i, T_ij = (T_i + T_j)/2
// + β Σ_edges b_ij |(x'_i − x'_j) − (c_i − c_j)|²       the rest follows the map, weakly (b_ij = (1 − f_ij)^p
//                                                        after the axis warp, p = follow_falloff; 1 otherwise)
// + w Σ_i (1 − f_i) (n_iᵀ (x'_i − q_i))²                 held to the stretched surface, free to slide
// + w_F Σ_boundary (1 − f_i)² |x'_i − c_i|²              a plate's rim follows the map
// + w_F Σ_extremes (x'_i − c_i)_a²                       the box
// + ε Σ |x'_i − c_i|²
// with q_i, n_i at first c_i and its vertex normal, then the closest point of the stretched surface.
// f_ij = (f_i + f_j)/2. Relaxed vertices (around faces that turned over) get f = 0 and β = 10.
MatrixX3d similarity_resize(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C, const Eigen::VectorXd& f0,
                            const ResizeOptions& o, const SimilarityBase& base) {
  const int n = static_cast<int>(X.rows());
  const double w = o.surface_weight, beta = base.beta, eps = 1e-6;
  const MatrixX3i F = faces(mesh);
  std::vector<std::array<int, 2>> edges;
  edges.reserve(mesh.n_edges());
  for (auto e : mesh.edges()) edges.push_back({e.v0().idx(), e.v1().idx()});
  Mesh mapped = mesh;
  set_positions(mapped, C);
  const MatrixX3d Nc = vertex_normals(mapped), N0 = vertex_normals(mesh);
  const MatrixX3d Fn_plain = face_normals(mapped);

  // T_i = s_i R_i from the map's local linear part J_i.
  report(o.progress, 0.05, "transforms");
  const std::vector<Eigen::Matrix3d> J = local_jacobians(mesh, X, C);
  std::vector<Eigen::Matrix3d> T(n);
  Eigen::VectorXd scale(n), s_lo(n), s_hi(n);
  similarity_transforms(J, N0, o.keep_feature_size, T, scale, s_lo, s_hi);

  // The frame: the vertices within frame_band mean edge lengths of a box face, along that axis (the
  // feet of a model standing on the box's floor stay level), and the mesh boundary.
  const std::vector<std::array<int, 2>> extremes = box_extremes(mesh, X, o.frame_band);  // (vertex, axis)
  MatrixX3d target = C;  // where the frame's vertices are pulled, moved until they land on C
  std::vector<char> boundary(n, 0);
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v)) boundary[v.idx()] = 1;

  Eigen::VectorXd f = f0;
  std::vector<char> relaxed(n, 0);
  constexpr double kRelaxed = 10.0;  // edge weight of relaxed vertices towards the map: above any similarity's
  const SparseMatrix ties = tie_springs(base.ties, n);
  const MatrixX3d tie_rest = ties * X;
  MatrixX3d Nrm = Nc, Q = C;
  SpdSolver solver;
  auto assemble = [&] {
    std::vector<Triplet> t;
    t.reserve(12 * edges.size() + 12 * n);
    add_blocks(t, similarity_edge_weights(edges, f, relaxed, beta, base.follow_falloff, kRelaxed) + ties, n);
    const Eigen::VectorXd pull = similarity_pull(boundary, f, eps, o.frame_weight);
    for (int i = 0; i < n; ++i) {
      const double wi = w * (1 - f[i]);
      for (int d = 0; d < 3; ++d) {
        t.emplace_back(d * n + i, d * n + i, pull[i]);
        for (int e = 0; e < 3; ++e) t.emplace_back(d * n + i, e * n + i, wi * Nrm(i, d) * Nrm(i, e));
      }
    }
    for (const auto& [v, a] : extremes) t.emplace_back(a * n + v, a * n + v, o.frame_weight);
    SparseMatrix A(3 * n, 3 * n);
    A.setFromTriplets(t.begin(), t.end());
    return A;
  };
  auto solve = [&] {
    MatrixX3d R = similarity_rhs(edges, X, C, T, f, relaxed, similarity_pull(boundary, f, eps, o.frame_weight),
                                 extremes, target, beta, base.follow_falloff, kRelaxed, o.frame_weight);
    for (int i = 0; i < n; ++i) R.row(i) += w * (1 - f[i]) * Nrm.row(i).dot(Q.row(i)) * Nrm.row(i);
    R += tie_rest;
    return unstack(solver.solve(stack(R)).col(0));
  };
  // The frame's vertices land where the map puts them: their targets are moved by what they miss
  // (a stiff region pulled by its tip moves as a whole instead of stretching), with the same factor.
  auto solve_frame = [&] {  // the targets carry over from the last call (a warm start)
    MatrixX3d Y = solve();
    for (int round = 0; round < 2; ++round) {
      for (const auto& [v, a] : extremes) target(v, a) += C(v, a) - Y(v, a);
      Y = solve();
    }
    return Y;
  };
  // Local step: the rotation that best turns each vertex's 1-ring edges into the solution's.
  auto refit = [&](const MatrixX3d& Y) { refit_similarities(mesh, X, Y, f, o.adapt_scale, s_lo, s_hi, scale, T); };
  const TriangleTree tree(C, F);
  auto project = [&](const MatrixX3d& Y) { project_planes(mesh, tree, F, Nc, f, Y, Q, Nrm); };
  auto flipped = [&](const MatrixX3d& Y) { return turned_faces(F, Fn_plain, Y, base.plain_normals); };

  report(o.progress, 0.2, "factor");
  SparseMatrix A = assemble();
  solver.analyze(A, 3);
  solver.factorize(A);
  report(o.progress, 0.3, "solve");
  MatrixX3d out = solve_frame();
  for (int it = 0; it < o.iterations; ++it) {
    report(o.progress, 0.3 + 0.4 * it / std::max(1, o.iterations), "local-global");
    refit(out);
    if (it == 0 || it == o.iterations / 2) {  // the constraint planes: the stretched surface where the solution is
      project(out);
      solver.factorize(assemble());
    }
    out = it + 1 == o.iterations ? solve_frame() : solve();
  }
  // Faces turned over against the plain map: relax them and rings around them to the map.
  for (int round = 0; round < o.flip_rounds; ++round) {
    const std::vector<int> bad = flipped(out);
    if (bad.empty()) break;
    report(o.progress, 0.7 + 0.25 * round / std::max(1, o.flip_rounds), fmt::format("relax {} turned faces", bad.size()));
    mark_around(mesh, F, bad, o.flip_rings + 2 * round, relaxed);  // wider each round
    for (int i = 0; i < n; ++i)
      if (relaxed[i]) {
        f[i] = 0;
        Q.row(i) = C.row(i);
        Nrm.row(i) = Nc.row(i);
      }
    solver.factorize(assemble());
    out = solve_frame();
  }
  // The box exactly as the map puts it: a per-axis scale of a few parts in 10⁴ (positive, so no face turns).
  fit_box_onto(out, C);
  return out;
}

// A scalar factor of the split similarity system (one for the three axes, or one per axis: see SplitSystem). Eigen's simplicial LDLᵀ below
// 50k vertices rather than SpdSolver's supernodal CHOLMOD: on the scalar system of a small surface mesh
// the supernodal factorization spends more time in its OpenMP regions and workspace than in arithmetic
// (stanford-bunny, 36k vertices: about 0.13 s against 0.09 s CPU); above, the supernodal one is faster.
class ScalarFactor {
 public:
  void factor(const SparseMatrix& A) {
    if (A.rows() >= kSupernodalVertices) {
      if (!supernodal_.analyzed()) supernodal_.analyze(A);
      supernodal_.factorize(A);
      return;
    }
    if (!analyzed_) simplicial_.analyzePattern(A), analyzed_ = true;
    simplicial_.factorize(A);
    if (simplicial_.info() != Eigen::Success || !(simplicial_.vectorD().minCoeff() > 0))
      throw SolverError(fmt::format("resize: the {0}x{0} split similarity system is not positive definite", A.rows()));
  }
  Eigen::MatrixXd solve(const Eigen::MatrixXd& R) const {
    Eigen::MatrixXd Y = R.rows() >= kSupernodalVertices ? supernodal_.solve(R) : Eigen::MatrixXd(simplicial_.solve(R));
    if (!Y.allFinite()) throw SolverError("resize: the split similarity solve is not finite");
    return Y;
  }

 private:
  static constexpr Eigen::Index kSupernodalVertices = 50000;
  SpdSolver supernodal_;
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> simplicial_;
  bool analyzed_ = false;
};

// The split similarity system's three scalar matrices A_a = A_0 + w_F Σ_{pins along a} e_v e_vᵀ (x, y and z
// differ only in the box's pins). Axes with few pinned vertices share one factor of A_0: their pins are
// added back by the Sherman–Morrison–Woodbury identity, A_a⁻¹ = A_0⁻¹ − Z_a (I + U_aᵀ Z_a)⁻¹ Z_aᵀ,
// U_a = √w_F E_a, Z_a = A_0⁻¹ U_a (one solve with a column per pinned vertex of the sharing axes, a
// k_a × k_a capacitance matrix per axis): a factorization and a multi-column solve instead of one of each
// per axis (igea, 25 pins: each relaxation round's factorizations from three to one). An axis with many
// pins (a flat bottom) gets its own factor of A_a; the others still share one when at least two can
// (stanford-bunny: the bottom's pins along y, a few along x and z: two factors instead of three).
class SplitSystem {
 public:
  static constexpr size_t kWoodburyPins = 64;  // pinned vertices (of the sharing axes) up to which they share A_0

  void factor(const SparseMatrix& G, const Eigen::VectorXd& d, const std::vector<std::array<int, 2>>& pins,
              double pin_weight, const MatrixX3d& along) {
    const int n = static_cast<int>(d.size());
    choose_shared(pins, along);
    pin_weight_ = pin_weight;
    for (int a = 0; a < 3; ++a) {
      if (shared_[a]) continue;
      Eigen::VectorXd da = d + along.col(a);
      for (const auto& [v, axis] : pins)
        if (axis == a) da[v] += pin_weight;
      factors_[a].factor(G + SparseMatrix(da.asDiagonal()));
    }
    if (shared_axes() == 0) return;
    factors_[3].factor(G + SparseMatrix(d.asDiagonal()));
    // Z = A_0⁻¹ U for every vertex pinned along a sharing axis at once (one multi-column solve).
    const double u = std::sqrt(pin_weight);
    Eigen::MatrixXd U = Eigen::MatrixXd::Zero(n, static_cast<Eigen::Index>(vertices_.size()));
    for (size_t k = 0; k < vertices_.size(); ++k) U(vertices_[k], static_cast<Eigen::Index>(k)) = u;
    Z_ = vertices_.empty() ? Eigen::MatrixXd(n, 0) : factors_[3].solve(U);
    for (int a = 0; a < 3; ++a) {
      rows_[a].clear();
      columns_[a].clear();
      if (!shared_[a]) continue;
      for (const auto& [v, axis] : pins)
        if (axis == a) {
          rows_[a].push_back(v);
          columns_[a].push_back(static_cast<int>(std::lower_bound(vertices_.begin(), vertices_.end(), v) - vertices_.begin()));
        }
      const auto k = static_cast<Eigen::Index>(rows_[a].size());
      Eigen::MatrixXd cap = Eigen::MatrixXd::Identity(k, k);
      for (Eigen::Index i = 0; i < k; ++i)
        for (Eigen::Index j = 0; j < k; ++j) cap(i, j) += u * Z_(rows_[a][i], columns_[a][j]);
      capacitance_[a].compute(0.5 * (cap + cap.transpose()));
    }
  }
  //! \return the columns of A_a⁻¹ R_a, a = x, y, z.
  MatrixX3d solve(const MatrixX3d& R) const {
    MatrixX3d Y(R.rows(), 3);
    std::vector<int> together;  // the sharing axes' columns, solved with A_0 at once
    for (int a = 0; a < 3; ++a)
      if (shared_[a]) together.push_back(a);
      else Y.col(a) = factors_[a].solve(R.col(a));
    if (together.empty()) return Y;
    Y(Eigen::all, together) = factors_[3].solve(R(Eigen::all, together));
    const double u = std::sqrt(pin_weight_);
    for (int a : together) {
      if (rows_[a].empty()) continue;
      Eigen::VectorXd t(static_cast<Eigen::Index>(rows_[a].size()));
      for (size_t k = 0; k < rows_[a].size(); ++k) t[static_cast<Eigen::Index>(k)] = u * Y(rows_[a][k], a);
      Y.col(a) -= Z_(Eigen::all, columns_[a]) * capacitance_[a].solve(t);
    }
    return Y;
  }

 private:
  // Which axes share A_0: from the fewest pinned vertices up, while their union stays within
  // kWoodburyPins; at least two (one axis alone is cheaper with its own factor).
  void choose_shared(const std::vector<std::array<int, 2>>& pins, const MatrixX3d& soft) {
    std::array<std::vector<int>, 3> along;
    for (const auto& [v, a] : pins) along[a].push_back(v);
    std::array<int, 3> order{0, 1, 2};
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return along[a].size() < along[b].size(); });
    vertices_.clear();
    shared_ = {false, false, false};
    for (int a : order) {
      if (soft.col(a).any()) continue;  // pins spread softly along a (soft_pins()): its own factor
      std::vector<int> merged = vertices_;
      merged.insert(merged.end(), along[a].begin(), along[a].end());
      std::sort(merged.begin(), merged.end());
      merged.erase(std::unique(merged.begin(), merged.end()), merged.end());
      if (merged.size() > kWoodburyPins) break;
      vertices_.swap(merged);
      shared_[a] = true;
    }
    if (shared_axes() < 2) shared_ = {false, false, false}, vertices_.clear();
  }
  int shared_axes() const { return int(shared_[0]) + int(shared_[1]) + int(shared_[2]); }

  std::array<ScalarFactor, 4> factors_;          // A_x, A_y, A_z (the axes of their own), A_0 (the sharing ones)
  std::array<bool, 3> shared_{};
  double pin_weight_ = 0;
  std::vector<int> vertices_;                    // the vertices pinned along a sharing axis: the columns of Z_
  std::array<std::vector<int>, 3> rows_;         // the vertices pinned along each sharing axis
  std::array<std::vector<int>, 3> columns_;      // and their columns of Z_
  Eigen::MatrixXd Z_;                            // A_0⁻¹ U, a column per pinned vertex: A_0⁻¹ U_a its axis' columns
  std::array<Eigen::LLT<Eigen::MatrixXd>, 3> capacitance_;  // I + U_aᵀ A_0⁻¹ U_a
};

// Similarity with the surface term split off (ResizeOptions::solver = Split): the energy of
// similarity_resize below, minimized by alternation. w (n_iᵀ(x_i − q_i))² is the least w |x_i − p_i|²
// over the points p_i of the plane (q_i, n_i); each step solves for x' with the p_i fixed (x, y and z
// apart: one scalar matrix G + diag each, which differ only in the box's pins along their axis) and
// then moves each p_i to the foot of x'_i on its plane: no step increases the energy. The matrices
// change only when faces are relaxed, not when the planes move, and each has a ninth of the coupled 3#V
// system's factor values. (Pins split off the same way, isotropic towards the plane x_a = t_a, would
// need one matrix for the three, but slide too slowly along the box: fandisk ×2 y ratio 0.47 -> 0.73.)
MatrixX3d similarity_resize_split(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C, const Eigen::VectorXd& f0,
                                  const ResizeOptions& o, const SimilarityBase& base) {
  const int n = static_cast<int>(X.rows());
  const double w = o.surface_weight, beta = base.beta, eps = 1e-6;
  constexpr double kRelaxed = 10.0;  // as in similarity_resize
  constexpr int kSettle = 3;         // steps after each factorization (the first, each relaxation)
  constexpr double kCoreAnchor = 100.0;  // a core held by the box: its anchors against edge weights ≤ 1 (10: 4.9 %)
  const MatrixX3i F = faces(mesh);
  std::vector<std::array<int, 2>> edges;
  edges.reserve(mesh.n_edges());
  for (auto e : mesh.edges()) edges.push_back({e.v0().idx(), e.v1().idx()});
  Mesh mapped = mesh;
  set_positions(mapped, C);
  const MatrixX3d Nc = vertex_normals(mapped), N0 = vertex_normals(mesh), Fn_plain = face_normals(mapped);
  report(o.progress, 0.05, "transforms");
  std::vector<Eigen::Matrix3d> T(n);
  Eigen::VectorXd scale(n), s_lo(n), s_hi(n);
  similarity_transforms(local_jacobians(mesh, X, C), N0, o.keep_feature_size, T, scale, s_lo, s_hi);
  const std::vector<std::array<int, 2>> pins = box_extremes(mesh, X, o.frame_band);  // (vertex, axis)
  const SoftPins soft = soft_pins(mesh, X, f0, pins, base.pin_rings, o.frame_weight);
  std::vector<char> boundary(n, 0), relaxed(n, 0);
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v)) boundary[v.idx()] = 1;
  Eigen::VectorXd f = f0;
  MatrixX3d target = C, Nrm = Nc, Q = C, P = C, spread = C;  // P: each vertex's point on its plane
  SplitSystem system;
  Eigen::VectorXd pull, hold;  // ε + the boundary's weight; the surface term's w (1 − f_i)
  Eigen::VectorXd anchor = Eigen::VectorXd::Zero(n);  // wholly important regions held at their similarity
  MatrixX3d place = C;
  const SparseMatrix ties = tie_springs(base.ties, n);
  const MatrixX3d tie_rest = ties * X;
  auto factor = [&] {
    pull = similarity_pull(boundary, f, eps, o.frame_weight);
    hold = w * (1 - f.array()).matrix();
    system.factor(similarity_edge_weights(edges, f, relaxed, beta, base.follow_falloff, kRelaxed) + ties,
                  pull + hold + anchor, pins, o.frame_weight, soft.weight);
  };
  // One step: x' for the points P, then P to the feet of x' on the planes; the pins' targets move by
  // what they miss (a stiff region pulled by its tip moves as a whole instead of stretching).
  auto step = [&] {
    MatrixX3d R = similarity_rhs(edges, X, C, T, f, relaxed, pull, pins, target, beta, base.follow_falloff, kRelaxed,
                                 o.frame_weight);
    R += hold.asDiagonal() * P + anchor.asDiagonal() * place + soft.weight.cwiseProduct(spread) + tie_rest;
    const MatrixX3d Y = system.solve(R);
    for (int i = 0; i < n; ++i) P.row(i) = Y.row(i) - (Y.row(i) - Q.row(i)).dot(Nrm.row(i)) * Nrm.row(i);
    for (const auto& [v, a] : pins) target(v, a) += C(v, a) - Y(v, a);
    for (std::size_t k = 0; k < soft.vertex.size(); ++k)  // pushed along the axis as its extreme's pin
      spread(soft.vertex[k], soft.axis[k]) = C(soft.vertex[k], soft.axis[k]) + target(soft.leader[k], soft.axis[k]) -
                                            C(soft.leader[k], soft.axis[k]);
    return Y;
  };
  const TriangleTree tree(C, F);
  const std::vector<std::vector<int>> cores =
      base.hold_cores_in_box ? wholly_important_regions(mesh, f0) : std::vector<std::vector<int>>{};
  report(o.progress, 0.2, "factor");
  factor();
  MatrixX3d out;
  for (int k = 0; k < kSettle; ++k) out = step();
  for (int it = 0; it < o.iterations; ++it) {  // local-global: rotations and scales, planes, then x'
    report(o.progress, 0.3 + 0.4 * it / std::max(1, o.iterations), "local-global");
    refit_similarities(mesh, X, out, f, o.adapt_scale, s_lo, s_hi, scale, T);
    project_planes(mesh, tree, F, Nc, f, out, Q, Nrm);
    for (int k = 0; k < o.split_steps; ++k) out = step();
  }
  const Vec3 extent = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
  if (anchor_cores_in_box(X, out, cores, o.adapt_scale, s_lo, s_hi, scale, extent, kCoreAnchor, anchor, place)) {
    factor();
    for (int k = 0; k < kSettle; ++k) out = step();
  }
  // Faces turned over against the plain map: relax them and rings around them to the map.
  for (int round = 0; round < o.flip_rounds; ++round) {
    const std::vector<int> bad = turned_faces(F, Fn_plain, out, base.plain_normals);
    if (bad.empty()) break;
    report(o.progress, 0.7 + 0.25 * round / std::max(1, o.flip_rounds), fmt::format("relax {} turned faces", bad.size()));
    mark_around(mesh, F, bad, o.flip_rings + 2 * round, relaxed);  // wider each round
    for (int i = 0; i < n; ++i)
      if (relaxed[i]) {
        f[i] = 0;
        anchor[i] = 0;  // a relaxed core vertex follows the map too
        Q.row(i) = C.row(i);
        Nrm.row(i) = Nc.row(i);
      }
    factor();
    for (int k = 0; k < kSettle; ++k) out = step();
  }
  fit_box_onto(out, C);  // the box exactly as the map puts it
  return out;
}

// The room for protrusions held at their size is one factor per axis over everything else: given only where at
// most this share of it is important (important_share_of_rest()), i.e. the rest is mostly stretchable. Measured:
// the tentacle stick 0.29 (level 1) and 0.43 (level 0), the tentacle plane 0.01; cheburashka 0.92, where the ears
// held at their size made the rest take up to ×1.7 the asked stretch and the detail ratio rose from 0.20-0.27
// to 0.30-0.99 (bench/resize.md, twelfth session).
constexpr double kStretchableRest = 0.5;

// Rigid protrusions (protrusion_placement.h) put back into a method's result \p out for the map \p C with
// importance \p f: the rest stretched a little more per axis so that the box holds them at their size, each put
// back as one piece where its foot went, faces the seams turned relaxed the map's way round, and the box fitted.
// \p out itself where that room cannot be made: the rest is mostly important (kStretchableRest) or the per-axis
// factors do not settle. A protrusion a tie joins to the rest (\p ties) stays where the method put it
// (untied_protrusions()).
MatrixX3d put_back_protrusions(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C, const Eigen::VectorXd& f,
                               const MatrixX3d& out, std::vector<RigidProtrusion> protrusions,
                               const std::vector<SurfaceTie>* ties) {
  if (ties) protrusions = untied_protrusions(mesh, X, std::move(protrusions), *ties);
  if (protrusions.empty() || important_share_of_rest(mesh, X, f, protrusions) > kStretchableRest) return out;
  const Vec3 lo = C.colwise().minCoeff(), hi = C.colwise().maxCoeff();
  const std::optional<MatrixX3d> room = fit_box_around_protrusions(mesh, X, out, lo, hi, protrusions);
  if (!room) return out;
  MatrixX3d Y = place_protrusions(mesh, X, *room, protrusions);
  relax_turned_faces(mesh, C, protrusions, Y);
  if (ties) hold_ties(Y, X, *ties);  // a tied vertex the relaxation moved goes with its point
  fit_box_onto(Y, C);
  return Y;
}

// The faces \p out crosses against the input's own, into \p untangled when given; repaired towards \p safe
// (untangle_resize()) when \p repair, and then towards \p plain (the plain stretch, affine, so crossing only what
// the input does) when given and faces the safe result crosses itself are left (the axis warp crosses one beyond
// the cow's own ×2 y and z). Not counted at all when neither is asked (feature_aware_resize() alone). The vertices
// of \p ties move with their points through the repair.
MatrixX3d count_and_untangle(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& out, const MatrixX3d& safe,
                             const MatrixX3d* plain, bool repair, const ResizeOptions& o, UntangleReport* untangled,
                             const std::vector<SurfaceTie>* ties = nullptr) {
  UntangleReport counts;
  if (!repair && !untangled) return out;
  constexpr UntangleRepair kHow = UntangleRepair::ShiftThenBlend;
  MatrixX3d Y = untangle_resize(mesh, X, out, safe, repair, counts, o.progress, kHow, ties);
  if (repair && plain && counts.excess_after() > 0) {
    UntangleReport second;
    Y = untangle_resize(mesh, X, Y, *plain, repair, second, o.progress, kHow, ties);
    counts.after = second.after;
    counts.blended = std::max(counts.blended, second.blended);
    counts.rounds += second.rounds;
  }
  if (counts.excess_before() > 0) report(o.progress, 0.99, counts.describe());
  if (untangled) *untangled = counts;
  return Y;
}

}  // namespace

ResizeMethod resolved_resize_method(const ResizeOptions& o, const MatrixX3d& X, const MatrixX3d& C) {
  if (o.method != ResizeMethod::Auto) return o.method;
  Vec3 stretch, lo;
  return box_scale_of(X, C, stretch, lo) && stretch.minCoeff() > 0 ? ResizeMethod::AxisSimilarity
                                                                    : ResizeMethod::Similarity;
}

namespace {

// The methods that solve for positions over the surface as one piece: they run on the mesh with its coincident
// vertices welded (weld.h), so that unwelded patches (the teapot's) are not solved apart and opened at their seams.
// Thesis (the preset: unchanged) and Sliding run on the input as it is, and so does every method without
// ResizeOptions::weld.
bool welds_for_solve(const ResizeOptions& o, ResizeMethod m) {
  return o.weld && (m == ResizeMethod::Similarity || m == ResizeMethod::Axis || m == ResizeMethod::AxisSimilarity);
}

// The ties the similarity stage holds on \p m, the mesh solved (the welded one, or the input when \p w welds
// nothing): the copies of each point contact (w.ties) and the rims resting on another part's faces (rim_contacts()):
// the teapot's handle's lower end. (The fifteenth session's rim_contacts() took vertices of no face for rims: 1,085 of
// the stanford-bunny's tied to its faces made its ×2 x 0.261 -> 0.453, one of the beetle's its ×2 z 0.743; those are
// no rim now; bench/resize.md, issue 25, sixteenth session.)
std::vector<SurfaceTie> solve_ties(const Weld& w, const Mesh& m) {
  std::vector<SurfaceTie> ties = rim_contacts(m);
  for (const auto& [a, b] : w.ties) ties.push_back({b, {a, a, a}, Vec3(1, 0, 0)});
  return ties;
}

// The box's lone pins of axis-similarity's similarity stage pull this many vertex rings around them softly along
// (soft_pins(); 2 rings: teapot ×2 z 0.252, 3: 0.241 and its prow 42° -> 15°; bench/resize.md, fifteenth session).
constexpr int kPinRings = 3;

// resize_as_stored() on a mesh whose bounding box is centred at the origin: \p mesh as it is (no weld), with the
// vertices of \p ties held at their points by the similarity stage and left there by the rigid protrusions' placement.
MatrixX3d resize_at_origin(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& features,
                           const ResizeOptions& options, UntangleReport* untangled,
                           const std::vector<SurfaceTie>* ties = nullptr) {
  require_valid(mesh, "resize input");
  check_options(options);
  const int n = static_cast<int>(mesh.n_vertices());
  if (C.rows() != n) throw InvalidInput(fmt::format("deformed positions: {} rows for {} vertices", C.rows(), n));
  if (features.size() != n)
    throw InvalidInput(fmt::format("feature map: {} weights for {} vertices", features.size(), n));
  if (!C.allFinite()) throw InvalidInput("deformed positions must be finite");
  if (!features.allFinite() || features.minCoeff() < 0 || features.maxCoeff() > 1)
    throw InvalidInput("feature weights must lie in [0, 1]");
  const MatrixX3d X = positions(mesh);
  ResizeOptions o = options;
  o.method = resolved_resize_method(options, X, C);
  report(o.progress, 0.0, "transforms");
  if (o.method == ResizeMethod::Axis || o.method == ResizeMethod::AxisSimilarity) {
    Vec3 stretch, lo;
    if (!box_scale_of(X, C, stretch, lo))
      throw InvalidInput("method axis: the deformation must be a box scale (scale); bends, twists, arcs and deformed "
                         "copies need another method (similarity)");
    // Rigid protrusions: found and scaled on the input, put back after the similarity stage (below).
    std::vector<RigidProtrusion> protrusions;
    if (o.method == ResizeMethod::AxisSimilarity && o.rigid_protrusions) {
      protrusions = find_protrusions(mesh, X, features);
      set_protrusion_scales(X, C, protrusions, o.keep_feature_size);
    }
    const MatrixX3d W = axis_warp(mesh, stretch, lo, features, o.axis).apply(X);
    // The similarity stage follows the warp's edges (β = the follow weight) and counts a face as turned
    // against the warp or the plain stretch (the reference; the two differ by the warp's slivers).
    Mesh plain = mesh;
    set_positions(plain, C);
    const MatrixX3d plain_normals = face_normals(plain);
    SimilarityBase base{o.axis.follow_weight, o.axis.follow_falloff, &plain_normals};
    base.hold_cores_in_box = true;  // a box scale: cores the box cannot hold are anchored (anchor_cores_in_box())
    base.pin_rings = kPinRings;
    base.ties = ties;
    MatrixX3d out = o.method == ResizeMethod::Axis            ? W
                    : o.solver == SimilaritySolver::Split ? similarity_resize_split(mesh, X, W, features, o, base)
                                                          : similarity_resize(mesh, X, W, features, o, base);
    // (Giving the protrusions' slabs full importance in the warp changed nothing measurable: bench/resize.md.)
    out = put_back_protrusions(mesh, X, C, features, out, protrusions, ties);
    out = count_and_untangle(mesh, X, out, W, &C, o.method == ResizeMethod::AxisSimilarity && o.untangle, o, untangled,
                             ties);
    report(o.progress, 1.0, "done");
    return out;
  }
  const SimilarityBase base{o.background_smoothness, 0.0, nullptr, false, ties};
  auto similarity = [&](const MatrixX3d& map) {
    return o.solver == SimilaritySolver::Split ? similarity_resize_split(mesh, X, map, features, o, base)
                                               : similarity_resize(mesh, X, map, features, o, base);
  };
  if (o.method == ResizeMethod::Similarity && o.rigid_protrusions) {
    std::vector<RigidProtrusion> protrusions = find_protrusions(mesh, X, features);
    if (!protrusions.empty()) {
      // The similarity method, then the protrusions put back. (Running the similarity method on a map with the
      // room already made and the pieces in place dented the stick's body: its important caps resisted the
      // larger stretch; bench/resize.md, eleventh session.)
      set_protrusion_scales(X, C, protrusions, o.keep_feature_size);
      MatrixX3d out = put_back_protrusions(mesh, X, C, features, similarity(C), protrusions, ties);
      out = count_and_untangle(mesh, X, out, C, nullptr, false, o, untangled);  // counted (see untangle)
      report(o.progress, 1.0, "done");
      return out;
    }
  }
  MatrixX3d out = o.method == ResizeMethod::Thesis    ? thesis_resize(mesh, X, C, features, o)
                  : o.method == ResizeMethod::Sliding ? sliding_resize(mesh, X, C, features, o)
                                                      : similarity(C);
  out = count_and_untangle(mesh, X, out, C, nullptr, false, o, untangled);  // counted only (see untangle)
  report(o.progress, 1.0, "done");
  return out;
}

// feature_aware_resize() without the weld: \p mesh as it is, with the vertices of \p ties held at their points by
// the similarity stage (solve_ties()) and left there by the rigid protrusions' placement. Solved about the box's
// centre: the similarity solve's small pull (ε) towards the map leaves its error in proportion to the positions,
// 6e-3 edge lengths at 10^4 diagonals off the origin (bench/invariance.py).
MatrixX3d resize_as_stored(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& features,
                           const ResizeOptions& options, UntangleReport* untangled,
                           const std::vector<SurfaceTie>* ties = nullptr) {
  const Vec3 c = bounding_box(mesh).center();
  Mesh centred = mesh;
  set_positions(centred, positions(mesh).rowwise() - c.transpose());
  MatrixX3d out = resize_at_origin(centred, C.rowwise() - c.transpose(), features, options, untangled, ties);
  return out.rowwise() + c.transpose();
}

}  // namespace

MatrixX3d feature_aware_resize(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& features,
                               const ResizeOptions& options, UntangleReport* untangled) {
  require_valid(mesh, "resize input");
  if (C.rows() != static_cast<Eigen::Index>(mesh.n_vertices()) || features.size() != C.rows() ||
      !welds_for_solve(options, resolved_resize_method(options, positions(mesh), C)))
    return resize_as_stored(mesh, C, features, options, untangled);  // (which refuses the sizes)
  const Weld w = weld_coincident(mesh);
  const std::vector<SurfaceTie> ties = solve_ties(w, w.identity() ? mesh : w.mesh);
  if (w.identity()) return resize_as_stored(mesh, C, features, options, untangled, &ties);
  // A weight painted on one side of a seam holds the welded vertex (the largest of the copies').
  return w.to_input(resize_as_stored(w.mesh, w.to_welded(C), w.max_to_welded(features), options, untangled, &ties));
}

MatrixX3d feature_aware_resize(const Mesh& mesh, const SpaceMap& map, const Eigen::VectorXd& features,
                               const ResizeOptions& options) {
  return feature_aware_resize(mesh, apply_space_map(map, positions(mesh)), features, options);
}

const OptionTable<ResizeRunOptions>& ResizeRunOptions::table() {
  using O = ResizeRunOptions;
  static const auto t = [] {
    OptionTable<O> t;
    t.nest(&O::map, SpaceMapOptions::table())
        .nest(&O::features, FeatureMapOptions::table())
        .nest(&O::feature_file, FeatureFileOptions::table())
        .nest(&O::resize, ResizeOptions::table());
    // The thesis' runs used a binary map of protrusions (Sec. 9.4): its preset selects "auto" too.
    for (const auto& p : ResizeOptions::table().presets())
      t.preset(p.name, p.help + (p.name == "thesis" ? ", binary feature map (auto)" : ""),
               [apply = p.apply, thesis = p.name == "thesis"](O& o) {
                 apply(o.resize);
                 if (thesis) o.features.method = FeatureMapMethod::Auto;
               });
    return t;
  }();
  return t;
}

ResizeResult resize_mesh(const Mesh& mesh, const ResizeRunOptions& options, const MatrixX3d* deformed,
                         const Eigen::VectorXd* features) {
  check_options(options);
  require_valid(mesh, "resize input");
  if (options.map.identity() == (deformed == nullptr))
    throw InvalidInput(deformed ? "give either a deformed copy or a space map (scale, bend, twist, arc_radius), not both"
                                : "give a deformation: scale, bend, twist, arc_radius (any together), or a deformed copy");
  const Eigen::Index n = mesh.n_vertices();
  ResizeResult r;
  if (deformed) {
    if (deformed->rows() != n)
      throw InvalidInput(fmt::format("the deformed copy has {} vertices, the input {}", deformed->rows(), n));
    r.mapped = *deformed;
  } else {
    r.mapped = apply_space_map(space_map(options.map, bounding_box(mesh)), positions(mesh));
  }
  // The feature map (an ADF needs a Laplace spectrum: seconds on large models) takes the first part
  // of the progress, the solve the rest.
  const double split = features ? 0.0 : 0.4;
  const ProgressFn& progress = options.progress;
  const auto part = [&progress](double lo, double hi) -> ProgressFn {
    if (!progress) return {};
    return [&progress, lo, hi](double f, std::string_view stage) { progress(lo + (hi - lo) * f, stage); };
  };
  if (features && features->size() != n)
    throw InvalidInput(fmt::format("feature map: {} weights for {} vertices", features->size(), n));
  ResizeOptions ro = options.resize;
  ro.progress = part(split, 1.0);
  r.method = resolved_resize_method(ro, positions(mesh), r.mapped);
  // The map and the solve on the welded mesh (welds_for_solve()); the result fields per input vertex.
  const bool weld = welds_for_solve(ro, r.method);
  const Weld w = weld ? weld_coincident(mesh) : Weld{};
  const Mesh& m = w.identity() ? mesh : w.mesh;
  Eigen::VectorXd f;
  if (features) {
    r.features = *features;
    f = w.identity() ? r.features : w.max_to_welded(r.features);  // painted on one side of a seam: held
    r.summary = summarize_features(m, f);
  } else {
    FeatureMapOptions fo = options.features;
    fo.progress = part(0.0, split);
    FeatureMap map = feature_map(m, fo);
    f = std::move(map.weights);
    r.features = w.identity() ? f : w.to_input(f);
    r.detector = map.method;
    r.summary = std::move(map.summary);
  }
  const std::vector<SurfaceTie> ties = weld ? solve_ties(w, m) : std::vector<SurfaceTie>{};
  if (w.identity()) {
    r.V = resize_as_stored(mesh, r.mapped, f, ro, &r.untangle, &ties);
  } else {
    r.V = w.to_input(resize_as_stored(m, w.to_welded(r.mapped), f, ro, &r.untangle, &ties));
  }
  r.welded_vertices = w.merged;
  r.weld_refused_groups = w.refused;
  return r;
}

}  // namespace geotex
