// A leave-one-out height-function fit over a vertex's rings: estimate_noise()'s cubic over the two-ring
// (noise_estimate.cpp) and misfit_growth()'s quartic over the three-ring (misfit_growth.cpp) share it.
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "geotex/core/geometry.h"
#include "geotex/core/mesh.h"

namespace geotex::detail {

//! The monomials of a height function z(x, y) up to degree 3 (\p Terms 10) or 4 (15), highest degree first.
template <int Terms>
Eigen::Matrix<double, Terms, 1> height_monomials(double x, double y) {
  static_assert(Terms == 10 || Terms == 15, "a cubic or a quartic");
  Eigen::Matrix<double, Terms, 1> b;
  if constexpr (Terms == 15)
    b << x * x * x * x, x * x * x * y, x * x * y * y, x * y * y * y, y * y * y * y, x * x * x, x * x * y, x * y * y,
        y * y * y, x * x, x * y, y * y, x, y, 1.0;
  else
    b << x * x * x, x * x * y, x * y * y, y * y * y, x * x, x * y, y * y, x, y, 1.0;
  return b;
}

//! Which rings a fit covers and when it gives up.
struct RingFitLimits {
  int rings = 2;             //!< the vertex's k-ring
  size_t max_points = 200;   //!< more points than this (a vertex of very high valence): no local ring, no fit
  double min_rcond = 1e-10;  //!< a normal matrix at or below this reciprocal condition: degenerate, no fit
};

//! The leave-one-out fit at \p vh: a height function of \p Terms monomials over the tangent plane (the ring's
//! principal axes) fitted to the vertex's ring without the vertex, lengths in \p h. \return (the vertex's residual
//! over the fit's own error, the ring's residual variance), or (-1, -1) for a ring of fewer than Terms + 4 points,
//! of more than \p lim.max_points, or degenerate. \p mark, \p ring and \p P are the calling thread's buffers
//! (mark[u] == tag: u is in this ring already).
template <int Terms>
std::pair<double, double> leave_one_out_fit(const Mesh& mesh, Mesh::VertexHandle vh, double h, const RingFitLimits& lim,
                                            int tag, std::vector<int>& mark, std::vector<int>& ring,
                                            std::vector<Vec3>& P) {
  constexpr std::pair<double, double> kNoFit{-1.0, -1.0};
  ring.assign(1, vh.idx());
  mark[vh.idx()] = tag;
  size_t begin = 0;
  for (int k = 0; k < lim.rings; ++k) {
    const size_t end = ring.size();
    for (size_t i = begin; i < end; ++i)
      for (auto u : mesh.vv_range(mesh.vertex_handle(ring[i])))
        if (mark[u.idx()] != tag) {
          mark[u.idx()] = tag;
          ring.push_back(u.idx());
          if (ring.size() > lim.max_points + 1) return kNoFit;
        }
    begin = end;
  }
  if (ring.size() < Terms + 5) return kNoFit;  // Terms + 4 points besides the vertex
  P.clear();
  Vec3 c = Vec3::Zero();
  for (size_t i = 1; i < ring.size(); ++i) {
    P.push_back(to_eigen(mesh.point(mesh.vertex_handle(ring[i]))));
    c += P.back();
  }
  c /= double(P.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Vec3& p : P) C += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(C);
  const Vec3 t1 = es.eigenvectors().col(2), t2 = es.eigenvectors().col(1), n = es.eigenvectors().col(0);
  auto basis = [&](const Vec3& p) {
    const Vec3 q = (p - c) / h;
    return std::pair(height_monomials<Terms>(q.dot(t1), q.dot(t2)), q.dot(n));
  };
  Eigen::Matrix<double, Terms, Terms> A = Eigen::Matrix<double, Terms, Terms>::Zero();
  Eigen::Matrix<double, Terms, 1> rhs = Eigen::Matrix<double, Terms, 1>::Zero();
  for (const Vec3& p : P) {
    const auto [b, z] = basis(p);
    A.noalias() += b * b.transpose();
    rhs += z * b;
  }
  const Eigen::LDLT<Eigen::Matrix<double, Terms, Terms>> ldlt(A);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > lim.min_rcond)) return kNoFit;
  const Eigen::Matrix<double, Terms, 1> beta = ldlt.solve(rhs);
  double rss = 0;
  for (const Vec3& p : P) {
    const auto [b, z] = basis(p);
    rss += (z - b.dot(beta)) * (z - b.dot(beta));
  }
  // Var(z0 − predicted) = σ² (1 + b0ᵀ A⁻¹ b0): the fit's own error adds to the vertex's.
  const auto [b0, z0] = basis(to_eigen(mesh.point(vh)));
  const double leverage = b0.dot(ldlt.solve(b0));
  return {std::abs(z0 - b0.dot(beta)) / std::sqrt(1.0 + leverage), rss / double(P.size() - Terms)};
}

}  // namespace geotex::detail
