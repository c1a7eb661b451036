#include "geotex/resize/resize.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>

#include "geotex/toolkit/diffusion.h"
#include "geotex/toolkit/editing.h"
#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/linear_solver.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/smoothing.h"
#include "geotex/core/spatial.h"

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

// Frame of the Sliding method: boundary vertices, and vertices within a band of a bounding-box face
// along every axis the mesh really extends in.
std::vector<char> frame_vertices(const Mesh& mesh, const MatrixX3d& X, double band_edges) {
  const int n = static_cast<int>(X.rows());
  std::vector<char> frame(n, 0);
  for (auto v : mesh.vertices())
    if (mesh.is_boundary(v)) frame[v.idx()] = 1;
  const Vec3 lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  const Vec3 ext = hi - lo;
  const double band = band_edges * mean_edge_length(mesh);
  for (int a = 0; a < 3; ++a) {
    if (ext[a] < 0.25 * ext.maxCoeff()) continue;
    for (int i = 0; i < n; ++i)
      if (X(i, a) <= lo[a] + band || X(i, a) >= hi[a] - band) frame[i] = 1;
  }
  return frame;
}

// One similarity per vertex: for vertices of a feature region (connected vertices with f > 0), the
// fit (original → deformed) over the region's foot ring, or over the region if it has no foot ring;
// identity elsewhere.
std::vector<Similarity> region_similarities(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& C,
                                            const Eigen::VectorXd& f, bool allow_scale) {
  const int n = static_cast<int>(X.rows());
  std::vector<Similarity> T(n);
  std::vector<int> region(n, -1), stack, members, foot;
  std::vector<int> foot_mark(n, -1);
  int count = 0;
  for (int seed = 0; seed < n; ++seed) {
    if (f[seed] <= 0 || region[seed] >= 0) continue;
    members.clear();
    foot.clear();
    region[seed] = count;
    stack.assign(1, seed);
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      members.push_back(v);
      for (auto w : mesh.vv_range(mesh.vertex_handle(v))) {
        const int j = w.idx();
        if (f[j] > 0) {
          if (region[j] < 0) { region[j] = count; stack.push_back(j); }
        } else if (foot_mark[j] != count) {
          foot_mark[j] = count;
          foot.push_back(j);
        }
      }
    }
    const std::vector<int>& fit = foot.size() >= 3 ? foot : members;
    Eigen::MatrixX3d P(fit.size(), 3), Q(fit.size(), 3);
    for (size_t k = 0; k < fit.size(); ++k) {
      P.row(k) = X.row(fit[k]);
      Q.row(k) = C.row(fit[k]);
    }
    const Similarity S = fit_similarity(P, Q, allow_scale);
    for (int v : members) T[v] = S;
    ++count;
  }
  return T;
}

}  // namespace

MatrixX3d feature_aware_resize(const Mesh& mesh, const MatrixX3d& C, const Eigen::VectorXd& f,
                               const ResizeOptions& o) {
  require_valid(mesh, "resize input");
  const int n = static_cast<int>(mesh.n_vertices());
  if (C.rows() != n) throw InvalidInput(fmt::format("deformed positions: {} rows for {} vertices", C.rows(), n));
  if (f.size() != n) throw InvalidInput(fmt::format("feature map: {} weights for {} vertices", f.size(), n));
  if (!C.allFinite()) throw InvalidInput("deformed positions must be finite");
  if (!f.allFinite() || f.minCoeff() < 0 || f.maxCoeff() > 1) throw InvalidInput("feature weights must lie in [0, 1]");
  if (!(o.position_weight > 0)) throw InvalidInput("position weight w must be positive");
  report(o.progress, 0.0, "transforms");

  const MatrixX3d X = positions(mesh);
  const SparseMatrix L = editing_laplacian(mesh, o.laplacian);
  const double w = o.position_weight;
  const double eps = 1e-6 * w;  // keeps the system definite when every vertex is a feature
  const Eigen::VectorXd p = Eigen::VectorXd::Ones(n) - f;  // p_i = 1 − f_i

  if (o.method == ResizeMethod::Thesis) {
    const MatrixX3d D = L * X;  // Eq. (9.1)
    // T_i by SVD between the original and the deformed 1-rings; δ^t_i = T_i δ_i (Eq. 9.3's D^t).
    const std::vector<Similarity> T = one_ring_similarities(mesh, X, C, !o.keep_feature_size);
    MatrixX3d Dt(n, 3);
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; ++i) Dt.row(i) = (T[i].linear() * D.row(i).transpose()).transpose();
    // Eq. (9.2–9.3) in normal-equation form: (Lᵀ F L + w P) X = Lᵀ F D^t + w P C.
    report(o.progress, 0.3, "factor");
    const Eigen::VectorXd pw = (w * p).array() + eps;
    SparseMatrix A = SparseMatrix(L.transpose() * f.asDiagonal() * L);
    for (int i = 0; i < n; ++i) A.coeffRef(i, i) += pw[i];
    SpdSolver solver;
    solver.compute(A);
    report(o.progress, 0.7, "solve");
    const MatrixX3d rhs = L.transpose() * (f.asDiagonal() * Dt) + pw.asDiagonal() * C;
    MatrixX3d out = solver.solve(rhs);
    report(o.progress, 1.0, "done");
    return out;
  }

  // Sliding. Unknowns stacked [x; y; z]. Energy:
  //   Σ_edges f_ij |(x'_i − x'_j) − T_r (x_i − x_j)|²  features stay rigid (rotated with their base, region r)
  // + β Σ_edges p_ij |(x'_i − x'_j) − (c_i − c_j)|²  background: a weak membrane spreading the stretch
  // + w Σ p_i (n_iᵀ (x'_i − q_i))²                background held to the deformed surface along its normal
  // + w_F Σ_{frame} p_i |x'_i − c_i|²             the outer frame follows the space map
  // + ε Σ |x'_i − c_i|²
  // with q_i = c_i and n_i the deformed base's vertex normal, then q_i, n_i re-taken at the closest
  // point of the deformed base and the system re-solved (refinements) while a plane changes.
  const double beta = o.background_smoothness;
  if (!(beta > 0)) throw InvalidInput("background smoothness must be positive");
  const std::vector<char> frame = frame_vertices(mesh, X, o.frame_band);
  const double h_mean = mean_edge_length(mesh);
  Mesh deformed = mesh;
  set_positions(deformed, C);
  // The base: faces whose vertices are all background (f < ½). The background slides along the
  // deformed base, not along a feature's deformed (e.g. stretched) surface, and its normals are the
  // base's own: a vertex normal averaged with a feature's faces would tilt toward the feature and
  // drag the feature's foot along it. Vertices without a base face keep their vertex normal.
  MatrixX3i Fb;
  MatrixX3d Nv = vertex_normals(deformed);
  {
    const MatrixX3i F = faces(mesh);
    const MatrixX3d Fn = face_normals(deformed);
    const Eigen::VectorXd area = face_areas(deformed);
    std::vector<int> base_faces;
    MatrixX3d acc = MatrixX3d::Zero(n, 3);
    for (Eigen::Index k = 0; k < F.rows(); ++k) {
      if (f[F(k, 0)] >= 0.5 || f[F(k, 1)] >= 0.5 || f[F(k, 2)] >= 0.5) continue;
      base_faces.push_back(static_cast<int>(k));
      for (int j = 0; j < 3; ++j) acc.row(F(k, j)) += area[k] * Fn.row(k);
    }
    Fb.resize(static_cast<Eigen::Index>(base_faces.size()), 3);
    for (size_t k = 0; k < base_faces.size(); ++k) Fb.row(k) = F.row(base_faces[k]);
    for (int i = 0; i < n; ++i)
      if (acc.row(i).norm() > 0) Nv.row(i) = acc.row(i).normalized();
  }
  MatrixX3d Nrm = Nv;
  MatrixX3d Q = C;

  // Features: one rotation (similarity) per connected feature region, fitted on the region's foot
  // ring (the background vertices around it, nearly planar, so the fit turns the region with the
  // tangent plane of its base) or, without a foot ring, on the region itself; then every edge inside a
  // feature keeps its rotated original vector (a rigid region, unlike Laplacian coordinates, which a
  // stretched rim stretches along).
  const std::vector<Similarity> Tc = region_similarities(mesh, X, C, f, !o.keep_feature_size);
  // Edge terms, one 1-ring stencil for both: feature edges keep their rotated original vectors
  // (weight f_ij = min(f_i, f_j)); background edges follow the deformed edge vectors with the small
  // weight β p_ij (a membrane that spreads the stretch; p_ij = max(p_i, p_j)).
  SparseMatrix G(n, n);
  MatrixX3d lap_rhs = MatrixX3d::Zero(n, 3);
  {
    std::vector<Triplet> t;
    t.reserve(4 * mesh.n_edges());
    for (auto e : mesh.edges()) {
      const int a = e.v0().idx(), b = e.v1().idx();
      const double fe = std::min(f[a], f[b]);
      const double be = beta * std::max(p[a], p[b]);
      const double we = fe + be;
      if (we <= 0) continue;
      const Eigen::RowVector3d r = fe * (Tc[a].linear() * (X.row(a) - X.row(b)).transpose()).transpose() +
                                   be * (C.row(a) - C.row(b));
      t.emplace_back(a, a, we);
      t.emplace_back(b, b, we);
      t.emplace_back(a, b, -we);
      t.emplace_back(b, a, -we);
      lap_rhs.row(a) += r;
      lap_rhs.row(b) -= r;
    }
    G.setFromTriplets(t.begin(), t.end());
  }
  Eigen::VectorXd diag_w(n);  // isotropic pull to c_i
  for (int i = 0; i < n; ++i) diag_w[i] = eps + (frame[i] ? o.frame_weight * p[i] : 0.0);

  std::vector<Triplet> base;
  add_blocks(base, G, n);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) base.emplace_back(d * n + i, d * n + i, diag_w[i]);

  SpdSolver solver;
  std::unique_ptr<TriangleTree> tree;
  MatrixX3d out = C;
  const int rounds = 1 + std::max(0, o.refinements);
  for (int round = 0; round < rounds; ++round) {
    report(o.progress, 0.1 + 0.8 * round / rounds, "factor");
    std::vector<Triplet> t = base;
    t.reserve(base.size() + 9 * n);
    Eigen::VectorXd b = stack(lap_rhs + diag_w.asDiagonal() * C);
    for (int i = 0; i < n; ++i) {
      const double wi = w * p[i];
      const Vec3 nv = Nrm.row(i);
      const double nq = nv.dot(Q.row(i));
      for (int d = 0; d < 3; ++d) {
        for (int e = 0; e < 3; ++e) t.emplace_back(d * n + i, e * n + i, wi * nv[d] * nv[e]);
        b[d * n + i] += wi * nv[d] * nq;
      }
    }
    SparseMatrix A(3 * n, 3 * n);
    A.setFromTriplets(t.begin(), t.end());
    if (round == 0) solver.analyze(A, 3);  // x, y, z of a vertex together (see SpdSolver::analyze)
    solver.factorize(A);
    report(o.progress, 0.1 + 0.8 * (round + 0.5) / rounds, "solve");
    out = unstack(solver.solve(b).col(0));
    if (round + 1 == rounds) break;
    // Re-take q_i and n_i at the closest point of the deformed base (curved bases); stop when no
    // constraint plane changes (flat bases: the system, and so the solution, would be the same).
    if (Fb.rows() == 0) break;
    if (!tree) tree = std::make_unique<TriangleTree>(C, Fb);
    double change = 0;
#pragma omp parallel for schedule(static) reduction(max : change)
    for (int i = 0; i < n; ++i) {
      if (p[i] <= 0) continue;
      const TriangleTree::Hit hit = tree->closest(out.row(i).transpose());
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
    if (change < 1e-9) break;
  }
  report(o.progress, 1.0, "done");
  return out;
}

MatrixX3d feature_aware_resize(const Mesh& mesh, const SpaceMap& map, const Eigen::VectorXd& features,
                               const ResizeOptions& options) {
  const MatrixX3d X = positions(mesh);
  MatrixX3d C(X.rows(), 3);
#pragma omp parallel for schedule(static)
  for (Eigen::Index i = 0; i < X.rows(); ++i) C.row(i) = map(X.row(i).transpose()).transpose();
  return feature_aware_resize(mesh, C, features, options);
}

// ---------------------------------------------------------------------------------------------

Eigen::VectorXd dilate_features(const Mesh& mesh, const Eigen::VectorXd& f, int rings) {
  Eigen::VectorXd g = f;
  for (int r = 0; r < rings; ++r) {
    Eigen::VectorXd h = g;
    for (auto e : mesh.edges()) {
      const int a = e.v0().idx(), b = e.v1().idx();
      h[a] = std::max(h[a], g[b]);
      h[b] = std::max(h[b], g[a]);
    }
    g = h;
  }
  return g;
}

Eigen::VectorXd features_from_values(const Mesh& mesh, const Eigen::VectorXd& height, double threshold, int dilate) {
  if (height.size() != static_cast<Eigen::Index>(mesh.n_vertices()))
    throw InvalidInput(fmt::format("{} height values for {} vertices", height.size(), mesh.n_vertices()));
  Eigen::VectorXd f = (height.array().abs() > threshold).cast<double>();
  return dilate_features(mesh, f, dilate);
}

Eigen::VectorXd features_from_height(const Mesh& mesh, const FeatureMapOptions& o) {
  SmoothingOptions s;
  s.laplacian = LaplacianType::Cotangent;
  s.lambda = o.smoothing_time;
  s.steps = 1;
  s.update_weights = false;
  Mesh base = mesh;
  set_positions(base, smooth(mesh, s));
  const MatrixX3d N = vertex_normals(base);
  const MatrixX3d d = positions(mesh) - positions(base);
  const double h = mean_edge_length(mesh);
  const Eigen::VectorXd height = (d.cwiseProduct(N)).rowwise().sum() / h;
  return features_from_values(mesh, height, o.height_threshold, o.dilate);
}

Eigen::VectorXd features_from_adf(const Mesh& mesh, double t, int eigenpairs, double threshold, int dilate) {
  const Eigen::VectorXd adf = auto_diffusion_function(mesh, {t, eigenpairs});
  const double lo = adf.minCoeff(), hi = adf.maxCoeff();
  const Eigen::VectorXd a = hi > lo ? Eigen::VectorXd((adf.array() - lo) / (hi - lo)) : Eigen::VectorXd::Zero(adf.size());
  return features_from_values(mesh, a, threshold, dilate);
}

// ---------------------------------------------------------------------------------------------

BumpyPlate bumpy_plate(const BumpyPlateOptions& o) {
  if (o.n < 2 || o.bumps < 0 || !(o.radius > 0)) throw InvalidInput("bumpy_plate: bad options");
  BumpyPlate b;
  b.mesh = plane(o.n, 2.0);
  b.radius = o.radius;
  b.height = o.height;
  for (int i = 0; i < o.bumps; ++i)
    for (int j = 0; j < o.bumps; ++j)
      b.centres.emplace_back((i - 0.5 * (o.bumps - 1)) * o.spacing, (j - 0.5 * (o.bumps - 1)) * o.spacing, 0.0);
  MatrixX3d X = positions(b.mesh);
  b.truth = Eigen::VectorXd::Zero(X.rows());
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    for (const Vec3& c : b.centres) {
      const double r = (X.row(v).head<2>() - c.head<2>().transpose()).norm();
      if (r < o.radius) {
        const double s = 1.0 - r * r / (o.radius * o.radius);
        X(v, 2) += o.height * s * s;
        b.truth[v] = 1;
      }
    }
  set_positions(b.mesh, X);
  return b;
}

BumpShape measure_bump(const MatrixX3d& X0, const MatrixX3d& X1, const Vec3& centre, double radius) {
  std::vector<int> rim;
  int tip = -1;
  double best = 1e300;
  for (Eigen::Index i = 0; i < X0.rows(); ++i) {
    const double r = (X0.row(i).head<2>() - centre.head<2>().transpose()).norm();
    if (r >= 0.7 * radius && r <= 0.95 * radius) rim.push_back(static_cast<int>(i));
    if (r < best) { best = r; tip = static_cast<int>(i); }
  }
  if (rim.size() < 3 || tip < 0) throw InvalidInput("measure_bump: too few vertices in the bump's rim ring");
  Eigen::MatrixX3d P(rim.size(), 3);
  for (size_t k = 0; k < rim.size(); ++k) P.row(k) = X1.row(rim[k]);
  const Eigen::RowVector3d c = P.colwise().mean();
  const Eigen::MatrixX3d Pc = P.rowwise() - c;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Pc.transpose() * Pc / static_cast<double>(rim.size()));
  // eigenvalues ascending: [0] is the plane normal's, [1], [2] the in-plane spreads.
  Vec3 nrm = es.eigenvectors().col(0);
  const Vec3 up = X1.row(tip).transpose() - c.transpose();
  if (nrm.dot(up) < 0) nrm = -nrm;
  BumpShape s;
  s.aspect = std::sqrt(es.eigenvalues()[2] / es.eigenvalues()[1]);
  s.height = nrm.dot(up);
  s.tilt_deg = std::acos(std::clamp(nrm.dot(up.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
  return s;
}

}  // namespace geotex
