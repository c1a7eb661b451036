#include "geotex/toolkit/parametrization.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/SparseLU>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

const EnumNames<ParamMethod>& param_method_names() {
  static const EnumNames<ParamMethod> n = {{"conformal", ParamMethod::Conformal},
                                           {"authalic", ParamMethod::Authalic},
                                           {"combined", ParamMethod::Combined},
                                           {"natural", ParamMethod::NaturalConformal}};
  return n;
}

const OptionTable<ParametrizationOptions>& ParametrizationOptions::table() {
  using O = ParametrizationOptions;
  static const auto t = OptionTable<O>()
      .choice("method", &O::method, param_method_names(),
              "conformal (cotangent harmonic), authalic, combined (Desbrun et al. 2002), or natural (free-boundary "
              "conformal)", "Eq. (5.84-5.88)")
      .add("conformal_weight", &O::conformal_weight, "combined: weight of the conformal energy (the authalic one gets 1 - it)",
           unit_interval())
      .alias("lambda");
  return t;
}

namespace {

constexpr double kMaxCot = 1e4;

inline Vec3 P(const Mesh& m, int i) { return to_eigen(m.point(m.vertex_handle(i))); }

// cot of the angle between u and v, clamped like cotan_matrix() does.
inline double cot(const Vec3& u, const Vec3& v) {
  const double c = u.cross(v).norm();
  const double d = u.dot(v);
  if (c <= std::abs(d) / kMaxCot) return d >= 0 ? kMaxCot : -kMaxCot;
  return std::clamp(d / c, -kMaxCot, kMaxCot);
}

// Authalic weights of Desbrun, Meyer, Alliez (2002): row i, column j gets
// (cot γ_ij + cot δ_ij) / |x_i − x_j|², with γ, δ the angles at x_j of the two faces beside edge ij.
// Not symmetric. Diagonal = −row sum, like Eq. (5.88).
SparseMatrix authalic_matrix(const Mesh& mesh) {
  const int n = static_cast<int>(mesh.n_vertices());
  std::vector<Triplet> t;
  t.reserve(4 * mesh.n_edges());
  for (auto f : mesh.faces()) {
    int id[3], k = 0;
    for (auto v : f.vertices()) id[k++] = v.idx();
    for (int c = 0; c < 3; ++c) {
      // Corner j = id[c]; its two edges go to i1 = id[c+1] and i2 = id[c+2]. The angle at j
      // is beside both edges (j, i1) and (j, i2): it contributes to rows i1 and i2 at column j.
      const int j = id[c], i1 = id[(c + 1) % 3], i2 = id[(c + 2) % 3];
      const Vec3 xj = P(mesh, j), x1 = P(mesh, i1), x2 = P(mesh, i2);
      const double ct = cot(x1 - xj, x2 - xj);
      const double w1 = ct / std::max((x1 - xj).squaredNorm(), 1e-300);
      const double w2 = ct / std::max((x2 - xj).squaredNorm(), 1e-300);
      t.emplace_back(i1, j, w1);
      t.emplace_back(i1, i1, -w1);
      t.emplace_back(i2, j, w2);
      t.emplace_back(i2, i2, -w2);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

// Dirichlet problem: rows of the interior vertices of K (rows sum to zero), boundary fixed to B.
// Solves K_II U_I = −K_IB B (Eq. 5.87). Symmetric negative semi-definite K goes to Cholesky.
MatrixX2d solve_fixed_boundary(const SparseMatrix& K, const std::vector<int>& loop, const MatrixX2d& B,
                               bool symmetric) {
  const int n = static_cast<int>(K.rows());
  std::vector<int> slot(n, -1);  // interior index, or −(boundary position + 2)
  for (size_t b = 0; b < loop.size(); ++b) slot[loop[b]] = -static_cast<int>(b) - 2;
  int ni = 0;
  for (int i = 0; i < n; ++i)
    if (slot[i] == -1) slot[i] = ni++;

  MatrixX2d U(n, 2);
  for (size_t b = 0; b < loop.size(); ++b) U.row(loop[b]) = B.row(static_cast<Eigen::Index>(b));
  if (ni == 0) return U;

  std::vector<Triplet> t;
  t.reserve(K.nonZeros());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(ni, 2);
  const double sign = symmetric ? -1.0 : 1.0;  // −K is positive definite on the interior
  for (int col = 0; col < K.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(K, col); it; ++it) {
      const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
      if (slot[r] < 0) continue;
      if (slot[c] >= 0)
        t.emplace_back(slot[r], slot[c], sign * it.value());
      else
        rhs.row(slot[r]) -= sign * it.value() * B.row(-slot[c] - 2);
    }
  SparseMatrix A(ni, ni);
  A.setFromTriplets(t.begin(), t.end());
  Eigen::MatrixXd X;
  if (symmetric) {
    SpdSolver solver;
    solver.compute(A);
    X = solver.solve(rhs);
  } else {
    Eigen::SparseLU<SparseMatrix> lu;
    lu.compute(A);
    if (lu.info() != Eigen::Success) throw SolverError("parametrization: sparse LU factorization failed");
    X = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !X.allFinite()) throw SolverError("parametrization: sparse LU solve failed");
  }
  for (int i = 0; i < n; ++i)
    if (slot[i] >= 0) U.row(i) = X.row(slot[i]);
  return U;
}

// Natural conformal map (DMA 2002, equivalent to least-squares conformal maps): minimize
// E_C = E_D − A(U), with E_D the Dirichlet energy ½ Σ_ij (−C_ij)|u_i − u_j|² and A the signed UV
// area, over z = [u; v] with two boundary vertices pinned. E_C is ≥ 0 and vanishes exactly for
// conformal maps; its quadratic form is symmetric positive semi-definite, definite once two points are pinned.
MatrixX2d natural_conformal(const Mesh& mesh, const std::vector<int>& loop) {
  const int n = static_cast<int>(mesh.n_vertices());
  const SparseMatrix C = cotan_matrix(mesh, {kMaxCot});
  std::vector<Triplet> t;
  t.reserve(2 * C.nonZeros() + 8 * loop.size());
  for (int col = 0; col < C.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(C, col); it; ++it) {
      t.emplace_back(it.row(), it.col(), -it.value());
      t.emplace_back(n + it.row(), n + it.col(), -it.value());
    }
  // Signed area ½ Σ (u_a v_b − u_b v_a) over the boundary halfedges a→b that carry a face, as a
  // symmetric form ½ zᵀ K z; the energy's matrix is −C ⊕ −C minus K.
  for (auto h : mesh.halfedges()) {
    if (!h.is_boundary()) continue;
    const auto hf = h.opp();  // a→b with the face on its left
    const int a = hf.from().idx(), b = hf.to().idx();
    t.emplace_back(a, n + b, -0.5);
    t.emplace_back(n + b, a, -0.5);
    t.emplace_back(b, n + a, 0.5);
    t.emplace_back(n + a, b, 0.5);
  }
  SparseMatrix Q(2 * n, 2 * n);
  Q.setFromTriplets(t.begin(), t.end());

  // Pin the two boundary vertices farthest apart (in 3D) to (0, 0) and (1, 0).
  int p0 = loop[0], p1 = loop[0];
  double best = -1;
  for (int a : loop)
    if (const double d = (P(mesh, a) - P(mesh, loop[0])).squaredNorm(); d > best) { best = d; p1 = a; }
  best = -1;
  for (int a : loop)
    if (const double d = (P(mesh, a) - P(mesh, p1)).squaredNorm(); d > best) { best = d; p0 = a; }
  // Two pins at one place leave the similarity of the map free (a singular system): decide it on the
  // input, scale-aware, before factoring.
  if (!((P(mesh, p0) - P(mesh, p1)).norm() > 1e-9 * mean_edge_length(mesh)))
    throw InvalidInput("natural parametrization: every boundary vertex is at one point (nothing to pin two "
                       "vertices apart)");
  Eigen::VectorXd z_fixed = Eigen::VectorXd::Zero(2 * n);
  std::vector<char> fixed(2 * n, 0);
  fixed[p0] = fixed[n + p0] = fixed[p1] = fixed[n + p1] = 1;
  z_fixed[p1] = 1.0;

  std::vector<int> slot(2 * n, -1);
  int nf = 0;
  for (int i = 0; i < 2 * n; ++i)
    if (!fixed[i]) slot[i] = nf++;
  std::vector<Triplet> tf;
  tf.reserve(Q.nonZeros());
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf);
  for (int col = 0; col < Q.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(Q, col); it; ++it) {
      const int r = static_cast<int>(it.row()), c = static_cast<int>(it.col());
      if (slot[r] < 0) continue;
      if (slot[c] >= 0)
        tf.emplace_back(slot[r], slot[c], it.value());
      else
        rhs[slot[r]] -= it.value() * z_fixed[c];
    }
  SparseMatrix A(nf, nf);
  A.setFromTriplets(tf.begin(), tf.end());
  SpdSolver solver;
  solver.compute(A);
  const Eigen::VectorXd x = solver.solve(rhs);
  MatrixX2d U(n, 2);
  for (int i = 0; i < n; ++i) {
    U(i, 0) = slot[i] >= 0 ? x[slot[i]] : z_fixed[i];
    U(i, 1) = slot[n + i] >= 0 ? x[slot[n + i]] : z_fixed[n + i];
  }
  // Normalise to the unit disk: centre on the boundary's centroid, farthest vertex at radius 1.
  Eigen::RowVector2d centre = Eigen::RowVector2d::Zero();
  for (int a : loop) centre += U.row(a);
  centre /= static_cast<double>(loop.size());
  U.rowwise() -= centre;
  const double r = U.rowwise().norm().maxCoeff();
  if (!(r > 0)) throw SolverError("natural conformal parametrization collapsed to a point");
  U /= r;
  return U;
}

}  // namespace

std::string disk_topology_problem(const Mesh& mesh) {
  if (mesh.n_faces() == 0) return "the mesh has no faces";
  const MeshSummary s = summarize(mesh);
  if (s.isolated_vertices > 0) return fmt::format("the mesh has {} isolated vertices", s.isolated_vertices);
  if (s.components != 1) return fmt::format("the mesh has {} connected components, a disk has 1", s.components);
  if (s.boundary_loops == 0) return "the mesh is closed (no boundary loop); cut it open to a disk first";
  if (s.boundary_loops > 1)
    return fmt::format("the mesh has {} boundary loops, a disk has 1 (annulus or holes)", s.boundary_loops);
  if (s.euler != 1) return fmt::format("the mesh has genus {} (Euler characteristic {}), a disk has 0", s.genus, s.euler);
  return {};
}

MatrixX2d boundary_on_circle(const Mesh& mesh, const std::vector<int>& loop) {
  const size_t m = loop.size();
  std::vector<double> s(m + 1, 0.0);
  for (size_t k = 0; k < m; ++k) s[k + 1] = s[k] + (P(mesh, loop[(k + 1) % m]) - P(mesh, loop[k])).norm();
  const double L = s[m];
  MatrixX2d B(m, 2);
  for (size_t k = 0; k < m; ++k) {
    // boundary_loops() walks the face-less halfedges, i.e. clockwise around the faces: go clockwise.
    const double th = L > 0 ? -2.0 * M_PI * s[k] / L : -2.0 * M_PI * k / m;
    B(k, 0) = std::cos(th);
    B(k, 1) = std::sin(th);
  }
  return B;
}

MatrixX2d parametrize(const Mesh& disk, const ParametrizationOptions& options) {
  check_options(options);
  require_valid(disk, "parametrization input");
  if (const std::string why = disk_topology_problem(disk); !why.empty())
    throw InvalidInput("parametrization needs a disk-topology mesh: " + why);
  const std::vector<int> loop = boundary_loops(disk).front();
  if (options.method == ParamMethod::NaturalConformal) return natural_conformal(disk, loop);

  const MatrixX2d B = boundary_on_circle(disk, loop);
  if (options.method == ParamMethod::Conformal) {
    // Eq. (5.88): M_ij = cot α_ij + cot β_ij = 2 C_ij; the factor 2 does not change the solution.
    return solve_fixed_boundary(cotan_matrix(disk, {kMaxCot}), loop, B, true);
  }
  SparseMatrix K = authalic_matrix(disk);
  if (options.method == ParamMethod::Combined) {
    const double lambda = options.conformal_weight;
    const double h2 = std::pow(mean_edge_length(disk), 2);
    K = (lambda * 2.0) * cotan_matrix(disk, {kMaxCot}) + ((1.0 - lambda) * h2) * K;
  }
  return solve_fixed_boundary(K, loop, B, false);
}

ParamQuality parametrization_quality(const Mesh& mesh, const MatrixX2d& uv) {
  if (uv.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
    throw InvalidInput("parametrization_quality: uv must have one row per vertex");
  ParamQuality q;
  const MatrixX3i F = faces(mesh);
  const MatrixX3d X = positions(mesh);
  double sum3 = 0, sum2 = 0;
  Eigen::VectorXd a3(F.rows()), a2(F.rows());
  double angle_sum = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 x0 = X.row(F(f, 0)), x1 = X.row(F(f, 1)), x2 = X.row(F(f, 2));
    const Eigen::Vector2d u0 = uv.row(F(f, 0)), u1 = uv.row(F(f, 1)), u2 = uv.row(F(f, 2));
    a3[f] = 0.5 * (x1 - x0).cross(x2 - x0).norm();
    const Eigen::Vector2d e1 = u1 - u0, e2 = u2 - u0;
    a2[f] = 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
    if (!(a2[f] > 0)) ++q.flipped;
    sum3 += a3[f];
    sum2 += std::abs(a2[f]);
    const Vec3 xs[3] = {x0, x1, x2};
    const Eigen::Vector2d us[3] = {u0, u1, u2};
    for (int c = 0; c < 3; ++c) {
      const Vec3 p = xs[(c + 1) % 3] - xs[c], r = xs[(c + 2) % 3] - xs[c];
      const Eigen::Vector2d pu = us[(c + 1) % 3] - us[c], ru = us[(c + 2) % 3] - us[c];
      const double t3 = std::atan2(p.cross(r).norm(), p.dot(r));
      const double t2 = std::atan2(std::abs(pu.x() * ru.y() - pu.y() * ru.x()), pu.dot(ru));
      const double err = std::abs(t2 - t3) * 180.0 / M_PI;
      angle_sum += err;
      q.max_angle_error_deg = std::max(q.max_angle_error_deg, err);
    }
  }
  q.mean_angle_error_deg = F.rows() ? angle_sum / (3.0 * F.rows()) : 0;
  double acc = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (a3[f] <= 0 || a2[f] == 0) continue;
    acc += a3[f] * std::abs(std::log((std::abs(a2[f]) / sum2) / (a3[f] / sum3)));
  }
  q.mean_log_area_ratio = sum3 > 0 ? acc / sum3 : 0;
  return q;
}

void write_obj_with_uv(const Mesh& mesh, const MatrixX2d& uv, const std::filesystem::path& path) {
  if (uv.rows() != static_cast<Eigen::Index>(mesh.n_vertices()))
    throw InvalidInput("write_obj_with_uv: uv must have one row per vertex");
  std::string out = "# geotex parametrization: one vt per vertex\n";
  out.reserve(64 * mesh.n_vertices() + 32 * mesh.n_faces());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    out += fmt::format("v {} {} {}\n", p[0], p[1], p[2]);
  }
  for (Eigen::Index i = 0; i < uv.rows(); ++i) out += fmt::format("vt {} {}\n", uv(i, 0), uv(i, 1));
  for (auto f : mesh.faces()) {
    out += 'f';
    for (auto v : f.vertices()) out += fmt::format(" {0}/{0}", v.idx() + 1);
    out += '\n';
  }
  write_text_atomic(path, out);
}

}  // namespace geotex
