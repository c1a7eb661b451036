// Self-intersections of a triangle mesh (core/self_intersections.h): the tree search against the test
// of every (edge, face) pair.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "geotex/core/random.h"
#include "geotex/core/self_intersections.h"
#include "test_util.h"

using namespace geotex;

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

TEST(SelfIntersections, FacesOfAFanMatchBruteForce) {
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

TEST(SelfIntersections, FacesOfNeedlesMatchBruteForce) {
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

TEST(SelfIntersections, FacesOfADenseSoupMatchBruteForce) {
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
