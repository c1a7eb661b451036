#pragma once
//! \file space_maps.h Smooth deformations of space beyond those of resize.h (scale_map, bend_map,
//! twist_map), and the tools to apply and differentiate them.

#include <functional>

#include "geotex/core/mesh.h"

namespace geotex {

//! A space map R³ → R³ applied to every vertex (the same type as resize.h's).
using SpaceMap = std::function<Vec3(const Vec3&)>;

//! Arc bend about the y axis: the line y = z = 0 goes by arclength onto the circle of radius \p radius
//! through (x0, 0, 0) with centre (x0, 0, radius); a point at height z above the line goes to the
//! concentric circle of radius radius − z (cross-sections stay rigid and perpendicular to the bent
//! axis, unlike bend_map's shear). x ↦ (x0 + r sin a, y, radius − r cos a), a = (x − x0)/radius,
//! r = radius − z. \throw InvalidInput unless radius is finite and non-zero.
SpaceMap arc_bend_map(double radius, double x0 = 0.0);

//! \return #V by 3: \p map applied to every row of \p X.
MatrixX3d apply_space_map(const SpaceMap& map, const MatrixX3d& X);

//! The Jacobian of \p map at \p x by central differences with step \p step.
Eigen::Matrix3d space_map_jacobian(const SpaceMap& map, const Vec3& x, double step = 1e-6);

}  // namespace geotex
