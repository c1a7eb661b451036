// Geodesic distance by the heat method (toolkit/geodesic.h).

#include <cmath>
#include <iostream>
#include <queue>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/geodesic.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {
int nearest(const Mesh& m, const Vec3& p) {
  Eigen::Index best;
  (positions(m).rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}
// Shortest edge paths (Dijkstra): what the disks used before, an overestimate on most meshes.
Eigen::VectorXd edge_path_distance(const Mesh& m, int src) {
  Eigen::VectorXd d = Eigen::VectorXd::Constant(m.n_vertices(), 1e300);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  d[src] = 0;
  q.push({0, src});
  while (!q.empty()) {
    const auto [dv, v] = q.top();
    q.pop();
    if (dv > d[v]) continue;
    for (auto w : m.vv_range(m.vertex_handle(v))) {
      const double nd = dv + (m.point(w) - m.point(m.vertex_handle(v))).norm();
      if (nd < d[w.idx()]) q.push({d[w.idx()] = nd, w.idx()});
    }
  }
  return d;
}
}  // namespace

TEST(HeatGeodesics, GreatCircleDistanceOnASphere) {
  const Mesh s = icosphere(5, 2.0);
  const int src = nearest(s, Vec3(0, 0, 2));
  const Eigen::VectorXd d = heat_geodesic_distance(s, {src});
  const MatrixX3d X = positions(s);
  const Vec3 p = X.row(src).transpose().normalized();
  const Eigen::VectorXd path = edge_path_distance(s, src);
  double worst = 0, worst_path = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double exact = 2.0 * std::acos(std::clamp(Vec3(X.row(i).transpose()).normalized().dot(p), -1.0, 1.0));
    if (exact < 0.5 || exact > 5.5) continue;  // away from both poles
    worst = std::max(worst, std::abs(d[i] - exact) / exact);
    worst_path = std::max(worst_path, std::abs(path[i] - exact) / exact);
  }
  std::cout << "[ heat geodesics, icosphere(5) radius 2 ] max relative error " << worst << " (edge paths " << worst_path
            << ")\n";
  EXPECT_LT(worst, 0.03);
  EXPECT_LT(worst, 0.5 * worst_path);
  EXPECT_EQ(d[src], 0.0);
}

TEST(HeatGeodesics, EuclideanDistanceOnAPlaneAndSeveralSources) {
  const Mesh p = plane(60, 2.0);
  const MatrixX3d X = positions(p);
  const int a = nearest(p, Vec3(-0.4, 0, 0)), b = nearest(p, Vec3(0.4, 0.1, 0));
  HeatGeodesics geo(p);
  const Eigen::VectorXd da = geo.distance(a), dab = geo.distance(std::vector<int>{a, b});
  const Eigen::VectorXd path = edge_path_distance(p, a);
  double worst = 0, worst2 = 0, worst_path = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double ea = (X.row(i) - X.row(a)).norm(), eb = (X.row(i) - X.row(b)).norm();
    if (std::abs(X(i, 0)) > 0.8 || std::abs(X(i, 1)) > 0.8) continue;  // Neumann boundary bends the field near it
    if (ea > 0.3) worst = std::max(worst, std::abs(da[i] - ea) / ea);
    if (ea > 0.3) worst_path = std::max(worst_path, std::abs(path[i] - ea) / ea);
    if (std::min(ea, eb) > 0.3) worst2 = std::max(worst2, std::abs(dab[i] - std::min(ea, eb)) / std::min(ea, eb));
  }
  // The grid's right triangles make the cotangent Laplacian slightly anisotropic: the distance along the
  // axes comes out ~3 % short (Crane et al.'s t = h²; longer times smooth it out).
  std::cout << "[ heat geodesics, plane (right triangles) ] max relative error beyond 9 edges " << worst
            << " (one source), " << worst2 << " (two); edge paths " << worst_path << "\n";
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(worst2, 0.08);
  EXPECT_LT(worst, worst_path);
  EXPECT_THROW(geo.distance(std::vector<int>{}), InvalidInput);
  EXPECT_THROW(geo.distance(-1), InvalidInput);
  EXPECT_THROW(HeatGeodesics(p, {.time_factor = 0}), InvalidInput);
}
