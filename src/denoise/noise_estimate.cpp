// Noise level of a mesh from leave-one-out local fits (auto_denoise.h).

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/auto_denoise.h"
#include "misfit_growth.h"
#include "noise_estimate.h"
#include "ring_fit.h"

namespace geotex {

namespace {
constexpr int kCubicTerms = 10;  // a cubic height function: curvature and its change fit, the noise does not
constexpr double kKeep = 0.5;    // the half of the vertices whose two-ring fits best
constexpr double kOutlier = 4;   // residuals beyond 4 robust standard deviations are outliers
// A cubic over the two-ring, at most 200 points (a vertex of very high valence has no local two-ring to fit).
constexpr detail::RingFitLimits kTwoRing{2, 200, 1e-10};
}  // namespace

namespace detail {

NoiseReading read_noise(const Mesh& mesh, int max_samples) {
  require_valid(mesh, "noise estimate input");
  NoiseReading reading;
  NoiseEstimate& out = reading.estimate;
  out.mean_edge = mean_edge_length(mesh);
  if (!(out.mean_edge > 0)) throw InvalidInput("noise estimate: zero mean edge length");
  const int nv = static_cast<int>(mesh.n_vertices());
  const int stride = std::max(1, nv / std::max(1, max_samples));
  std::vector<int>& samples = reading.samples;
  for (int v = 0; v < nv; v += stride)
    if (!mesh.is_boundary(mesh.vertex_handle(v)) && !mesh.is_isolated(mesh.vertex_handle(v))) samples.push_back(v);
  reading.fits.assign(samples.size(), {-1.0, -1.0});
#pragma omp parallel if (samples.size() > 2000)
  {
    std::vector<int> ring, mark(nv, -1);  // mark[u] == s: u is already in sample s's ring
    std::vector<Vec3> P;
#pragma omp for schedule(dynamic, 64)
    for (size_t s = 0; s < samples.size(); ++s) {
      const auto [res, rss] = leave_one_out_fit<kCubicTerms>(mesh, mesh.vertex_handle(samples[s]), out.mean_edge,
                                                             kTwoRing, static_cast<int>(s), mark, ring, P);
      reading.fits[s] = {rss, res};
    }
  }
  // Keep the vertices whose ring the surface fits best (creases and rough detail fit badly). In a least-
  // squares fit the residuals are independent of the prediction, so choosing by the ring's fit does not
  // bias the vertex's own residual.
  std::vector<std::pair<double, double>> fits;  // (ring fit, vertex residual)
  for (const auto& f : reading.fits)
    if (f.second >= 0) fits.push_back(f);
  if (fits.empty()) throw InvalidInput("noise estimate: no interior vertex with a large enough two-ring");
  const size_t keep = std::max<size_t>(1, static_cast<size_t>(kKeep * fits.size()));
  std::nth_element(fits.begin(), fits.begin() + (keep - 1), fits.end());
  fits.resize(keep);
  // The mean square of the residuals (whatever the shape of the noise's distribution: isotropic noise has
  // a normal component N(0, s²)·cos θ, more peaked than a Gaussian), without outliers beyond kOutlier
  // times a robust scale (the lower quartile of |r| over its value for a standard normal).
  std::vector<double> residual;
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
  reading.rms = std::sqrt(sum2 / double(kept));
  const double normal_abs = reading.rms * out.mean_edge;
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
  out.misfit_growth = misfit_growth(mesh, samples, out.mean_edge, residual);
  out.noise_share = noise_share_of_residual(out.misfit_growth, out.sigma, out.outliers);
  out.normal_sigma *= out.noise_share, out.sigma *= out.noise_share, out.rms_normal_sigma *= out.noise_share;
  return reading;
}

}  // namespace detail

NoiseEstimate estimate_noise(const Mesh& mesh, int max_samples) {
  return detail::read_noise(mesh, max_samples).estimate;
}

}  // namespace geotex
