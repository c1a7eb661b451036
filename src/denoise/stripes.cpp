// Scanner stripes along one world axis: the axis fitted in 3D from the residual's gradients, refined to the
// direction along which one sinusoid explains most of the residual (issue 24, fifteenth session).
#include "stripes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace geotex::detail {
namespace {

// The periods tried, in mean edge lengths: 3 (a band of 1.5 edges, the shortest a 1-ring median leaves) to 32
// (longer waves are shape to the sharp fit, which keeps them), log-spaced.
constexpr double kShortestPeriod = 3, kLongestPeriod = 32;
constexpr int kPeriods = 110;
// Bins of half an edge along the axis: 6 per period at the shortest.
constexpr double kBinsPerEdge = 2;
// The refinement's eight neighbouring directions, in the plane orthogonal to the axis.
constexpr std::array<std::pair<int, int>, 8> kNeighbours{
    {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}}};

// The axis a minimising Σ w (a·(g × n))² against its white-noise expectation Σ w |g|² (1 − (a·n)²) / 2.
Vec3 gradient_axis(const MatrixX3d& Xs, const MatrixX3i& F, const std::vector<int>& faces, const Eigen::VectorXd& r) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero(), W = Eigen::Matrix3d::Zero();
  for (int f : faces) {
    const Vec3 a = Xs.row(F(f, 0)), b = Xs.row(F(f, 1)), c = Xs.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    const double n2 = n.squaredNorm();
    if (!(n2 > 0)) continue;
    // The gradient of the linear interpolant of r over the face, its unit normal, its area.
    const Vec3 g = (n.cross(c - b) * r[F(f, 0)] + n.cross(a - c) * r[F(f, 1)] + n.cross(b - a) * r[F(f, 2)]) / n2;
    const double len = std::sqrt(n2), area = 0.5 * len;
    const Vec3 u = n / len, m = g.cross(u);
    M += area * m * m.transpose();
    W += area * 0.5 * g.squaredNorm() * (Eigen::Matrix3d::Identity() - u * u.transpose());
  }
  // W^(-1/2), pseudo-inverse: a flat part leaves its normal's direction unobserved.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ew(W);
  const double top = ew.eigenvalues().maxCoeff();
  if (!(top > 0)) return Vec3::UnitZ();
  Eigen::Vector3d inv = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (ew.eigenvalues()[k] > 1e-9 * top) inv[k] = 1 / std::sqrt(ew.eigenvalues()[k]);
  const Eigen::Matrix3d Wih = ew.eigenvectors() * inv.asDiagonal() * ew.eigenvectors().transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> em(Wih * M * Wih);
  // The smallest eigenvector within W's range (a zero column of Wih reads 0 there too: skip it).
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis = Wih * em.eigenvectors().col(k);
    if (axis.norm() > 1e-12) return axis.normalized();
  }
  return Vec3::UnitZ();
}

// The share of r's variance over \p verts that one sinusoid along \p axis explains, at the best period.
std::pair<double, double> sinusoid_share(const MatrixX3d& X, const std::vector<int>& verts, const Eigen::VectorXd& r,
                                         double h, const Vec3& axis) {
  double lo = std::numeric_limits<double>::max(), hi = -lo, mean = 0;
  for (int v : verts) {
    const double t = X.row(v).dot(axis) / h;
    lo = std::min(lo, t), hi = std::max(hi, t), mean += r[v];
  }
  mean /= static_cast<double>(verts.size());
  const int bins = static_cast<int>(std::floor((hi - lo) * kBinsPerEdge)) + 1;
  std::vector<double> count(bins, 0), sum(bins, 0);
  double total = 0;
  for (int v : verts) {
    const int b = std::min(bins - 1, static_cast<int>(std::floor((X.row(v).dot(axis) / h - lo) * kBinsPerEdge)));
    count[b] += 1, sum[b] += r[v] - mean, total += (r[v] - mean) * (r[v] - mean);
  }
  if (!(total > 0)) return {0, 0};
  double best = 0, best_period = 0;
  for (int p = 0; p < kPeriods; ++p) {
    const double period = kShortestPeriod * std::pow(kLongestPeriod / kShortestPeriod, p / (kPeriods - 1.0));
    const double k = 2 * M_PI / period;
    // Weighted least squares of the bins' sums on cos, sin and a constant (the counts the weights).
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (int b = 0; b < bins; ++b) {
      if (count[b] == 0) continue;
      const double tc = (b + 0.5) / kBinsPerEdge;
      const Eigen::Vector3d q(std::cos(k * tc), std::sin(k * tc), 1);
      G += count[b] * q * q.transpose(), y += sum[b] * q;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(G);
    if (ldlt.info() != Eigen::Success) continue;
    const double explained = ldlt.solve(y).dot(y) / total;
    if (explained > best) best = explained, best_period = period;
  }
  return {best, best_period};
}

}  // namespace

StripeFit fit_stripes(const MatrixX3d& X, const MatrixX3d& Xs, const MatrixX3i& F, const std::vector<int>& faces,
                      const std::vector<int>& verts, const Eigen::VectorXd& r, double h) {
  StripeFit fit;
  if (faces.size() < 3 || verts.size() < 3 || !(h > 0)) return fit;
  fit.axis = gradient_axis(Xs, F, faces, r);
  std::tie(fit.share, fit.period) = sinusoid_share(X, verts, r, h, fit.axis);
  // The fitted axis is off by a few degrees where shape enters the residual (the cylinder's facets); over a part
  // tens of edges long that dephases the bands, so the share is refined over directions, coarse to fine.
  for (const double step : {0.15, 0.05, 0.015, 0.005}) {
    for (bool improved = true; improved;) {
      improved = false;
      const Vec3 u = fit.axis.unitOrthogonal(), w = fit.axis.cross(u);
      for (const auto& [du, dw] : kNeighbours) {
        const Vec3 axis = (fit.axis + step * (du * u + dw * w)).normalized();
        const auto [share, period] = sinusoid_share(X, verts, r, h, axis);
        if (share > fit.share + 1e-9) fit = {axis, period, share}, improved = true;
      }
    }
  }
  return fit;
}

}  // namespace geotex::detail
