// Coincident vertices found and welded (core/weld.h): what is welded, what is left apart, and the way back.

#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/core/spatial.h"
#include "geotex/core/weld.h"
#include "geotex/tools/shapes.h"

#include "test_util.h"

using namespace geotex;

using test::soup;

TEST(Weld, CoincidentGroupsChainWithinTheToleranceAcrossCellWalls) {
  // Near copies on either side of a grid wall (the grid is 1024 tolerances from the lowest point), exact copies, and
  // a point just beyond the tolerance.
  const double tol = 1e-3, wall = 1024 * tol;
  MatrixX3d X(7, 3);
  X << 0, 0, 0,                              //
      wall - 0.4 * tol, 0.5, 0.5,            // 1 and 2: across the wall x = wall, 0.8 tol apart
      wall + 0.4 * tol, 0.5, 0.5,            //
      0.3, 0.3, 0.3,                         // 3 and 4: the same point
      0.3, 0.3, 0.3,                         //
      0.3 + 1.2 * tol, 0.3, 0.3,             // 5: beyond the tolerance from 3 and 4
      wall + 1.1 * tol, 0.5, 0.5;            // 6: within it of 2 only: chained onto 1
  const std::vector<int> g = coincident_groups(X, tol);
  EXPECT_EQ(g, (std::vector<int>{0, 1, 1, 3, 3, 5, 1}));
  const std::vector<int> only{1, 3, 5};  // a subset: its members' copies outside it are not looked at
  EXPECT_EQ(coincident_groups(X, tol, &only), (std::vector<int>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(coincident_groups(X, 0.0), (std::vector<int>{0, 1, 2, 3, 3, 5, 6}));  // exact copies only
}

TEST(Weld, TwoPatchesSharingAnEdgeAreWeldedAndTheWayBackKeepsTheInputsVertices) {
  // A unit square stored as two triangles with their diagonal twice.
  const Mesh m = soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {3, 4, 5}});
  EXPECT_EQ(boundary_loops(m).size(), 2u);
  const Weld w = weld_coincident(m);
  ASSERT_FALSE(w.identity());
  EXPECT_EQ(w.merged, 2);
  EXPECT_EQ(w.refused, 0);
  EXPECT_EQ(w.mesh.n_vertices(), 4u);
  EXPECT_EQ(w.mesh.n_faces(), 2u);
  EXPECT_EQ(boundary_loops(w.mesh).size(), 1u);
  EXPECT_EQ(w.welded, (std::vector<int>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(w.first, (std::vector<int>{0, 1, 2, 5}));
  MatrixX3d W(4, 3);
  W << 0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0;
  const MatrixX3d V = w.to_input(W);
  ASSERT_EQ(V.rows(), 6);
  EXPECT_EQ(V.row(3), V.row(0));
  EXPECT_EQ(V.row(4), V.row(2));
  Eigen::VectorXd f(6);
  f << 0, 0, 0, 1, 0.5, 0;  // painted on one side of the diagonal
  const Eigen::VectorXd g = w.max_to_welded(f);
  EXPECT_EQ(g, Eigen::Vector4d(1, 0, 0.5, 0));
}

TEST(Weld, GroupsThatWouldMakeTheMeshWorseAreLeftApart) {
  // Two triangles touching at one point (welded: a vertex joining two fans): welded per fan, i.e. nothing merged,
  // and the two copies tied for a solve to keep together (not identity: the welded mesh is the input's copy).
  const Mesh bowtie = soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {-1, 0, 0}, {0, -1, 0}}, {{0, 1, 2}, {3, 4, 5}});
  Weld w = weld_coincident(bowtie);
  EXPECT_FALSE(w.identity());
  EXPECT_EQ(w.merged, 0);
  EXPECT_EQ(w.refused, 1);
  EXPECT_EQ(w.ties, (std::vector<std::array<int, 2>>{{0, 3}}));
  EXPECT_EQ(w.mesh.n_vertices(), 6u);
  EXPECT_EQ(w.welded, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  // Two triangles on one edge the same way round (welded: an orientation no halfedge mesh holds).
  const Mesh same_way =
      soup({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0, 0, 0}, {1, 0, 0}, {0.5, -1, 0.1}}, {{0, 1, 2}, {3, 4, 5}});
  w = weld_coincident(same_way);
  EXPECT_TRUE(w.identity());
  EXPECT_EQ(w.refused, 2);
  EXPECT_TRUE(w.ties.empty());  // left apart, not per fan: nothing to tie
  // A face with two corners at one point (welded: degenerate) beside a seam that is welded.
  const Mesh sliver = soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 1, 0}},
                           {{0, 1, 2}, {3, 4, 5}, {6, 5, 4}});
  w = weld_coincident(sliver);
  EXPECT_EQ(w.refused, 1);  // 5 and 6
  EXPECT_EQ(w.merged, 2);   // the diagonal
  EXPECT_EQ(w.mesh.n_faces(), 3u);
  EXPECT_TRUE(w.ties.empty());
}

TEST(Weld, AWeldedModelIsLeftAsItIs) {
  const Mesh m = icosphere(3);
  const Weld w = weld_coincident(m);
  EXPECT_TRUE(w.identity());
  EXPECT_EQ(w.refused, 0);
  EXPECT_EQ(w.mesh.n_vertices(), 0u);
}

namespace {

// An open tube (\p segments around, \p rings along) of radius 0.25 standing on the unit icosphere along \p axis: its
// lower rim's vertices moved onto their closest points on the ball's faces (none on a ball vertex: a rim resting on
// another part's faces, as the teapot's handle ends on its body), its upper rim 0.6 out. The ball's vertices first.
Mesh tube_on_a_ball(const Vec3& axis, int segments = 16, int rings = 6) {
  const Mesh ball = icosphere(3);
  const MatrixX3d B = positions(ball);
  const MatrixX3i Fb = faces(ball);
  const TriangleTree tree(B, Fb);
  const Vec3 a = axis.normalized(), u = a.unitOrthogonal(), w = a.cross(u);
  const Eigen::Index nb = B.rows(), nt = static_cast<Eigen::Index>(segments) * (rings + 1);
  MatrixX3d X(nb + nt, 3);
  X.topRows(nb) = B;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double t = 2 * M_PI * (s + 0.5) / segments;
      const Vec3 p = 0.9 * a + 0.25 * (std::cos(t) * u + std::sin(t) * w) + (0.7 * r / rings) * a;
      X.row(nb + r * segments + s) = (r == 0 ? tree.closest(p).point : p).transpose();
    }
  MatrixX3i F(Fb.rows() + 2 * segments * rings, 3);
  F.topRows(Fb.rows()) = Fb;
  for (int r = 0, k = static_cast<int>(Fb.rows()); r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const int i = static_cast<int>(nb) + r * segments, j = i + segments, s1 = (s + 1) % segments;
      F.row(k++) = Eigen::RowVector3i(i + s, i + s1, j + s1);
      F.row(k++) = Eigen::RowVector3i(i + s, j + s1, j + s);
    }
  return make_mesh(X, F);
}

}  // namespace

// Rims resting on another part's faces: every vertex of the tube's lower rim is found, tied to a face of the ball
// (never its own part's) at barycentric weights that give it back; the upper rim, 0.6 out, is not; a tolerance below
// the lower rim's distance from the ball finds nothing once the rim is lifted off it.
TEST(Weld, RimsRestingOnAnotherPartsFacesAreTiedToTheirPointsOnThem) {
  const int segments = 16;
  const Mesh m = tube_on_a_ball(Vec3(1, 0.3, 0.2), segments);
  const MatrixX3d X = positions(m);
  const int nb = static_cast<int>(icosphere(3).n_vertices());
  const std::vector<SurfaceTie> ties = rim_contacts(m);
  ASSERT_EQ(ties.size(), static_cast<size_t>(segments));
  const double unit = mean_edge_length(m);
  for (size_t k = 0; k < ties.size(); ++k) {
    const SurfaceTie& t = ties[k];
    EXPECT_EQ(t.vertex, nb + static_cast<int>(k));  // the lower rim, by vertex
    Vec3 at = Vec3::Zero();
    for (int c = 0; c < 3; ++c) {
      EXPECT_LT(t.corners[c], nb);
      EXPECT_GE(t.weights[c], 0.0);
      at += t.weights[c] * X.row(t.corners[c]).transpose();
    }
    EXPECT_NEAR(t.weights.sum(), 1.0, 1e-12);
    EXPECT_LE((at - X.row(t.vertex).transpose()).norm(), 1e-9 * unit);
    EXPECT_LT(t.weights.maxCoeff(), 1.0);  // on a face or an edge, not at a ball vertex
  }
  MatrixX3d lifted = X;  // the tube moved out by a tenth of a mean edge length
  const Vec3 a = Vec3(1, 0.3, 0.2).normalized();
  for (Eigen::Index i = nb; i < X.rows(); ++i) lifted.row(i) += 0.1 * unit * a.transpose();
  Mesh off = m;
  set_positions(off, lifted);
  EXPECT_EQ(rim_contacts(off).size(), static_cast<size_t>(segments));
  EXPECT_TRUE(rim_contacts(off, 0.05).empty());
  EXPECT_TRUE(rim_contacts(icosphere(2)).empty());  // no rim
}
