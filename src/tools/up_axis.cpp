// The automatic up axis of a picture (UpAxis::Auto, see render.h): read from the points the way a
// person sets a model down on a table.

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "geotex/tools/render.h"

namespace geotex {
namespace {

using Point2 = std::array<double, 2>;

double cross(const Point2& o, const Point2& a, const Point2& b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

//! The convex hull of \p p, counter-clockwise (Andrew's monotone chain; \p p is sorted in place).
std::vector<Point2> convex_hull(std::vector<Point2>& p) {
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Point2> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {  // upper chain
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  h.resize(k - 1);
  return h;
}

//! How well the model stands on its lowest points along the axis \p axis, its \p sign side down:
//! the area of the convex hull of the points within 1% of the height of the lowest one (the
//! footprint: four hooves, a plinth, the rim of an open bottom), as a share of the box's cross
//! section, halved when the points' centroid does not project inside it (the model would topple).
double footprint_score(const MatrixX3d& P, int axis, double sign, const Vec3& lo, const Vec3& hi, const Vec3& centroid) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const double section = (hi[a] - lo[a]) * (hi[b] - lo[b]);
  const double floor = sign > 0 ? lo[axis] : hi[axis], band = 0.01 * (hi[axis] - lo[axis]);
  if (!(section > 0) || !(band > 0)) return 0;
  std::vector<Point2> feet;
  for (Eigen::Index i = 0; i < P.rows(); ++i)
    if (std::abs(P(i, axis) - floor) <= band) feet.push_back({P(i, a), P(i, b)});
  const std::vector<Point2> hull = convex_hull(feet);
  if (hull.size() < 3) return 0;
  double area = 0;
  bool inside = true;
  const Point2 c{centroid[a], centroid[b]};
  for (size_t i = 0; i < hull.size(); ++i) {
    const Point2& p = hull[i];
    const Point2& q = hull[(i + 1) % hull.size()];
    area += 0.5 * (p[0] * q[1] - q[0] * p[1]);
    if (cross(p, q, c) < 0) inside = false;
  }
  return (inside ? 1.0 : 0.5) * area / section;
}

}  // namespace

Vec3 up_vector(UpAxis up, const MatrixX3d& points) {
  switch (up) {
    case UpAxis::X: return Vec3::UnitX();
    case UpAxis::Y: return Vec3::UnitY();
    case UpAxis::Z: return Vec3::UnitZ();
    case UpAxis::NegX: return -Vec3::UnitX();
    case UpAxis::NegY: return -Vec3::UnitY();
    case UpAxis::NegZ: return -Vec3::UnitZ();
    case UpAxis::Auto: break;
  }
  if (points.rows() == 0) return Vec3::UnitY();
  const Vec3 lo = points.colwise().minCoeff().transpose(), hi = points.colwise().maxCoeff().transpose();
  // 1. Flat: the camera looks onto the flat side.
  const Vec3 e = (hi - lo).cwiseMax(0.0);
  int axis[3] = {0, 1, 2};  // by extent, thinnest first
  std::sort(axis, axis + 3, [&](int a, int b) { return e[a] < e[b]; });
  if (e[axis[0]] < 0.3 * e[axis[1]]) return Vec3::Unit(axis[0]);
  // 2. Placed on a floor at 0 by its exporter.
  const double tol = 1e-6 * e.norm();
  const bool rests_y = std::abs(lo.y()) <= tol, rests_z = std::abs(lo.z()) <= tol;
  if (rests_z && !rests_y) return Vec3::UnitZ();
  if (rests_y && !rests_z) return Vec3::UnitY();
  // 3. The side it stands on best, when clearly better than y's: a z-up bust on its plinth, a CAD
  //    part on its flat base; scans and characters stand on y.
  const Vec3 centroid = points.colwise().mean().transpose();
  const double y_score = footprint_score(points, 1, 1.0, lo, hi, centroid);
  Vec3 best = Vec3::UnitY();
  double best_score = y_score;
  for (int k = 0; k < 3; ++k)
    for (double sign : {1.0, -1.0}) {
      const double s = footprint_score(points, k, sign, lo, hi, centroid);
      if (s > best_score) best_score = s, best = sign * Vec3::Unit(k);
    }
  if (best_score >= 0.05 && best_score >= 2 * y_score) return best;
  // 4. Otherwise y: scans (Stanford, Cyberware) and most exchange files are y-up.
  return Vec3::UnitY();
}

}  // namespace geotex
