// estimate_noise()'s reading kept for region_noise() (region_noise.h): the sampled vertices' two-ring fits and the
// whole mesh's statistic, computed once per denoise call (issue 24, sixteenth session).
#pragma once

#include <utility>
#include <vector>

#include "geotex/core/mesh.h"
#include "geotex/denoise/auto_denoise.h"

namespace geotex::detail {

//! estimate_noise() with what it read on the way: the estimate, its samples (every stride-th interior vertex, at
//! most max_samples) with each one's leave-one-out fit of the two-ring cubic, and the reduction over the better-
//! fitting half without outliers.
struct NoiseReading {
  NoiseEstimate estimate;
  std::vector<int> samples;  //!< the sampled vertices
  //! Per sample, (the ring's residual variance, the vertex's residual over the fit's own error), mean edge lengths;
  //! (-1, -1) where the ring has no fit
  std::vector<std::pair<double, double>> fits;
  //! The mean square of the better-fitting half's residuals without outliers, mean (noisy) edge lengths:
  //! normal_sigma before the clean edge correction and the noise_share
  double rms = 0;
};

//! estimate_noise(\p mesh, \p max_samples) and its samples' fits. \throw InvalidInput as estimate_noise().
NoiseReading read_noise(const Mesh& mesh, int max_samples = 20000);

}  // namespace geotex::detail
