// Tangent direction fields (toolkit/direction_field.h).

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"
#include "geotex/toolkit/direction_field.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

// Mean and largest angle (degrees) between the field at the two ends of each edge, the far one turned
// into the near one's tangent plane (projected and renormalised: a first-order transport).
std::vector<double> edge_turn_list(const Mesh& m, const MatrixX3d& F) {
  const MatrixX3d N = vertex_normals(m, NormalWeighting::Angle);
  std::vector<double> out;
  for (auto e : m.edges()) {
    const auto h = m.halfedge_handle(e, 0);
    const int i = m.from_vertex_handle(h).idx(), j = m.to_vertex_handle(h).idx();
    const Vec3 n = N.row(i).transpose();
    Vec3 fj = F.row(j).transpose();
    fj = (fj - fj.dot(n) * n).normalized();
    out.push_back(std::acos(std::clamp(fj.dot(F.row(i).transpose()), -1.0, 1.0)) * 180 / M_PI);
  }
  return out;
}

std::pair<double, double> edge_turns(const Mesh& m, const MatrixX3d& F) {
  const std::vector<double> a = edge_turn_list(m, F);
  double sum = 0, worst = 0;
  for (double x : a) sum += x, worst = std::max(worst, x);
  return {sum / a.size(), worst};
}

}  // namespace

TEST(DirectionField, OnAPlaneItIsTheProjectedGuide) {
  const Mesh m = plane(20, 2.0);
  const Vec3 guide(1, 2, 0.7);
  const Vec3 expected = Vec3(1, 2, 0).normalized();
  for (FieldMethod method : {FieldMethod::Smooth, FieldMethod::Projected}) {
    DirectionFieldOptions o;
    o.method = method;
    const MatrixX3d F = direction_field(m, guide.transpose(), o);
    ASSERT_EQ(F.rows(), static_cast<Eigen::Index>(m.n_vertices()));
    for (Eigen::Index i = 0; i < F.rows(); ++i)
      ASSERT_LT((F.row(i).transpose() - expected).norm(), 1e-6) << "vertex " << i;
  }
}

TEST(DirectionField, OnASphereItIsTangentUnitAndSmooth) {
  const Mesh m = icosphere(4);
  const MatrixX3d N = vertex_normals(m, NormalWeighting::Angle);
  // Along z the guide is normal at the poles: the projected field jumps there, the smooth one fills in.
  const Vec3 guide(0.2, 0, 1);
  DirectionFieldOptions smooth, projected;
  projected.method = FieldMethod::Projected;
  const MatrixX3d S = direction_field(m, guide.transpose(), smooth);
  const MatrixX3d P = direction_field(m, guide.transpose(), projected);
  const MatrixX3d X = positions(m);
  for (Eigen::Index i = 0; i < S.rows(); ++i) {
    EXPECT_NEAR(S.row(i).norm(), 1.0, 1e-9);
    EXPECT_LT(std::abs(S.row(i).dot(N.row(i))), 1e-9);
    // Away from the poles the smooth field follows the guide.
    if (std::abs(X(i, 2)) < 0.7) EXPECT_GT(S.row(i).dot(P.row(i)), std::cos(15 * M_PI / 180)) << "vertex " << i;
  }
  const auto [mean_s, worst_s] = edge_turns(m, S);
  std::cout << "mean / largest turn across an edge: " << mean_s << " / " << worst_s << " deg\n";
  // A field on a sphere has singularities (index sum 2): only there are the turns large.
  EXPECT_LT(mean_s, 3.0);
  size_t large = 0;
  for (const double a : edge_turn_list(m, S)) large += a > 20;
  EXPECT_LT(large, m.n_edges() / 50);  // 1.1 % here: the rings around the two singularities
}

TEST(DirectionField, ANoisyGuideGivesASmoothField) {
  const Mesh m = icosphere(4);
  const MatrixX3d X = positions(m);
  MatrixX3d guide(X.rows(), 3);
  Rng rng(3);
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    guide.row(i) = Eigen::RowVector3d(1, 0, 0) + 0.8 * Eigen::RowVector3d(rng.normal(), rng.normal(), rng.normal());
  DirectionFieldOptions smooth, projected;
  projected.method = FieldMethod::Projected;
  const MatrixX3d S = direction_field(m, guide, smooth), P = direction_field(m, guide, projected);
  const double mean_s = edge_turns(m, S).first, mean_p = edge_turns(m, P).first;
  std::cout << "noisy guide: mean turn across an edge " << mean_s << " deg (projected " << mean_p << ")\n";
  EXPECT_LT(mean_s, 0.25 * mean_p);
  // It still follows the guide's mean, x, away from the singularities at ±x.
  const MatrixX3d Q = direction_field(m, Vec3(1, 0, 0).transpose(), projected);
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (std::abs(X(i, 0)) < 0.7) EXPECT_GT(S.row(i).dot(Q.row(i)), std::cos(25 * M_PI / 180)) << "vertex " << i;
}

TEST(DirectionField, RejectsABadGuide) {
  const Mesh m = icosphere(1);
  EXPECT_THROW(direction_field(m, MatrixX3d::Zero(3, 3)), InvalidInput);
  EXPECT_THROW(direction_field(m, Vec3(NAN, 0, 0).transpose()), InvalidInput);
}
