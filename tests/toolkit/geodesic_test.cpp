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

TEST(HeatGeodesics, IsolatedVerticesAreUnreachedAndChangeNothing) {
  // An isolated vertex has no mass and no cotangent row: the heat and Poisson systems were singular
  // ("sparse Cholesky failed" in texture transfer on a soup). It is its own component now: +inf, and
  // the surface's distances are those of the mesh without it.
  const Mesh s = icosphere(3);
  MatrixX3d V(s.n_vertices() + 2, 3);
  V << positions(s), Eigen::RowVector3d(5, 0, 0), Eigen::RowVector3d(0, 5, 0);
  const Mesh with_isolated = make_mesh(V, faces(s));
  ASSERT_EQ(with_isolated.n_vertices(), s.n_vertices() + 2);
  const Eigen::VectorXd d0 = heat_geodesic_distance(s, {0});
  const Eigen::VectorXd d1 = heat_geodesic_distance(with_isolated, {0});
  const Eigen::Index n = s.n_vertices();
  EXPECT_LT((d1.head(n) - d0).cwiseAbs().maxCoeff(), 1e-9 * d0.maxCoeff());
  EXPECT_TRUE(std::isinf(d1[n]) && std::isinf(d1[n + 1]));
}

TEST(HeatGeodesics, DegenerateComponentsBesideAPlainOne) {
  // A needle triangle (|cot| at its cap) as a component of its own: the Poisson system's null space
  // was lifted by a vanishing multiple of the mass, a pivot below round-off there ("sparse Cholesky
  // failed" in texture transfer and atlas on a triangle soup). Now φ is pinned per component: the
  // plain component's distances stay (up to the heat time, which the needle's edges change a little),
  // the needle is unreached, and from the needle the distances are finite (a needle has no gradient
  // to follow: their values mean little).
  const Mesh s = icosphere(3);
  const Eigen::Index n = s.n_vertices();
  // And a zero-area triangle with two corners at one point (its third corner gets no weight at all).
  MatrixX3d V(n + 6, 3);
  V << positions(s), Eigen::RowVector3d(3, 0, 0), Eigen::RowVector3d(3.1, 0, 0), Eigen::RowVector3d(3.05, 1e-9, 0),
      Eigen::RowVector3d(5, 0, 0), Eigen::RowVector3d(5, 0, 0), Eigen::RowVector3d(5, 0.1, 0);
  MatrixX3i F(s.n_faces() + 2, 3);
  F << faces(s), Eigen::RowVector3i(n, n + 1, n + 2), Eigen::RowVector3i(n + 3, n + 4, n + 5);
  const Mesh both = make_mesh(V, F);
  const Eigen::VectorXd d0 = heat_geodesic_distance(s, {0});
  const Eigen::VectorXd d1 = heat_geodesic_distance(both, {0});
  EXPECT_LT((d1.head(n) - d0).cwiseAbs().maxCoeff(), 1e-3 * d0.maxCoeff());
  EXPECT_TRUE(std::isinf(d1[n]) && std::isinf(d1[n + 2]) && std::isinf(d1[n + 5]));
  const Eigen::VectorXd d2 = heat_geodesic_distance(both, {static_cast<int>(n)});  // from the needle's corner
  EXPECT_TRUE(d2.segment(n, 3).allFinite() && d2.segment(n, 3).minCoeff() >= 0 && std::isinf(d2[n + 3]));
  EXPECT_TRUE(std::isinf(d2[0]));
  const Eigen::VectorXd d3 = heat_geodesic_distance(both, {static_cast<int>(n + 3)});
  EXPECT_TRUE(d3.tail(3).allFinite() && d3.tail(3).minCoeff() >= 0);
}
