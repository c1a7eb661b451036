// A coarse model's change held to what its noise explains, per region (auto_denoise step 6c).
#pragma once

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/surfel.h"

namespace geotex::detail {

//! Per face of \p F over positions \p X, ν², the expected squared angle (radians², at most 1) by which Gaussian
//! noise of standard deviation \p s (absolute, along each axis) turns its normal: a corner moved by δ along the
//! normal turns it by δ / h_i, h_i = 2A / |e_i| the corner's height over the opposite edge, and the three corners'
//! noise is independent, so ν² = s² Σ_i (|e_i| / 2A)². \return #F values.
Eigen::VectorXd face_normal_noise(const MatrixX3i& F, const MatrixX3d& X, double s);

//! Per vertex, the share t of the change from the input \p X to \p P kept: t = min(1, ν̄² / D̄²), ν̄² the mean of
//! face_normal_noise() and D̄² the mean of |n_P − n_X|² over the faces of the vertex's closed one-ring and of its
//! neighbours', each face weighted by 1 / ν_f. Shrinking the change by t turns each normal by t (n_P − n_X) to first
//! order; with the result's own error independent of the noise, E|n_t − n*|² = ν² − 2t ν² + t² D², least at
//! t = ν² / D² and never above ν², the input's own (a Wiener shrinkage of the change towards the input). The error
//! read is each face's angle, E|θ_f| ≈ √(E θ_f²), whose sum is least at t = Σ ν_f / Σ (D_f² / ν_f): the weights,
//! without which a sliver's large ν² excuses its well-shaped neighbours' turn. Where the change is what the noise
//! explains (D² ≈ ν²: the noise removed) t = 1; where it is far beyond (a coarse model's facets rounded) the input
//! is mostly kept. \p s as face_normal_noise(). \return #X values in [0, 1].
Eigen::VectorXd region_guard_share(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& P,
                                   double s);

//! Step 6c of auto_denoise, after the untangling (which, before it, undid it on the beetle's thin faces): where the
//! noise estimate read part of its residual as a coarse model's own facets (r.noise.noise_share < 1,
//! misfit_growth.h), r.positions' change from the input \p X is shrunk per vertex by region_guard_share() with the
//! estimated noise (\p sigma_abs, absolute, the 3-D σ: σ / √3 along each axis). Between the input and the untangled
//! result, it leaves r.turned_over as the untangling counted it.
void hold_change_to_noise(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X, double sigma_abs,
                          AutoDenoiseResult& r);

}  // namespace geotex::detail
