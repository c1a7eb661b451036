// Noise levels that differ region to region (issue 24, sixteenth session): a scan noisy in one region and nearly
// clean in another (the side far from the sensor, the overlap of two scans, a repaired patch) denoised region by
// region at its own level (step 6's share of the change, s = σ⁴ / (σ⁴ + σ0⁴) of each region's level).
#pragma once

#include <string>

#include <Eigen/Core>

#include "geotex/core/mesh.h"

namespace geotex::detail {

//! \p map (region_noise()'s level per vertex) averaged with the one-ring \p rounds times (Jacobi): a region's level
//! read over about three rings varies within about 17 % under white noise, its mean over a few more rings less.
//! \return #V values.
Eigen::VectorXd smoothed_levels(const Mesh& mesh, const Eigen::VectorXd& map, int rounds);

//! The spread of \p levels over the vertices: the ratio of the 90 % quantile to the 10 % quantile (at least 1e-3 ×
//! the 90 % quantile, so that a noise-free region gives a finite spread). \return 1 for an empty or flat map.
double level_spread(const Eigen::VectorXd& levels);

//! Per vertex, the level each region is measured against where the levels differ (level_spread() of the smoothed map
//! above \p min_spread, and still 0.8 × that after seventeen more rounds: a part, not specks): the smoothed map × \p
//! unit (rms over normal sigma, as the mesh's level). Empty where the levels do not differ or \p min_spread is 0.
struct MixedLevels {
  Eigen::VectorXd level;  //!< #V, or empty: the levels do not differ
  double spread = 1;      //!< level_spread() of the smoothed map
  double wide_spread = 0; //!< the same smoothed over 17 more rings (impulses: specks, which it evens out)
};
MixedLevels mixed_levels(const Mesh& mesh, const Eigen::VectorXd& map, double unit, double min_spread);

//! A choices line for mixed_levels()' result \p m (\p keep: the share of the change kept per vertex).
std::string describe_mixed_levels(const MixedLevels& m, const Eigen::VectorXd& keep, double min_spread);

}  // namespace geotex::detail
