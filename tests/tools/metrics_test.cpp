#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/tools/metrics.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"
#include "geotex/core/spatial.h"
#include "test_util.h"

using namespace geotex;

TEST(Metrics, IdenticalMeshesScoreZero) {
  const Mesh m = subdivided_cube(6);
  const Comparison c = compare_meshes(m, m);
  EXPECT_EQ(c.mean_normal_error_deg, 0);
  EXPECT_EQ(c.ev, 0);
  EXPECT_EQ(c.hausdorff, 0);
  EXPECT_TRUE(c.faces_by_index);
}

TEST(Metrics, RotationGivesItsAngleAsNormalError) {
  const Mesh m = icosphere(3);
  Mesh r = m;
  const double angle = 7.0 * M_PI / 180.0;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  set_positions(r, positions(m) * R.transpose());
  // A normal at angle a from the axis turns by acos(cos²a + sin²a cos θ) (Rodrigues).
  const MatrixX3d N = face_normals(m);
  const Vec3 axis = Vec3(1, 2, 3).normalized();
  double expect = 0;
  for (Eigen::Index f = 0; f < N.rows(); ++f) {
    const double c = N.row(f).dot(axis);
    expect += std::acos(std::clamp(c * c + (1 - c * c) * std::cos(angle), -1.0, 1.0));
  }
  expect *= 180.0 / M_PI / N.rows();
  const Comparison cmp = compare_meshes(r, m);
  EXPECT_NEAR(cmp.mean_normal_error_deg, expect, 1e-6);
  EXPECT_NEAR(cmp.max_normal_error_deg, 7.0, 0.5);  // faces nearly normal to the axis turn by ~θ
}

TEST(Metrics, ScaledSphereIsItsScaleAway) {
  const Mesh m = icosphere(4, 1.0);
  Mesh s = m;
  set_positions(s, 1.01 * positions(m));
  const Comparison c = compare_meshes(s, m);
  // Vertices of the scaled sphere are 0.01 outside the original's vertices; the facets sit slightly
  // inside the sphere, so distances are a bit above 0.01.
  EXPECT_NEAR(c.ev, 0.01, 0.002);
  EXPECT_GE(c.hausdorff, c.ev);
  EXPECT_NEAR(c.ev_relative, c.ev / bounding_box(m).diagonal(), 1e-15);
  EXPECT_NEAR(c.mean_normal_error_deg, 0, 1e-9);
}

TEST(Metrics, TreeClosestPointMatchesBruteForce) {
  const Mesh m = torus(1, 0.3, 24, 12);
  const TriangleTree tree(m);
  const MatrixX3d V = positions(m);
  const MatrixX3i F = faces(m);
  Rng rng(11);
  for (int q = 0; q < 300; ++q) {
    const Vec3 p(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-1, 1));
    double best = 1e300;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      best = std::min(best, (closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2))) - p).squaredNorm());
    const auto hit = tree.closest(p);
    EXPECT_NEAR(hit.sq_distance, best, 1e-12);
    // barycentric coordinates reproduce the point
    const Vec3 q2 = hit.bary[0] * V.row(F(hit.face, 0)).transpose() + hit.bary[1] * V.row(F(hit.face, 1)).transpose() +
                    hit.bary[2] * V.row(F(hit.face, 2)).transpose();
    EXPECT_LT((q2 - hit.point).norm(), 1e-12);
  }
}

namespace {
// 2,000 random needles (length 0.5, widths 5e-5 to 5e-3: aspects 100 to 10^4, held by the tree as slabs)
// in the unit cube, and a fan of 3,000 slivers around one vertex (issue 30).
void needle_soup(MatrixX3d& V, MatrixX3i& F) {
  const int k = 2000;
  V.resize(3 * k, 3);
  F.resize(k, 3);
  Rng rng(5);
  for (int i = 0; i < k; ++i) {
    const Vec3 a(rng.uniform(), rng.uniform(), rng.uniform());
    const Vec3 d = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
    const Vec3 w = d.cross(Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))).normalized();
    V.row(3 * i) = a.transpose();
    V.row(3 * i + 1) = (a + 0.5 * d).transpose();
    V.row(3 * i + 2) = (a + 0.25 * d + std::pow(10.0, rng.uniform(-4.3, -2.3)) * w).transpose();
    F.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  }
}
void sliver_fan(MatrixX3d& V, MatrixX3i& F) {
  const int k = 3000;
  V.resize(k + 1, 3);
  F.resize(k, 3);
  V.row(0) << 0, 0, 0.2;
  for (int i = 0; i < k; ++i) {
    V.row(i + 1) << std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0;
    F.row(i) << 0, 1 + i, 1 + (i + 1) % k;
  }
}
}  // namespace

TEST(Metrics, TreeClosestPointOfSliversMatchesBruteForce) {
  // The tree holds slivers as slabs with boxes of their own; its closest point must still be the one
  // found by trying every face (the first of the nearest in face order: the same face, point and
  // distance, bit for bit, for points off ties), near the needles, on them and away from them.
  for (int shape = 0; shape < 2; ++shape) {
    MatrixX3d V;
    MatrixX3i F;
    if (shape == 0) needle_soup(V, F);
    else sliver_fan(V, F);
    const TriangleTree tree(V, F);
    size_t references = 0;
    for (int node = 0; node < tree.node_count(); ++node) references += tree.node_faces(node).size();
    EXPECT_GT(references, 3u * F.rows());  // the slabs are there
    Rng rng(9);
    for (int q = 0; q < 600; ++q) {
      Vec3 p(rng.uniform(-0.5, 1.5), rng.uniform(-0.5, 1.5), rng.uniform(-0.5, 1.5));
      if (q % 3 == 1) {  // on a face
        const int f = static_cast<int>(rng.uniform() * F.rows());
        const double s = rng.uniform(), t = rng.uniform() * (1 - s);
        p = (1 - s - t) * V.row(F(f, 0)).transpose() + s * V.row(F(f, 1)).transpose() + t * V.row(F(f, 2)).transpose();
      } else if (q % 3 == 2) {  // just off a vertex
        p = V.row(static_cast<int>(rng.uniform() * V.rows())).transpose() + 1e-3 * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
      }
      int face = -1;
      double best = std::numeric_limits<double>::infinity();
      Vec3 point;
      for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const Vec3 c = closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
        if ((c - p).squaredNorm() < best) {
          best = (c - p).squaredNorm();
          face = static_cast<int>(f);
          point = c;
        }
      }
      const TriangleTree::Hit hit = tree.closest(p);
      if (shape == 0) {
        EXPECT_EQ(hit.sq_distance, best) << "query " << q;
        EXPECT_EQ(hit.point, point) << "query " << q;
        EXPECT_EQ(hit.face, face) << "query " << q;
      } else {  // on the fan, a point nearest to a shared edge is a tie of two faces (rounded apart)
        EXPECT_NEAR(hit.sq_distance, best, 1e-15 * (1 + best)) << "query " << q;
        EXPECT_LT((hit.point - point).norm(), 1e-14) << "query " << q;
      }
      // The best-first search visits every face within the radius once, nearest box first, at a box
      // distance no larger than the face's.
      const double radius = std::sqrt(best) + 0.05;
      std::vector<int> visited;
      double last = 0;
      tree.visit_nearest(p, radius, [&](int f, double box_distance) {
        EXPECT_GE(box_distance, last);
        last = box_distance;
        const Vec3 c = closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
        EXPECT_LE(box_distance, (c - p).norm() + 1e-12);
        visited.push_back(f);
        return radius;
      });
      std::sort(visited.begin(), visited.end());
      EXPECT_EQ(std::adjacent_find(visited.begin(), visited.end()), visited.end()) << "a face visited twice";
      for (Eigen::Index f = 0; f < F.rows(); ++f) {
        const Vec3 c = closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
        if ((c - p).norm() <= radius)
          EXPECT_TRUE(std::binary_search(visited.begin(), visited.end(), static_cast<int>(f))) << "face " << f << " missed";
      }
    }
  }
}

TEST(Metrics, EdgeLabelScoresMatchEdgesEitherWayRound) {
  MatrixX2i truth(4, 2), labelled(3, 2);
  truth << 0, 1, 1, 2, 2, 3, 3, 4;
  labelled << 1, 0, 2, 3, 5, 6;  // two right (one reversed), one wrong
  const LabelScore s = score_edge_labels(labelled, truth);
  EXPECT_EQ(s.true_positive, 2u);
  EXPECT_DOUBLE_EQ(s.precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall, 0.5);
  EXPECT_DOUBLE_EQ(s.f1, 2 * (2.0 / 3.0) * 0.5 / (2.0 / 3.0 + 0.5));
}
