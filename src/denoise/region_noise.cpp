// The noise level per region (region_noise.h).

#include "region_noise.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/geometry.h"

namespace geotex::detail {

namespace {
// A region: the sampled vertices nearest a sample (breadth-first), about the three-ring (37 vertices at valence 6)
// where every vertex is sampled. Its better-fitting half, 18 residuals, reads the level within about 17 %.
constexpr size_t kRegionSamples = 36;
constexpr size_t kRegionVisits = 4000;  // a region stops growing here (a strided sample of a huge mesh)
// estimate_noise()'s statistic: outliers beyond 4 robust standard deviations (the lower quartile of |r|).
constexpr double kRegionOutlier = 4, kLowerQuartileOfNormal = 0.31863936396437515;
// A region reads noisier than the mesh above this multiple of the whole's level (white noise: the region's
// better-fitting half, 18 residuals, reads the level within about 17 %). Quieter regions are measured against the
// mesh's level all the same: keeping less of the change where a region read below a third of the whole cost the
// cylinder and the sphere under oblique depth noise 0.3-1.5 % (bench/denoise.md, fifteenth session).
constexpr double kNoisierRegion = 2.0;
// running_level(): a mesh whose level keeps less than kNoiseFree of the change (auto_denoise() returns it as it is),
// with at least kNoisyShare of the vertices above keep_below by their regions. Raised wherever the mesh's level keeps
// less than half, it also took low-frequency noise (the estimate follows the field) away from the low-frequency rule:
// the cylinder under a field over 4 edges 15.73° -> 18.48° (fandisk and spot under a field over 8 edges -5 %;
// bench/denoise.md, fifteenth session).
constexpr double kNoiseFree = 1e-6, kNoisyShare = 0.1;

// The mean square of the better-fitting half of \p fits (ring fit, residual) without outliers, as estimate_noise().
double region_level(std::vector<std::pair<double, double>>& fits) {
  const size_t keep = std::max<size_t>(1, fits.size() / 2);
  std::nth_element(fits.begin(), fits.begin() + (keep - 1), fits.end());
  std::vector<double> r(keep);
  for (size_t i = 0; i < keep; ++i) r[i] = fits[i].second;
  const size_t q = (r.size() - 1) / 4;
  std::nth_element(r.begin(), r.begin() + q, r.end());
  const double cut = kRegionOutlier * r[q] / kLowerQuartileOfNormal;
  double sum2 = 0;
  size_t kept = 0;
  for (double x : r)
    if (x <= cut) sum2 += x * x, ++kept;
  return kept > 0 ? std::sqrt(sum2 / double(kept)) : 0.0;
}
}  // namespace

RegionNoise region_noise(const Neighborhoods& N, const NoiseReading& reading) {
  const int nv = static_cast<int>(N.size());
  const NoiseEstimate& global = reading.estimate;
  RegionNoise out;
  out.level = Eigen::VectorXd::Zero(nv);
  Eigen::VectorXd& level = out.level;
  if (nv == 0 || !(global.mean_edge > 0) || !(global.clean_edge > 0)) return out;
  // estimate_noise()'s samples and their two-ring fits, by vertex.
  const std::vector<int>& samples = reading.samples;
  std::vector<std::pair<double, double>> fit(nv, {-1.0, -1.0});  // (ring fit, residual) at the samples
  for (size_t s = 0; s < samples.size(); ++s) fit[samples[s]] = reading.fits[s];
  // Each sample's region, breadth-first.
  std::vector<char> has(nv, 0);
  const double unit = global.mean_edge / global.clean_edge;
  out.whole = reading.rms * unit;  // region_level() over all the samples: estimate_noise()'s reduction
#pragma omp parallel if (samples.size() > 2000)
  {
    std::vector<int> mark(nv, -1), queue;
    std::vector<std::pair<double, double>> near;
#pragma omp for schedule(dynamic, 64)
    for (size_t s = 0; s < samples.size(); ++s) {
      const int tag = static_cast<int>(s);
      queue.assign(1, samples[s]);
      mark[samples[s]] = tag;
      near.clear();
      for (size_t head = 0; head < queue.size() && near.size() < kRegionSamples && queue.size() < kRegionVisits; ++head) {
        const int u = queue[head];
        if (fit[u].second >= 0) near.push_back(fit[u]);
        for (int k = N.offsets[u]; k < N.offsets[u + 1]; ++k)
          if (const int w = N.indices[k]; mark[w] != tag) mark[w] = tag, queue.push_back(w);
      }
      if (near.size() >= 4) level[samples[s]] = region_level(near) * unit, has[samples[s]] = 1;
    }
  }
  // Every other vertex: its nearest sample's level (breadth-first from all samples at once).
  std::vector<int> front;
  for (int v = 0; v < nv; ++v)
    if (has[v]) front.push_back(v);
  for (size_t head = 0; head < front.size(); ++head) {
    const int u = front[head];
    for (int k = N.offsets[u]; k < N.offsets[u + 1]; ++k)
      if (const int w = N.indices[k]; !has[w]) has[w] = 1, level[w] = level[u], front.push_back(w);
  }
  return out;
}

Eigen::VectorXd region_levels(const RegionNoise& map, const NoiseEstimate& noise, double normal_noise) {
  const Eigen::Index n = map.level.size();
  Eigen::VectorXd out = Eigen::VectorXd::Constant(n, normal_noise);
  // rms_normal_sigma over normal_sigma: impulses included, as normal_noise; 1 where the estimate read none.
  const double c = noise.normal_sigma > 0 ? noise.rms_normal_sigma / noise.normal_sigma : 1.0;
  // Where the mesh's residual was read partly as a coarse model's facets (noise_share < 1, misfit_growth.h), a
  // region's excess is read the same: a coarse model's misfit is not even over it (the ears and limbs coarser), and
  // read whole it ran a mesh read noise-free at its coarsest regions' misfit (cheburashka decimated to 1500
  // vertices at σ 0.02: share 0, 1.8 times the noisy input's error; bench/denoise.md, sixteenth session).
  const double whole = map.whole, x1 = kNoisierRegion, share = std::clamp(noise.noise_share, 0.0, 1.0);
  for (Eigen::Index v = 0; v < n; ++v)
    if (const double m = map.level[v]; m > x1 * whole)
      out[v] = std::max(normal_noise, share * c * (m - (x1 - 1) * whole));
  return out;
}

double running_level(const Eigen::VectorXd& levels, double normal_noise, double keep_below) {
  if (std::pow(normal_noise / keep_below, 4) >= kNoiseFree || levels.size() == 0) return normal_noise;  // not noise-free
  std::vector<double> above;
  for (Eigen::Index v = 0; v < levels.size(); ++v)
    if (levels[v] >= keep_below) above.push_back(levels[v]);
  if (double(above.size()) < kNoisyShare * double(levels.size())) return normal_noise;
  const auto mid = above.begin() + static_cast<std::ptrdiff_t>(above.size() / 2);
  std::nth_element(above.begin(), mid, above.end());
  return *mid;
}

std::string describe_region_noise(const Eigen::VectorXd& map, double global) {
  if (map.size() == 0) return "noise per region: none read";
  std::vector<double> x(map.data(), map.data() + map.size());
  std::sort(x.begin(), x.end());
  auto quantile = [&](double q) { return x[static_cast<size_t>(q * double(x.size() - 1))]; };
  double low = 0, high = 0;
  for (double v : x) low += v < global / 3, high += v > 2 * global;
  return fmt::format("noise per region (normal sigma over about three rings): 10/50/90% quantiles {:.3f} / {:.3f} / "
                     "{:.3f}; {:.0f}% of the vertices below a third of the mesh's {:.3f}, {:.0f}% above twice it",
                     quantile(0.1), quantile(0.5), quantile(0.9), 100 * low / double(x.size()), global,
                     100 * high / double(x.size()));
}

}  // namespace geotex::detail
