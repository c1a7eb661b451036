// How a local fit's misfit grows with the fit's size: a coarse model's facets against noise (noise_estimate.cpp).
#pragma once

#include <utility>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex::detail {

//! Share of outliers in the noise estimate above which the noise is not read white and Gaussian: auto_denoise's
//! noise choice line reads it impulsive, and noise_share_of_residual() leaves the estimate whole.
constexpr double kGaussianOutliers = 0.02;

//! The growth of the leave-one-out residual from estimate_noise()'s fit (a cubic over the two-ring, its residuals
//! \p small in mean edge lengths \p h) to a quartic over the three-ring, at (at most 4000 of) \p vertices: the
//! ratio of the residuals' medians, each over the half of the vertices whose ring fits best. Noise gives about 1
//! at both sizes (at most 1.15 measured on the shared models at σ 0.02-0.2); the misfit of a coarse model's own
//! facets grows (the clean cow 1.35).
double misfit_growth(const Mesh& mesh, const std::vector<int>& vertices, double h, const std::vector<double>& small);

//! The share of the two-ring residual's RMS that is noise, given its \p growth (misfit_growth()): 1 up to
//! kNoiseGrowth, 0 from kNoiseGrowth × kFacetGrowth; 1 where the estimate (\p sigma, mean edge lengths, and
//! the share of \p outliers) is not that of white Gaussian noise on a coarse model (see misfit_growth.cpp).
double noise_share_of_residual(double growth, double sigma, double outliers);

}  // namespace geotex::detail
