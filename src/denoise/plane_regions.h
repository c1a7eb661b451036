// Flat regions read as planes (issue 24, sixteenth session): a region the sharp fit makes one plane, and whose
// input lies on that plane to within its noise, is read creased throughout (plane_regions.cpp).
#pragma once

#include <Eigen/Core>

#include "geotex/core/mesh.h"

namespace geotex::detail {

//! The sharp fit's flat regions that the input shows to be planes. The regions: the faces of \p Xs (the sharp fit)
//! joined across each edge where their normals differ by less than kSharpEnd's 10°, the angle below which the
//! sharp pass makes neighbouring surfels parallel. A region of at least kMinPlaneVertices vertices is a plane
//! where (a) the input \p X's root-mean-square distance from its least-squares plane is at most \p misfit × the
//! region's noise along the normal (the median of \p noise_map, normal σ in units of \p h, the mean edge length;
//! region_noise.h), and (b) a quadric height field over that plane explains no more than noise would (F statistic of
//! its three extra terms below kCurvedF, the 1 % level): a flat cap under white or depth noise reads 0.9-1.2 and F
//! 0.3-2.6, organic regions of that size 1.5+ (bench/denoise.md, sixteenth session). \return #V, 1 at the vertices
//! of such regions, 0 elsewhere.
Eigen::VectorXd plane_regions(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Xs,
                              const Eigen::VectorXd& noise_map, double h, double misfit);

}  // namespace geotex::detail
