// Noise level of a mesh from leave-one-out local fits (auto_denoise.h).

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/auto_denoise.h"
#include "misfit_growth.h"

namespace geotex {

namespace {
constexpr int kTerms = 10;      // a cubic height function: curvature and its change fit, the noise does not
constexpr double kKeep = 0.5;   // the half of the vertices whose two-ring fits best
constexpr double kOutlier = 4;  // residuals beyond 4 robust standard deviations are outliers
constexpr size_t kMaxRing = 200;
constexpr std::pair<double, double> kNoFit{-1.0, -1.0};

// The leave-one-out fit at \p vh: a cubic height function over the tangent plane fitted to the vertex's
// two-ring (without the vertex; lengths in \p h). \return (the vertex's residual over the fit's own error,
// the ring's residual variance), or kNoFit for a ring too small, too large or degenerate. \p mark, \p ring
// and \p P are the calling thread's buffers (mark[u] == tag: u is in this ring already).
std::pair<double, double> two_ring_fit(const Mesh& mesh, Mesh::VertexHandle vh, int tag, double h,
                                       std::vector<int>& mark, std::vector<int>& ring, std::vector<Vec3>& P) {
  // The two-ring of the vertex, without the vertex; at most kMaxRing points (a vertex of very high
  // valence has no local two-ring to fit, and is skipped).
  ring.clear();
  mark[vh.idx()] = tag;
  for (auto u : mesh.vv_range(vh)) {
    ring.push_back(u.idx());
    mark[u.idx()] = tag;
  }
  const size_t one = ring.size();
  bool too_large = one > kMaxRing;
  for (size_t k = 0; k < one && !too_large; ++k)
    for (auto u : mesh.vv_range(mesh.vertex_handle(ring[k]))) {
      if (mark[u.idx()] == tag) continue;
      mark[u.idx()] = tag;
      ring.push_back(u.idx());
      if (ring.size() > kMaxRing) {
        too_large = true;
        break;
      }
    }
  if (too_large || ring.size() < kTerms + 4) return kNoFit;
  P.clear();
  Vec3 c = Vec3::Zero();
  for (int u : ring) {
    P.push_back(to_eigen(mesh.point(mesh.vertex_handle(u))));
    c += P.back();
  }
  c /= double(P.size());
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Vec3& p : P) C += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(C);
  const Vec3 t1 = es.eigenvectors().col(2), t2 = es.eigenvectors().col(1), n = es.eigenvectors().col(0);
  // A cubic height function z(x, y) over the tangent plane, fitted to the ring (in mean edge lengths).
  auto basis = [&](const Vec3& p) {
    const Vec3 q = (p - c) / h;
    const double x = q.dot(t1), y = q.dot(t2);
    Eigen::Matrix<double, kTerms, 1> b;
    b << x * x * x, x * x * y, x * y * y, y * y * y, x * x, x * y, y * y, x, y, 1.0;
    return std::pair(b, q.dot(n));
  };
  Eigen::Matrix<double, kTerms, kTerms> A = Eigen::Matrix<double, kTerms, kTerms>::Zero();
  Eigen::Matrix<double, kTerms, 1> rhs = Eigen::Matrix<double, kTerms, 1>::Zero();
  for (const Vec3& p : P) {
    const auto [b, z] = basis(p);
    A.noalias() += b * b.transpose();
    rhs += z * b;
  }
  const Eigen::LDLT<Eigen::Matrix<double, kTerms, kTerms>> ldlt(A);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-10)) return kNoFit;
  const auto [b0, z0] = basis(to_eigen(mesh.point(vh)));
  const Eigen::Matrix<double, kTerms, 1> beta = ldlt.solve(rhs);
  const double predicted = b0.dot(beta);
  double rss = 0;
  for (const Vec3& p : P) {
    const auto [b, z] = basis(p);
    rss += (z - b.dot(beta)) * (z - b.dot(beta));
  }
  // Var(z0 − predicted) = σ² (1 + b0ᵀ A⁻¹ b0): the fit's own error adds to the vertex's.
  const double leverage = b0.dot(ldlt.solve(b0));
  return {std::abs(z0 - predicted) / std::sqrt(1.0 + leverage), rss / double(P.size() - kTerms)};
}

}  // namespace

NoiseEstimate estimate_noise(const Mesh& mesh, int max_samples) {
  require_valid(mesh, "noise estimate input");
  NoiseEstimate out;
  out.mean_edge = mean_edge_length(mesh);
  if (!(out.mean_edge > 0)) throw InvalidInput("noise estimate: zero mean edge length");
  const int nv = static_cast<int>(mesh.n_vertices());
  const int stride = std::max(1, nv / std::max(1, max_samples));
  std::vector<int> samples;
  for (int v = 0; v < nv; v += stride)
    if (!mesh.is_boundary(mesh.vertex_handle(v)) && !mesh.is_isolated(mesh.vertex_handle(v))) samples.push_back(v);
  std::vector<double> residual(samples.size(), -1.0), ring_rss(samples.size(), -1.0);
#pragma omp parallel if (samples.size() > 2000)
  {
    std::vector<int> ring, mark(nv, -1);  // mark[u] == s: u is already in sample s's ring
    std::vector<Vec3> P;
#pragma omp for schedule(dynamic, 64)
    for (size_t s = 0; s < samples.size(); ++s) {
      const auto [res, rss] = two_ring_fit(mesh, mesh.vertex_handle(samples[s]), static_cast<int>(s), out.mean_edge,
                                           mark, ring, P);
      residual[s] = res;
      ring_rss[s] = rss;
    }
  }
  // Keep the vertices whose ring the surface fits best (creases and rough detail fit badly). In a least-
  // squares fit the residuals are independent of the prediction, so choosing by the ring's fit does not
  // bias the vertex's own residual.
  std::vector<std::pair<double, double>> fits;  // (ring fit, vertex residual)
  for (size_t s = 0; s < samples.size(); ++s)
    if (residual[s] >= 0) fits.emplace_back(ring_rss[s], residual[s]);
  if (fits.empty()) throw InvalidInput("noise estimate: no interior vertex with a large enough two-ring");
  const size_t keep = std::max<size_t>(1, static_cast<size_t>(kKeep * fits.size()));
  std::nth_element(fits.begin(), fits.begin() + (keep - 1), fits.end());
  fits.resize(keep);
  // The mean square of the residuals (whatever the shape of the noise's distribution: isotropic noise has
  // a normal component N(0, s²)·cos θ, more peaked than a Gaussian), without outliers beyond kOutlier
  // times a robust scale (the lower quartile of |r| over its value for a standard normal).
  residual.clear();
  for (const auto& f : fits) residual.push_back(f.second);
  constexpr double kQuantile = 0.25, kStandardQuantile = 0.31863936396437515;  // Φ⁻¹((1 + 0.25) / 2)
  const size_t q = static_cast<size_t>(kQuantile * (residual.size() - 1));
  std::nth_element(residual.begin(), residual.begin() + q, residual.end());
  const double cut = kOutlier * residual[q] / kStandardQuantile;
  double sum2 = 0, all2 = 0;
  size_t kept = 0;
  for (double r : residual) {
    all2 += r * r;
    if (r <= cut) {
      sum2 += r * r;
      ++kept;
    }
  }
  const double normal_abs = std::sqrt(sum2 / double(kept)) * out.mean_edge;
  // Noise lengthens edges: E|e_noisy|² = E|e|² + 2 s² for a displacement of variance s² per vertex
  // (s² = 3 σ⊥² for isotropic noise). The clean mean edge length is the unit of the estimate (as in
  // geotex noise); the correction is bounded, so that it never more than halves the unit.
  double rms2 = 0;
  for (auto e : mesh.edges()) rms2 += mesh.calc_edge_sqr_length(e);
  rms2 /= double(mesh.n_edges());
  const double shrink = std::sqrt(std::max(0.25, 1.0 - 2.0 * 3.0 * normal_abs * normal_abs / rms2));
  out.clean_edge = out.mean_edge * shrink;
  out.normal_sigma = normal_abs / out.clean_edge;
  out.sigma = std::sqrt(3.0) * out.normal_sigma;
  out.samples = static_cast<int>(residual.size());
  out.outliers = 1.0 - double(kept) / double(residual.size());
  out.rms_normal_sigma = std::sqrt(all2 / double(residual.size())) * out.mean_edge / out.clean_edge;
  // A coarse model's facets are not noise: the share of the residual that is (misfit_growth.h).
  out.misfit_growth = detail::misfit_growth(mesh, samples, out.mean_edge, residual);
  out.noise_share = detail::noise_share_of_residual(out.misfit_growth, out.sigma, out.outliers);
  out.normal_sigma *= out.noise_share, out.sigma *= out.noise_share, out.rms_normal_sigma *= out.noise_share;
  return out;
}

}  // namespace geotex
