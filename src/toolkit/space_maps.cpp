#include "geotex/toolkit/space_maps.h"

#include <cmath>

#include "geotex/core/error.h"

namespace geotex {

SpaceMap arc_bend_map(double radius, double x0) {
  if (!std::isfinite(radius) || radius == 0 || !std::isfinite(x0))
    throw InvalidInput("arc bend: radius must be finite and non-zero");
  return [radius, x0](const Vec3& p) -> Vec3 {
    const double a = (p.x() - x0) / radius, r = radius - p.z();
    return {x0 + r * std::sin(a), p.y(), radius - r * std::cos(a)};
  };
}

MatrixX3d apply_space_map(const SpaceMap& map, const MatrixX3d& X) {
  MatrixX3d Y(X.rows(), 3);
  for (Eigen::Index i = 0; i < X.rows(); ++i) Y.row(i) = map(X.row(i).transpose()).transpose();
  return Y;
}

Eigen::Matrix3d space_map_jacobian(const SpaceMap& map, const Vec3& x, double step) {
  Eigen::Matrix3d J;
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = step * Vec3::Unit(k);
    J.col(k) = (map(x + e) - map(x - e)) / (2 * step);
  }
  return J;
}

}  // namespace geotex
