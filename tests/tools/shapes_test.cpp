#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

TEST(Shapes, CountsAndTopologyMatchTheirFormulas) {
  for (int n : {1, 3, 10}) {
    const Mesh c = subdivided_cube(n);
    EXPECT_EQ(c.n_vertices(), static_cast<size_t>(6 * n * n + 2));
    EXPECT_EQ(c.n_faces(), static_cast<size_t>(12 * n * n));
    const MeshSummary s = summarize(c);
    EXPECT_TRUE(s.closed);
    EXPECT_EQ(s.genus, 0);
    EXPECT_GT(s.volume, 0);  // outward
  }
  const Mesh s = icosphere(3, 2.0);
  EXPECT_EQ(s.n_faces(), 20u * 64u);
  for (auto v : s.vertices()) EXPECT_NEAR(s.point(v).norm(), 2.0, 1e-12);
  const MeshSummary cyl = summarize(cylinder(0.5, 1.0, 32, 8));
  EXPECT_TRUE(cyl.closed);
  EXPECT_EQ(cyl.genus, 0);
  EXPECT_GT(cyl.volume, 0);
  EXPECT_NEAR(cyl.volume, 32 / 2.0 * 0.25 * std::sin(2 * M_PI / 32) * 1.0, 1e-12);  // regular 32-gon prism
  EXPECT_EQ(summarize(torus()).genus, 1);
  EXPECT_GT(signed_volume(torus()), 0);
  EXPECT_EQ(boundary_loops(plane(5)).size(), 1u);
  for (const auto& name : shape_names()) EXPECT_GT(make_shape(name, 0).textured.n_faces(), 100u) << name;
  EXPECT_THROW(make_shape("teapot"), InvalidInput);
}

TEST(Shapes, SpikesLeanPastTheirFootprint) {
  // The texture cannot be a height field along the normal: each tip has moved sideways by more than
  // its footprint radius, so the surface overhangs the foot.
  SpikeOptions o;
  o.count = 6;
  const Mesh base = icosphere(4);
  const TexturedShape s = spiky(base, o);
  ASSERT_EQ(s.spike_centres.size(), 6u);
  const double h = mean_edge_length(base);
  const MatrixX3d B = positions(s.base), T = positions(s.textured);
  const MatrixX3d N = vertex_normals(s.base);
  for (size_t k = 0; k < s.spike_centres.size(); ++k) {
    const int c = s.spike_centres[k];
    const Vec3 d = (T.row(c) - B.row(c)).transpose();
    const Vec3 n = N.row(c).transpose();
    const Vec3 tangential = d - d.dot(n) * n;
    EXPECT_NEAR(d.norm(), o.height * h, 1e-9);
    EXPECT_GT(tangential.norm(), o.radius * h) << "spike " << k;
    EXPECT_GT(tangential.normalized().dot(s.lean[k]), 0.99);  // leans the way it says
  }
  // Same connectivity; same seed, same shape.
  EXPECT_TRUE(faces(s.base) == faces(s.textured));
  EXPECT_TRUE(positions(spiky(base, o).textured) == T);
}

TEST(Shapes, CapsuleIsAClosedSphereWithTheRightArea) {
  const Mesh m = capsule(1.0, 6.0, 80);
  EXPECT_EQ(euler_characteristic(m), 2);
  EXPECT_TRUE(boundary_loops(m).empty());
  EXPECT_GT(signed_volume(m), 0);  // outward
  // Area 2πrL + 4πr² of the smooth capsule, approached from below by the inscribed mesh.
  const double area = face_areas(m).sum(), exact = 2 * M_PI * 6.0 + 4 * M_PI;
  EXPECT_LT(area, exact);
  EXPECT_GT(area, 0.99 * exact);
}

TEST(Shapes, TentacleStickTentaclesBendAsTheySay) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(0, &info);
  ASSERT_EQ(info.size(), 9u);
  EXPECT_TRUE(faces(s.base) == faces(s.textured));
  EXPECT_EQ(euler_characteristic(s.textured), 2);
  const MatrixX3d B = positions(s.base), T = positions(s.textured);
  const MatrixX3d N = vertex_normals(s.base);
  const double R = TentacleOptions().radius, L = TentacleOptions().length;
  for (const auto& t : info) {
    // The centreline turns at a constant rate from the normal to bend_deg: the chord from foot to
    // tip makes half that angle with the normal, and has length (2/κ) sin(θ/2), κ = θ/L.
    const double theta = t.bend_deg * M_PI / 180;
    EXPECT_NEAR(t.lean_deg, 0.5 * t.bend_deg, 1.0);
    EXPECT_NEAR(t.length, 2 * L / theta * std::sin(theta / 2), 0.02 * L);
    // It leans the way it says, and overhangs its foot: the tip is further sideways than the footprint.
    const Vec3 d = (T.row(t.foot) - B.row(t.foot)).transpose(), n = N.row(t.foot).transpose();
    const Vec3 side = d - d.dot(n) * n;
    EXPECT_GT(side.normalized().dot(t.lean), 0.99);
    EXPECT_GT(side.norm(), 0.5 * R);
  }
  // Only the footprints move.
  const Eigen::VectorXd truth = tentacle_truth(s.base, info, R);
  for (Eigen::Index i = 0; i < B.rows(); ++i)
    if (truth[i] == 0) EXPECT_EQ((T.row(i) - B.row(i)).norm(), 0.0);
  EXPECT_GT(truth.sum(), 0.02 * B.rows());
  EXPECT_LT(truth.sum(), 0.2 * B.rows());
}
