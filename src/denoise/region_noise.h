// The noise level per region: estimate_noise()'s leave-one-out statistic read over each vertex's neighbourhood
// instead of over the whole mesh (issue 24, fifteenth session).
#pragma once

#include <string>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/surfel.h"
#include "noise_estimate.h"

namespace geotex::detail {

//! Per vertex, the normal noise of its region (mean clean edge lengths, as NoiseEstimate::normal_sigma): at the
//! vertices estimate_noise() samples, the two-ring cubic's leave-one-out residuals (\p reading's, read_noise()) of
//! the kRegionSamples sampled vertices nearest it (about three rings where every vertex is sampled), the half
//! whose ring fits best, their mean square without outliers, as estimate_noise() reads the whole mesh; every
//! other vertex takes its nearest sample's. Breadth-first over the mesh's one-rings \p N (one_ring_neighborhoods(),
//! in the order of the mesh's own circulators). The mesh's estimate (its mean and clean edge lengths): \p reading's.
//! Depth noise along a scanner's axis a has the normal variance σ² (n·a)², which one level per mesh reads at the
//! least noisy orientations; a mesh of which a part is noise-free reads the noise-free part. \return #V values;
//! 0 where no vertex of a large enough two-ring is near (boundaries of small meshes).
struct RegionNoise {
  Eigen::VectorXd level;  //!< #V: the normal noise of each vertex's region, mean clean edge lengths
  //! The same statistic over the whole mesh: estimate_noise()'s normal_sigma before its noise_share (a coarse
  //! model's facets) is applied, the reference a region's level is compared with
  double whole = 0;
};
RegionNoise region_noise(const Neighborhoods& N, const NoiseReading& reading);

//! Per vertex, the normal noise (mean edge lengths) the denoiser measures a region against: \p normal_noise (the
//! mesh's level, auto_denoise()'s) where the region reads at most kNoisierRegion × \p map's whole, its own level
//! where it reads more (less the whole's level beyond 1: continuous there); in rms_normal_sigma's units (impulses
//! included), \p noise the mesh's estimate; a region's own level times the estimate's noise_share (the share of the
//! residual read as noise, not a coarse model's facets).
Eigen::VectorXd region_levels(const RegionNoise& map, const NoiseEstimate& noise, double normal_noise);

//! The level the denoiser runs at: \p normal_noise, or where the mesh reads noise-free by it (keeps less than 1e-6 of
//! the change, keep_below \p keep_below) while a tenth of the vertices or more would keep more than half by their
//! \p levels (region_levels()), those vertices' median level (a mesh noise-free but for some regions).
double running_level(const Eigen::VectorXd& levels, double normal_noise, double keep_below);

//! A choices line for \p map (region_noise()): its quantiles over the vertices and the shares of the vertices whose
//! region reads below a third of \p global (the mesh's normal_sigma) or above twice it.
std::string describe_region_noise(const Eigen::VectorXd& map, double global);

}  // namespace geotex::detail
