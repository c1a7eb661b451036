// Simplification (toolkit/simplify.h): a coarse mesh whose vertices are input vertices, and the
// harmonic extension of values known there.

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/toolkit/simplify.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

TEST(Simplify, KeepsInputVerticesWhereTheyAreAndTheTopology) {
  const Mesh in = icosphere(4);  // 2,562 vertices, closed, genus 0
  const SimplifiedMesh s = simplify(in, 300);
  const Mesh& m = s.mesh;
  EXPECT_LE(m.n_vertices(), 300u);
  EXPECT_GE(m.n_vertices(), 250u);
  ASSERT_EQ(s.original.size(), m.n_vertices());
  std::set<int> distinct(s.original.begin(), s.original.end());
  EXPECT_EQ(distinct.size(), s.original.size());
  for (auto v : m.vertices()) {
    const int o = s.original[v.idx()];
    ASSERT_GE(o, 0);
    ASSERT_LT(o, static_cast<int>(in.n_vertices()));
    EXPECT_EQ(m.point(v), in.point(in.vertex_handle(o)));  // not moved: the same point, bit for bit
  }
  // Euler characteristic of a sphere, and no boundary opened.
  EXPECT_EQ(static_cast<int>(m.n_vertices()) - static_cast<int>(m.n_edges()) + static_cast<int>(m.n_faces()), 2);
  for (auto e : m.edges()) EXPECT_FALSE(m.is_boundary(e));
  // No face flipped: every face's normal points away from the centre, as the sphere's do.
  for (auto f : m.faces()) {
    Vec3 c = Vec3::Zero(), p[3];
    int k = 0;
    for (auto v : m.fv_range(f)) c += (p[k++] = to_eigen(m.point(v)));
    EXPECT_GT((p[1] - p[0]).cross(p[2] - p[0]).dot(c), 0);
  }
  // Small enough already: returned as it is.
  const SimplifiedMesh same = simplify(in, 5000);
  EXPECT_EQ(same.mesh.n_vertices(), in.n_vertices());
  EXPECT_EQ(same.original[17], 17);
  EXPECT_THROW(simplify(in, 3), InvalidInput);
}

TEST(Simplify, HarmonicExtensionAveragesNeighboursAndKeepsItsBounds) {
  const Mesh m = icosphere(3);
  const SimplifiedMesh s = simplify(m, 100);
  Eigen::MatrixXd known(s.original.size(), 2);
  for (size_t k = 0; k < s.original.size(); ++k) {
    const Vec3 p = to_eigen(m.point(m.vertex_handle(s.original[k])));
    known(k, 0) = p.x() * p.y() + p.z();  // any values
    known(k, 1) = 3.0;                    // a constant
  }
  const Eigen::MatrixXd x = extend_harmonic(m, s.original, known);
  ASSERT_EQ(x.rows(), static_cast<Eigen::Index>(m.n_vertices()));
  std::vector<char> is_known(m.n_vertices(), 0);
  for (size_t k = 0; k < s.original.size(); ++k) {
    is_known[s.original[k]] = 1;
    EXPECT_EQ(x(s.original[k], 0), known(k, 0));
  }
  for (auto v : m.vertices()) {
    EXPECT_NEAR(x(v.idx(), 1), 3.0, 1e-9);
    EXPECT_GE(x(v.idx(), 0), known.col(0).minCoeff() - 1e-12);  // the maximum principle
    EXPECT_LE(x(v.idx(), 0), known.col(0).maxCoeff() + 1e-12);
    if (is_known[v.idx()]) continue;
    double sum = 0;
    int k = 0;
    for (auto w : m.vv_range(v)) sum += x(w.idx(), 0), ++k;
    EXPECT_NEAR(x(v.idx(), 0), sum / k, 1e-9);
  }
  EXPECT_THROW(extend_harmonic(m, {0, 1}, Eigen::MatrixXd::Zero(3, 1)), InvalidInput);
}

TEST(ExtendHarmonic, AComponentWithoutKnownVerticesIsRefusedByName) {
  // Two disjoint triangles' fans: values known on the first only. Decided before any factorization.
  Mesh m;
  std::vector<Mesh::VertexHandle> v;
  for (int k = 0; k < 8; ++k) v.push_back(m.add_vertex(Mesh::Point(k % 4 == 0 ? 0 : std::cos(k), std::sin(k), k / 4)));
  m.add_face(v[0], v[1], v[2]);
  m.add_face(v[0], v[2], v[3]);
  m.add_face(v[4], v[5], v[6]);
  m.add_face(v[4], v[6], v[7]);
  try {
    extend_harmonic(m, {0}, Eigen::MatrixXd::Ones(1, 1));
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("component 2 of 2"), std::string::npos) << e.what();
  }
  const Eigen::MatrixXd x = extend_harmonic(m, {0, 4}, Eigen::MatrixXd::Ones(2, 1));
  EXPECT_NEAR((x.array() - 1).abs().maxCoeff(), 0.0, 1e-12);
}
