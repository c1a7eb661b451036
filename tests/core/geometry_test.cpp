#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

// A model far off the origin has the volume it has at the origin (issue 25, fifteenth session): summed over
// tetrahedra on the origin, 10^4 diagonals out, each term is 10^12 times the volume and the sum cancelled to noise.
TEST(Geometry, TheVolumeDoesNotDependOnWhereTheModelIs) {
  const Mesh sphere = icosphere(3);
  const double v0 = signed_volume(sphere);
  MatrixX3d X = positions(sphere);
  Mesh far = sphere;
  set_positions(far, X.rowwise() + 2e4 * Vec3(0.6, -0.48, 0.64).transpose());
  EXPECT_NEAR(signed_volume(far), v0, 1e-9 * v0);
}

TEST(Geometry, CubeNormalsAreaAndDihedralAngles) {
  const Mesh cube = subdivided_cube(4, 2.0);
  EXPECT_NEAR(surface_area(cube), 24.0, 1e-12);
  EXPECT_NEAR(signed_volume(cube), 8.0, 1e-12);  // outward orientation
  const MatrixX3d N = face_normals(cube);
  for (Eigen::Index f = 0; f < N.rows(); ++f) EXPECT_NEAR(N.row(f).cwiseAbs().maxCoeff(), 1.0, 1e-12);
  // Every edge is flat (0) or a cube edge (+90°, convex); none is concave.
  const Eigen::VectorXd D = dihedral_angles(cube);
  int sharp = 0;
  for (Eigen::Index e = 0; e < D.size(); ++e) {
    if (std::abs(D[e]) > 1e-9) {
      EXPECT_NEAR(D[e], M_PI / 2, 1e-12);
      ++sharp;
    }
  }
  EXPECT_EQ(sharp, 12 * 4);  // 12 cube edges, 4 mesh edges each
  // Vertex normals of the corners point along (±1, ±1, ±1) under angle weighting (three right angles).
  const MatrixX3d VN = vertex_normals(cube, NormalWeighting::Angle);
  const MatrixX3d X = positions(cube);
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if ((X.row(i).cwiseAbs().array() == 1.0).all())
      EXPECT_NEAR(VN.row(i).dot(X.row(i).normalized()), 1.0, 1e-12);
}

TEST(Geometry, ConcaveEdgesAreNegative) {
  // A "V" of two triangles folded up: a valley.
  MatrixX3d V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0.5, 1, 0.5, 0.5, -1, 0.5;
  MatrixX3i F(2, 3);
  F << 0, 1, 2, 1, 0, 3;
  const Mesh m = make_mesh(V, F);
  const Eigen::VectorXd D = dihedral_angles(m);
  double interior = 0;
  for (auto e : m.edges())
    if (!m.is_boundary(e)) interior = D[e.idx()];
  EXPECT_LT(interior, 0);
  EXPECT_NEAR(std::abs(interior), 2 * std::atan(0.5), 1e-12);  // normals (0,∓0.5,1): cos = 0.6
}

TEST(Geometry, TopologyOfTheTestShapes) {
  EXPECT_EQ(euler_characteristic(icosphere(3)), 2);
  EXPECT_EQ(euler_characteristic(torus()), 0);
  EXPECT_EQ(summarize(torus()).genus, 1);
  EXPECT_EQ(summarize(cylinder()).genus, 0);
  EXPECT_TRUE(summarize(cylinder()).closed);
  const Mesh p = plane(6);
  const auto loops = boundary_loops(p);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 24u);
  EXPECT_EQ(euler_characteristic(p), 1);
  // Consecutive loop vertices share a boundary edge.
  for (size_t k = 0; k < loops[0].size(); ++k) {
    auto a = p.vertex_handle(loops[0][k]), b = p.vertex_handle(loops[0][(k + 1) % loops[0].size()]);
    auto h = p.find_halfedge(a, b);
    ASSERT_TRUE(h.is_valid());
    EXPECT_TRUE(p.is_boundary(p.edge_handle(h)));
  }
}

TEST(Geometry, ComponentsAndMeanEdgeLengthAreCounted) {
  // Two spheres side by side.
  const Mesh a = icosphere(1);
  MatrixX3d V(2 * a.n_vertices(), 3);
  MatrixX3i F(2 * a.n_faces(), 3);
  const MatrixX3d Va = positions(a);
  const MatrixX3i Fa = faces(a);
  V << Va, Va.rowwise() + Eigen::RowVector3d(5, 0, 0);
  F << Fa, Fa.array() + static_cast<int>(a.n_vertices());
  const Mesh two = make_mesh(V, F);
  int k = 0;
  const Eigen::VectorXi comp = connected_components(two, &k);
  EXPECT_EQ(k, 2);
  EXPECT_EQ(comp[0], 0);
  EXPECT_EQ(comp[a.n_vertices()], 1);
  EXPECT_EQ(summarize(two).components, 2);
  // Mean edge length of a unit grid.
  EXPECT_NEAR(mean_edge_length(plane(1, 1.0)), (4 + std::sqrt(2.0)) / 5, 1e-12);
  const BoundingBox b = bounding_box(two);
  EXPECT_NEAR(b.max[0] - b.min[0], 7.0, 1e-12);
}
