#pragma once
// The change a denoiser may make to a region (step 6a of auto_denoise.h): what it removes from a noisy
// mesh is the noise, white from vertex to vertex; what it removes from a coarse mesh's own facets (or a
// model's genuine relief) is spatially coherent. The coherent part beyond the noise is given back.

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

struct CoherentChangeOptions {
  //! κ: how strongly a coherent change is given back (0 keeps every change).
  double weight = 0.3;
  int rings = 3;        //!< rings over which each vertex's neighbourhood statistics are summed
  double z = 2;         //!< standard errors by which the local covariance is lowered (a white change reads 0)
  double rho = 0.45;    //!< the edge correlation of a coherent change (a coarse model's smoothing: 0.33–0.54)
};

//! Per vertex, the share of the change \p change (#V by 3) to keep: with d the change along \p normals,
//! C the covariance of d across the edges within options.rings rings (lowered by z standard errors, at
//! least 0) and σ² = \p noise_var (the normal noise's variance, absolute units²), the Wiener gain
//! g = σ² / (σ² + κ C / ρ): 1 where the change is white, towards 0 where it is coherent beyond the noise.
//! \p N: one-rings (one_ring_neighborhoods()). \throw InvalidInput on mismatched sizes.
Eigen::VectorXd coherent_change_gain(const Neighborhoods& N, const MatrixX3d& normals, const MatrixX3d& change,
                                     double noise_var, const CoherentChangeOptions& options = {});

}  // namespace geotex
