#include "geotex/resize/axis_warp.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "geotex/core/error.h"

namespace geotex {

const OptionTable<AxisWarpOptions>& AxisWarpOptions::table() {
  using O = AxisWarpOptions;
  static const auto t = OptionTable<O>()
      .add("cells", &O::cells, "axis: grid cells along the box's diagonal (each axis about cells L_a / diagonal)",
           between(1, 4096))
      .add("smoothness", &O::smoothness, "axis: weight of the stretch's variation along each axis", non_negative())
      .add("size_weight", &O::size_weight,
           "axis: weight of important faces keeping the asked scale's smallest factor", non_negative())
      .add("plain_weight", &O::plain_weight, "axis: weight of each grid node's pull to the plain stretch", positive())
      .add("in_plane_size", &O::in_plane_size,
           "axis: the size term counts each axis by its share in a face's plane (1 - n_a^2): a face across the stretch "
           "takes it for free; false: every axis fully")
      .add("slab_weight", &O::slab_weight,
           "axis: weight of each slab keeping the asked scale's smallest factor by its mean importance v as v / (1 - v) "
           "(a slab holding only a protrusion's end does not stretch; opt-in: lowers other models' ratios)",
           non_negative())
      .add("min_scale", &O::min_scale,
           "axis: no cell is squeezed below this share of the asked scale's smallest factor", between(0.01, 0.99))
      .add("max_scale", &O::max_scale,
           "axis: no cell along an axis is stretched beyond this multiple of the asked factor along it (0: no limit)",
           non_negative())
      .add("follow_weight", &O::follow_weight,
           "axis-similarity: weight of every edge following the warp in the similarity stage (its background "
           "smoothness)", positive())
      .add("follow_falloff", &O::follow_falloff,
           "axis-similarity: an edge follows the warp with the follow weight times (1 - f)^p, p this value and f its "
           "importance: important regions follow only their similarity (0: every edge the follow weight)",
           between(0, 8));
  return t;
}

double AxisWarp::map(int a, double x) const {
  const Eigen::VectorXd& s = scales[a];
  if (s.size() == 0) return out_lo[a] + stretch[a] * (x - lo[a]);
  const int k = static_cast<int>(s.size()) - 1;
  const double h = step[a], u = (x - lo[a]) / h;
  if (u <= 0) return out_lo[a] + s[0] * (x - lo[a]);
  double g = out_lo[a];  // g at node m: the trapezoid sums of σ (σ is linear between nodes)
  const int m = std::min(static_cast<int>(u), k);
  for (int j = 0; j < m; ++j) g += 0.5 * h * (s[j] + s[j + 1]);
  const double d = x - (lo[a] + m * h);
  if (m == k) return g + s[k] * d;  // beyond the box: linear
  return g + s[m] * d + 0.5 * (s[m + 1] - s[m]) * d * d / h;
}

MatrixX3d AxisWarp::apply(const MatrixX3d& X) const {
  MatrixX3d Y(X.rows(), 3);
  for (int a = 0; a < 3; ++a) {
    const Eigen::VectorXd& s = scales[a];
    if (s.size() == 0) {
      for (Eigen::Index i = 0; i < X.rows(); ++i) Y(i, a) = out_lo[a] + stretch[a] * (X(i, a) - lo[a]);
      continue;
    }
    const int k = static_cast<int>(s.size()) - 1;
    const double h = step[a];
    Eigen::VectorXd G(k + 1);  // g at the nodes
    G[0] = out_lo[a];
    for (int j = 0; j < k; ++j) G[j + 1] = G[j] + 0.5 * h * (s[j] + s[j + 1]);
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      const double x = X(i, a), u = (x - lo[a]) / h;
      if (u <= 0) {
        Y(i, a) = G[0] + s[0] * (x - lo[a]);
        continue;
      }
      const int m = std::min(static_cast<int>(u), k);
      const double d = x - (lo[a] + m * h);
      Y(i, a) = m == k ? G[k] + s[k] * d : G[m] + s[m] * d + 0.5 * (s[m + 1] - s[m]) * d * d / h;
    }
  }
  return Y;
}

double AxisWarp::length(int a) const {
  const Eigen::VectorXd& s = scales[a];
  if (s.size() == 0) return 0;
  return step[a] * (s.sum() - 0.5 * (s[0] + s[s.size() - 1]));
}

bool box_scale_of(const MatrixX3d& X, const MatrixX3d& C, Vec3& stretch, Vec3& out_lo) {
  if (X.rows() != C.rows() || X.rows() == 0) return false;
  const Vec3 xlo = X.colwise().minCoeff(), xhi = X.colwise().maxCoeff();
  const Vec3 clo = C.colwise().minCoeff(), chi = C.colwise().maxCoeff();
  const double tol = 1e-6 * std::max((xhi - xlo).norm(), (chi - clo).norm());
  for (int a = 0; a < 3; ++a) {
    const double L = xhi[a] - xlo[a];
    stretch[a] = L > tol ? (chi[a] - clo[a]) / L : 1.0;  // a flat axis: its stretch is not seen
    out_lo[a] = clo[a];
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if (std::abs(C(i, a) - (clo[a] + stretch[a] * (X(i, a) - xlo[a]))) > tol) return false;
  }
  return true;
}

namespace {

// The QP of axis_warp.h: minimize sᵀ H s + 2 gᵀ s subject to A s = b, s ≥ s_min.
struct AxisQp {
  Eigen::MatrixXd H, A;
  Eigen::VectorXd g, b;
};

// One face's terms: s(p) = B σ + c, B picking the two nodes around p on each axis (c: flat axes' λ_a).
void add_face_terms(AxisQp& qp, const AxisWarp& w, const std::array<int, 3>& offset, const std::array<int, 3>& cells,
                    const Vec3& p, const Vec3& n, double weight, double size_weight, bool in_plane, double s_bar) {
  int idx[6];
  double coef[6], c[3];
  for (int a = 0; a < 3; ++a) {
    const int nodes = cells[a] > 0 ? cells[a] + 1 : 0;
    if (nodes == 0) {
      idx[2 * a] = idx[2 * a + 1] = -1;
      coef[2 * a] = coef[2 * a + 1] = 0;
      c[a] = w.stretch[a];
      continue;
    }
    const double u = std::clamp((p[a] - w.lo[a]) / w.step[a], 0.0, static_cast<double>(nodes - 1));
    const int m = std::min(static_cast<int>(u), nodes - 2);
    idx[2 * a] = offset[a] + m, idx[2 * a + 1] = offset[a] + m + 1;
    coef[2 * a] = 1 - (u - m), coef[2 * a + 1] = u - m;
    c[a] = 0;
  }
  const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
  // The size term μ Σ_k c_k (s_k − s̄)²: c_k = P_kk = 1 − n_k², the share of axis k in the face's plane (in_plane),
  // since the scale along a face's normal does not change the face (a face across the stretch takes it for
  // free); else c_k = 1.
  Eigen::Vector3d size;
  for (int k = 0; k < 3; ++k) size[k] = size_weight * (in_plane ? std::max(P(k, k), 0.0) : 1.0);
  Eigen::Matrix3d M;  // |dev(P diag(s) P)|² = sᵀ M s, plus the size term
  for (int k = 0; k < 3; ++k)
    for (int l = 0; l < 3; ++l) M(k, l) = weight * (P(k, l) * P(k, l) - 0.5 * P(k, k) * P(l, l) + (k == l ? size[k] : 0));
  Eigen::Vector3d cs(c[0], c[1], c[2]);
  const Eigen::Vector3d lin = M * cs - weight * s_bar * size;
  for (int r = 0; r < 6; ++r) {
    if (idx[r] < 0) continue;
    qp.g[idx[r]] += coef[r] * lin[r / 2];
    for (int q = 0; q < 6; ++q)
      if (idx[q] >= 0) qp.H(idx[r], idx[q]) += coef[r] * coef[q] * M(r / 2, q / 2);
  }
}

// Primal active-set method (Nocedal & Wright, Alg. 16.3) from the feasible plain stretch, with bounds
// s_min ≤ s_i ≤ s_max,i: each step solves the equality-constrained problem on the free nodes; a blocking bound
// joins the active set, an active bound whose multiplier has the wrong sign leaves it. Strictly convex (the ε
// term), so it terminates.
Eigen::VectorXd solve_axis_qp(const AxisQp& qp, Eigen::VectorXd s, double s_min, const Eigen::VectorXd& s_max) {
  const Eigen::Index n = s.size(), rows = qp.A.rows();
  std::vector<signed char> active(n, 0);  // −1 at s_min, +1 at s_max
  for (int iter = 0; iter < 20 * n + 100; ++iter) {
    std::vector<Eigen::Index> free;
    for (Eigen::Index i = 0; i < n; ++i)
      if (!active[i]) free.push_back(i);
    const Eigen::Index nf = static_cast<Eigen::Index>(free.size());
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(nf + rows, nf + rows);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(nf + rows);
    const Eigen::VectorXd grad = qp.H * s + qp.g;
    for (Eigen::Index i = 0; i < nf; ++i) {
      for (Eigen::Index j = 0; j < nf; ++j) K(i, j) = qp.H(free[i], free[j]);
      for (Eigen::Index r = 0; r < rows; ++r) K(nf + r, i) = K(i, nf + r) = qp.A(r, free[i]);
      rhs[i] = -grad[free[i]];
    }
    const Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
    Eigen::VectorXd p = Eigen::VectorXd::Zero(n);
    for (Eigen::Index i = 0; i < nf; ++i) p[free[i]] = sol[i];
    if (p.cwiseAbs().maxCoeff() <= 1e-13 * std::max(1.0, s.cwiseAbs().maxCoeff())) {
      const Eigen::VectorXd mult = grad + qp.A.transpose() * sol.tail(rows);  // bound multipliers
      Eigen::Index leave = -1;
      double worst = 1e-14;
      for (Eigen::Index i = 0; i < n; ++i)
        if (active[i] && active[i] * mult[i] > worst) worst = active[i] * mult[i], leave = i;
      if (leave < 0) return s;
      active[leave] = 0;
      continue;
    }
    double alpha = 1;
    Eigen::Index block = -1;
    signed char side = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (active[i]) continue;
      if (p[i] < 0 && (s[i] - s_min) / -p[i] < alpha) alpha = (s[i] - s_min) / -p[i], block = i, side = -1;
      if (p[i] > 0 && (s_max[i] - s[i]) / p[i] < alpha) alpha = (s_max[i] - s[i]) / p[i], block = i, side = 1;
    }
    s += alpha * p;
    if (block >= 0) active[block] = side, s[block] = side < 0 ? s_min : s_max[block];
  }
  throw SolverError("axis warp: the active-set method did not converge");
}

// The slab term μ_s Σ_a Σ_m (w_{a,m} / L_a) r(v̄_{a,m}) (σ_{a,m} − s̄)², r(v) = v / max(1 − v, 0.01): v̄_{a,m} the
// area-weighted mean importance of the faces around node m along axis a (their centroids' hat-function shares).
// A slab resists growing by how important its surface is on average, not by how much of it there is, and one
// that holds nothing unimportant (a tentacle's far end: v̄ → 1) has no room at all (bench/resize.md, tenth session).
void add_slab_terms(AxisQp& qp, const MatrixX3d& X, const MatrixX3i& F, const Eigen::VectorXd& f, const AxisWarp& w,
                    const std::array<int, 3>& offset, const std::array<int, 3>& cells, double weight, double s_bar) {
  if (weight <= 0) return;
  const Eigen::Index n = qp.g.size();
  Eigen::VectorXd num = Eigen::VectorXd::Zero(n), den = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    const Vec3 p0 = X.row(F(k, 0)), p1 = X.row(F(k, 1)), p2 = X.row(F(k, 2)), p = (p0 + p1 + p2) / 3;
    const double area = 0.5 * (p1 - p0).cross(p2 - p0).norm(), v = (f[F(k, 0)] + f[F(k, 1)] + f[F(k, 2)]) / 3;
    for (int a = 0; a < 3; ++a) {
      if (cells[a] == 0) continue;
      const double u = std::clamp((p[a] - w.lo[a]) / w.step[a], 0.0, static_cast<double>(cells[a]));
      const int m = std::min(static_cast<int>(u), cells[a] - 1);
      for (int j : {m, m + 1}) {
        const double share = area * (j == m ? 1 - (u - m) : u - m);
        num[offset[a] + j] += share * v, den[offset[a] + j] += share;
      }
    }
  }
  for (int a = 0; a < 3; ++a)
    for (int m = 0; m <= cells[a] && cells[a] > 0; ++m) {
      const int i = offset[a] + m;
      if (!(den[i] > 0)) continue;
      const double v = num[i] / den[i];
      const double c = weight * (m == 0 || m == cells[a] ? 0.5 : 1.0) / cells[a] * v / std::max(1 - v, 0.01);
      qp.H(i, i) += c, qp.g[i] -= c * s_bar;
    }
}

}  // namespace

AxisWarp axis_warp(const Mesh& mesh, const Vec3& stretch, const Vec3& out_lo, const Eigen::VectorXd& f,
                   const AxisWarpOptions& o) {
  check_options(o);
  const MatrixX3d X = positions(mesh);
  const MatrixX3i F = faces(mesh);
  if (f.size() != X.rows()) throw InvalidInput(fmt::format("axis warp: {} weights for {} vertices", f.size(), X.rows()));
  if (X.rows() == 0) throw InvalidInput("axis warp: an empty mesh");
  if ((stretch.array() <= 0).any() || !stretch.allFinite()) throw InvalidInput("axis warp: the stretch must be positive");
  const Vec3 lo = X.colwise().minCoeff(), ext = Vec3(X.colwise().maxCoeff()) - lo;
  const double diag = ext.norm(), cell = diag / o.cells;
  AxisWarp w;
  std::array<int, 3> offset{}, cells{};
  int n = 0;
  double s_bar = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    w.lo[a] = lo[a], w.out_lo[a] = out_lo[a], w.stretch[a] = stretch[a];
    const bool flat = !(ext[a] > 1e-9 * diag);
    cells[a] = flat ? 0 : std::max(1, static_cast<int>(std::ceil(ext[a] / cell - 1e-9)));
    w.step[a] = flat ? 1.0 : ext[a] / cells[a];
    offset[a] = n;
    n += flat ? 0 : cells[a] + 1;
    if (!flat) s_bar = std::min(s_bar, stretch[a]);
  }
  if (n == 0) return w;  // a point: nothing to warp
  AxisQp qp;
  qp.H = Eigen::MatrixXd::Zero(n, n), qp.g = Eigen::VectorXd::Zero(n);
  double total = 0;
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    const Vec3 p0 = X.row(F(k, 0)), p1 = X.row(F(k, 1)), p2 = X.row(F(k, 2));
    const Vec3 nrm = (p1 - p0).cross(p2 - p0);
    const double weight = 0.5 * nrm.norm() * (f[F(k, 0)] + f[F(k, 1)] + f[F(k, 2)]) / 3;
    if (!(weight > 0)) continue;
    add_face_terms(qp, w, offset, cells, (p0 + p1 + p2) / 3, nrm.normalized(), weight, o.size_weight, o.in_plane_size,
                   s_bar);
    total += weight;
  }
  if (total > 0) qp.H /= total, qp.g /= total;
  add_slab_terms(qp, X, F, f, w, offset, cells, o.slab_weight, s_bar);
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
    if (cells[a] > 0) axes.push_back(a);
  qp.A = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(axes.size()), n);
  qp.b.resize(qp.A.rows());
  Eigen::VectorXd start(n), s_max(n);
  for (std::size_t r = 0; r < axes.size(); ++r) {
    const int a = axes[r], k = cells[a];
    for (int m = 0; m <= k; ++m) {
      const int i = offset[a] + m;
      s_max[i] = o.max_scale > 0 ? std::max(o.max_scale, 1.0) * stretch[a] : std::numeric_limits<double>::infinity();
      const double wm = (m == 0 || m == k ? 0.5 : 1.0) / k;  // trapezoid weights over L_a
      qp.A(r, i) = wm;
      qp.H(i, i) += o.plain_weight * wm;
      qp.g[i] -= o.plain_weight * wm * stretch[a];
      start[i] = stretch[a];
    }
    qp.b[r] = stretch[a];
  }
  // λ K_a (σ_{m+1} − σ_m)², λ per interval: raised tenfold over the intervals a face spans when the warp turns
  // it (near) against the plain stretch (a skinny face across cells of different slope; the beetle's), until none does.
  Eigen::VectorXd smooth = Eigen::VectorXd::Constant(n, o.smoothness);  // interval (i, i + 1) of its axis
  const MatrixX3d plain_normals = [&] {
    MatrixX3d N(F.rows(), 3);
    for (Eigen::Index k = 0; k < F.rows(); ++k) {
      const Vec3 p0 = X.row(F(k, 0)), e1 = Vec3(X.row(F(k, 1))) - p0, e2 = Vec3(X.row(F(k, 2))) - p0;
      N.row(k) = e1.cwiseProduct(stretch).cross(e2.cwiseProduct(stretch)).transpose();
    }
    return N;
  }();
  constexpr int kGuardRounds = 8;
  // A face counts as turned from 80° to the plain stretch's normal, not 90°: the similarity stage cannot undo a
  // face the warp left near 90° (the beetle ×2 z under the outline term: 85° in the warp, 98° after the stage,
  // bench/resize.md, twelfth session).
  const double kGuardCos = std::cos(80.0 * M_PI / 180.0);
  for (int round = 0;; ++round) {
    AxisQp q = qp;
    for (int a : axes)
      for (int m = 0; m < cells[a]; ++m) {
        const int i = offset[a] + m;
        const double c = smooth[i] * cells[a];
        q.H(i, i) += c, q.H(i + 1, i + 1) += c, q.H(i, i + 1) -= c, q.H(i + 1, i) -= c;
      }
    const Eigen::VectorXd s = solve_axis_qp(q, start, o.min_scale * s_bar, s_max);
    for (int a : axes) {
      w.scales[a] = s.segment(offset[a], cells[a] + 1);
      w.scales[a] *= stretch[a] * ext[a] / w.length(a);  // the box exact up to rounding
    }
    if (round == kGuardRounds) break;
    const MatrixX3d Y = w.apply(X);
    std::vector<char> raise(static_cast<std::size_t>(n), 0);
    bool turned = false;
    for (Eigen::Index k = 0; k < F.rows(); ++k) {
      const Vec3 p0 = Y.row(F(k, 0)), e1 = Vec3(Y.row(F(k, 1))) - p0, e2 = Vec3(Y.row(F(k, 2))) - p0;
      const Vec3 nk = e1.cross(e2), pk = plain_normals.row(k).transpose();
      if (!(nk.dot(pk) < kGuardCos * nk.norm() * pk.norm())) continue;
      turned = true;
      for (int a : axes) {  // the intervals the face spans, and one more on each side
        double x0 = X(F(k, 0), a), x1 = x0;
        for (int j = 1; j < 3; ++j) x0 = std::min(x0, X(F(k, j), a)), x1 = std::max(x1, X(F(k, j), a));
        const int m0 = std::max(0, static_cast<int>((x0 - w.lo[a]) / w.step[a]) - 1);
        const int m1 = std::min(cells[a] - 1, static_cast<int>((x1 - w.lo[a]) / w.step[a]) + 1);
        for (int m = m0; m <= m1; ++m) raise[offset[a] + m] = 1;
      }
    }
    if (!turned) break;
    for (int i = 0; i < n; ++i)
      if (raise[i]) smooth[i] = std::max(10 * smooth[i], 1e-6);
  }
  return w;
}

}  // namespace geotex
