// Noise levels that differ region to region (mixed_levels.h).

#include "mixed_levels.h"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

namespace geotex::detail {

namespace {
// The map averaged with the one-ring this many times: about three rings more than region_noise()'s own.
constexpr int kSmoothingRounds = 3;
// Regions that differ over a part, not in specks: the spread after kWideRounds more rounds at least kWideShare of it.
// Impulses (10 % of the vertices) make specks that read up to 1000x the quiet regions between them on woody, 3-28x
// on fandisk, spot, cheburashka, the teapot, which 20 rounds bring down to 0.03-0.77 of the spread; regions of
// different noise keep 0.84-0.87 (fandisk, the cow). Measured on woody with impulses, the levels of the specks cost
// 0.28 -> 3.32 deg (bench/denoise.md, sixteenth session).
constexpr int kWideRounds = 17;
constexpr double kWideShare = 0.8;
}  // namespace

Eigen::VectorXd smoothed_levels(const Mesh& mesh, const Eigen::VectorXd& map, int rounds) {
  Eigen::VectorXd cur = map, next(map.size());
  for (int k = 0; k < rounds; ++k) {
    for (Eigen::Index v = 0; v < cur.size(); ++v) {
      double sum = cur[v];
      int n = 1;
      for (auto w : mesh.vv_range(mesh.vertex_handle(static_cast<int>(v)))) sum += cur[w.idx()], ++n;
      next[v] = sum / n;
    }
    cur.swap(next);
  }
  return cur;
}

double level_spread(const Eigen::VectorXd& levels) {
  if (levels.size() == 0) return 1;
  std::vector<double> x(levels.data(), levels.data() + levels.size());
  const auto at = [&](double q) {
    const auto k = x.begin() + static_cast<std::ptrdiff_t>(q * double(x.size() - 1));
    std::nth_element(x.begin(), k, x.end());
    return *k;
  };
  const double hi = at(0.9), lo = std::max(at(0.1), 1e-3 * hi);
  return hi > 0 ? hi / lo : 1.0;
}

MixedLevels mixed_levels(const Mesh& mesh, const Eigen::VectorXd& map, double unit, double min_spread) {
  MixedLevels out;
  if (!(min_spread > 0) || map.size() == 0) return out;
  const Eigen::VectorXd s = smoothed_levels(mesh, map, kSmoothingRounds);
  out.spread = level_spread(s);
  if (out.spread <= min_spread) return out;
  out.wide_spread = level_spread(smoothed_levels(mesh, s, kWideRounds));
  if (out.wide_spread < kWideShare * out.spread) return out;  // specks: impulses
  out.level = unit * s;
  return out;
}

std::string describe_mixed_levels(const MixedLevels& m, const Eigen::VectorXd& keep, double min_spread) {
  if (m.level.size() == 0) return {};
  return fmt::format("noise per region: the levels differ (90/10 % quantile ratio {:.1f} > {:.1f}, {:.1f} over "
                     "twenty rings): each region measured against its own, {:.0f}% of the change kept on average "
                     "({:.0f}% to {:.0f}%)", m.spread, min_spread, m.wide_spread, 100 * keep.mean(), 100 * keep.minCoeff(), 100 * keep.maxCoeff());
}

}  // namespace geotex::detail
