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

namespace {
// The faces some edge of another face (sharing no vertex with it) crosses, by testing every (edge, face)
// pair (Moller-Trumbore): the reference the self-intersection search is checked against.
std::vector<char> crossed_faces_brute_force(const MatrixX3d& V, const MatrixX3i& F) {
  std::vector<char> brute(F.rows(), 0);
  for (Eigen::Index g = 0; g < F.rows(); ++g)
    for (int s = 0; s < 3; ++s) {
      const int a = F(g, s), b = F(g, (s + 1) % 3);
      const Vec3 p0 = V.row(a).transpose(), d = (V.row(b) - V.row(a)).transpose();
      for (Eigen::Index f = 0; f < F.rows(); ++f) {
        if ((F.row(f).array() == a).any() || (F.row(f).array() == b).any()) continue;
        const Vec3 A = V.row(F(f, 0)).transpose(), e1 = (V.row(F(f, 1)) - V.row(F(f, 0))).transpose(),
                   e2 = (V.row(F(f, 2)) - V.row(F(f, 0))).transpose();
        const Vec3 pv = d.cross(e2);
        const double det = e1.dot(pv);
        if (!(std::abs(det) > 1e-30)) continue;
        const Vec3 q = (p0 - A).cross(e1);
        const double u = (p0 - A).dot(pv) / det, v = d.dot(q) / det, w = e2.dot(q) / det;
        if (u > 1e-9 && v > 1e-9 && u + v < 1 - 1e-9 && w > 1e-9 && w < 1 - 1e-9) brute[f] = 1;
      }
    }
  return brute;
}

}  // namespace

TEST(Metrics, SelfIntersectionsOfAFanMatchBruteForce) {
  // A fan of 1,500 triangles around one vertex (more than the 1,024 that give a hub its own search tree,
  // issue 30) crossed by a few long triangles, some through the hub: the crossed faces found by the
  // tree search equal those of the test over every (edge, face) pair.
  const int k = 1500;
  MatrixX3d V(k + 1 + 9, 3);
  MatrixX3i F(k + 3, 3);
  V.row(0) << 0, 0, 0.2;
  for (int i = 0; i < k; ++i) {
    const double t = 2 * M_PI * i / k;
    V.row(1 + i) << std::cos(t), std::sin(t), 0;
    F.row(i) << 0, 1 + i, 1 + (i + 1) % k;
  }
  const double pierce[3][9] = {{0.3, 0.1, -1, 0.31, 0.12, 1, 0.9, 0.5, 0.0},     // through the fan
                               {-0.5, -0.2, -1, -0.52, -0.2, 1, -0.1, -0.9, 0.0},  // through the fan
                               {0, 0, 0.2, 0.2, 0.2, 1, -0.3, 0.4, 1}};            // at the hub, above it
  for (int t = 0; t < 3; ++t) {
    for (int c = 0; c < 3; ++c) V.row(k + 1 + 3 * t + c) << pierce[t][3 * c], pierce[t][3 * c + 1], pierce[t][3 * c + 2];
    F.row(k + t) << k + 1 + 3 * t, k + 2 + 3 * t, k + 3 + 3 * t;
  }
  F(k + 2, 0) = 0;  // the third shares the hub
  const std::vector<char> hit = self_intersecting_faces(V, F);
  const std::vector<char> brute = crossed_faces_brute_force(V, F);
  EXPECT_EQ(hit, brute);
  EXPECT_GE(std::count(brute.begin(), brute.end(), 1), 4);  // the piercing triangles and fan faces they cross
}

TEST(Metrics, SelfIntersectionsOfNeedlesMatchBruteForce) {
  // 600 random needles (aspect 100, cut into 16 slabs for the search) in a small box, so that many
  // cross: the crossed faces equal those of the test over every (edge, face) pair.
  const int k = 600;
  MatrixX3d V(3 * k, 3);
  MatrixX3i F(k, 3);
  uint64_t state = 7;
  auto uniform = [&] { return double((state = state * 6364136223846793005ULL + 1442695040888963407ULL) >> 11) / double(1ULL << 53); };
  for (int i = 0; i < k; ++i) {
    const Vec3 a(uniform(), uniform(), uniform());
    const Vec3 d = Vec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5).normalized();
    const Vec3 w = d.cross(Vec3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5)).normalized();
    V.row(3 * i) = a.transpose();
    V.row(3 * i + 1) = (a + 0.5 * d).transpose();
    V.row(3 * i + 2) = (a + 0.25 * d + 5e-3 * w).transpose();
    F.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  }
  const std::vector<char> hit = self_intersecting_faces(V, F);
  const std::vector<char> brute = crossed_faces_brute_force(V, F);
  EXPECT_EQ(hit, brute);
  std::printf("  needles: %d of %d crossed\n", static_cast<int>(std::count(brute.begin(), brute.end(), 1)), k);
  EXPECT_GE(std::count(brute.begin(), brute.end(), 1), 5);
}

TEST(Metrics, SelfIntersectionsOfADenseSoupMatchBruteForce) {
  // 500 random triangles of about a third of the box's side: most faces are crossed, so the first
  // search (one piece in 8) flags more than a quarter of them and the rest search the faces left.
  const int k = 500;
  MatrixX3d V(3 * k, 3);
  MatrixX3i F(k, 3);
  Rng rng(13);
  for (int i = 0; i < k; ++i) {
    const Vec3 c(rng.uniform(), rng.uniform(), rng.uniform());
    for (int j = 0; j < 3; ++j)
      V.row(3 * i + j) = (c + 0.3 * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))).transpose();
    F.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  }
  const std::vector<char> hit = self_intersecting_faces(V, F);
  const std::vector<char> brute = crossed_faces_brute_force(V, F);
  EXPECT_EQ(hit, brute);
  EXPECT_GE(std::count(brute.begin(), brute.end(), 1), k / 2);
}
