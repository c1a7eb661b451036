#include <cmath>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/tools/noise.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

namespace {
Mesh bumpy_sphere() {
  Mesh m = icosphere(3);
  NoiseOptions n;
  n.sigma = 0.2;
  set_positions(m, add_noise(m, n));
  return m;
}
}  // namespace

TEST(Laplace, RowsSumToZero) {
  for (const Mesh& m : {bumpy_sphere(), plane(8), cylinder(0.5, 1, 16, 4)}) {
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(m.n_vertices());
    EXPECT_LT((umbrella_laplacian(m) * one).cwiseAbs().maxCoeff(), 1e-13);
    for (auto mass : {MassType::Voronoi, MassType::Barycentric, MassType::Thesis})
      EXPECT_LT((cotan_laplacian(m, mass) * one).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(Laplace, CotanMatrixIsSymmetricNegativeSemiDefinite) {
  const Mesh m = icosphere(2);
  const SparseMatrix C = cotan_matrix(m);
  EXPECT_LT((SparseMatrix(C - SparseMatrix(C.transpose()))).norm(), 1e-12);
  const Eigen::MatrixXd Cd(C);
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Cd).eigenvalues();
  EXPECT_LT(ev.maxCoeff(), 1e-10);
  EXPECT_GT(ev.minCoeff(), -1e3);
}

TEST(Laplace, CotanVanishesOnFlatPatchInterior) {
  // Irregular flat patch: a grid with jittered interior vertices, still in the plane z = 0.
  Mesh m = plane(10);
  MatrixX3d X = positions(m);
  Rng rng(3);
  for (auto v : m.vertices())
    if (!m.is_boundary(v)) {
      X(v.idx(), 0) += 0.02 * rng.uniform(-1, 1);
      X(v.idx(), 1) += 0.02 * rng.uniform(-1, 1);
    }
  set_positions(m, X);
  const MatrixX3d LX = cotan_laplacian(m) * X;
  const MatrixX3d UX = umbrella_laplacian(m) * X;
  double umbrella_max = 0;
  for (auto v : m.vertices())
    if (!m.is_boundary(v)) {
      EXPECT_LT(LX.row(v.idx()).norm(), 1e-10) << "vertex " << v.idx();
      umbrella_max = std::max(umbrella_max, UX.row(v.idx()).norm());
    }
  EXPECT_GT(umbrella_max, 1e-4);  // the umbrella operator does not vanish: it drifts tangentially
}

TEST(Laplace, UmbrellaRankIsVerticesMinusComponents) {
  // Eq. (5.18): rank(L) = n - k.
  const Mesh a = icosphere(1), b = torus(1, 0.3, 8, 5), c = plane(3);
  std::vector<const Mesh*> parts = {&a, &b, &c};
  MatrixX3d V(0, 3);
  MatrixX3i F(0, 3);
  for (const Mesh* p : parts) {
    MatrixX3d V2(V.rows() + p->n_vertices(), 3);
    V2 << V, positions(*p);
    MatrixX3i F2(F.rows() + p->n_faces(), 3);
    F2 << F, faces(*p).array() + static_cast<int>(V.rows());
    V = V2;
    F = F2;
  }
  const Mesh m = make_mesh(V, F);
  int k = 0;
  connected_components(m, &k);
  ASSERT_EQ(k, 3);
  const Eigen::MatrixXd L(umbrella_laplacian(m));
  Eigen::FullPivLU<Eigen::MatrixXd> lu(L);
  lu.setThreshold(1e-10);
  EXPECT_EQ(lu.rank(), static_cast<Eigen::Index>(m.n_vertices()) - k);
}

TEST(Laplace, MeanCurvatureNormalOfASphere) {
  for (double r : {0.5, 2.0}) {
    const Mesh m = icosphere(4, r);
    const MatrixX3d H = mean_curvature_normals(m);
    const MatrixX3d X = positions(m);
    double worst = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      const Vec3 expect = X.row(i).transpose() / (r * r);  // n / r
      worst = std::max(worst, (Vec3(H.row(i)) - expect).norm() * r);
    }
    EXPECT_LT(worst, 0.02);  // relative to 1/r
  }
}

TEST(Laplace, MassSumsToAreaAndThesisNormalization) {
  const Mesh m = bumpy_sphere();
  const double area = surface_area(m);
  EXPECT_NEAR(mass_diagonal(m, MassType::Voronoi).sum(), area, 1e-10 * area);
  EXPECT_NEAR(mass_diagonal(m, MassType::Barycentric).sum(), area, 1e-10 * area);
  EXPECT_NEAR(mass_diagonal(m, MassType::Thesis).sum(), 6 * area, 1e-9 * area);
  // Eq. (5.11) evaluated directly at one vertex equals the Thesis-mass Laplacian row.
  const auto v = m.vertex_handle(7);
  const MatrixX3d X = positions(m);
  double A = 0;
  for (auto f : m.vf_range(v)) {
    Vec3 p[3];
    int k = 0;
    for (auto w : m.fv_range(f)) p[k++] = to_eigen(m.point(w));
    A += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
  }
  Vec3 sum = Vec3::Zero();
  for (auto h : m.voh_range(v)) {
    auto cot_at = [&](Mesh::HalfedgeHandle hh) {
      if (m.is_boundary(hh)) return 0.0;
      const Vec3 a = to_eigen(m.point(m.from_vertex_handle(hh))), b = to_eigen(m.point(m.to_vertex_handle(hh)));
      const Vec3 o = to_eigen(m.point(m.to_vertex_handle(m.next_halfedge_handle(hh))));
      return (a - o).dot(b - o) / (a - o).cross(b - o).norm();
    };
    const Vec3 xj = to_eigen(m.point(m.to_vertex_handle(h)));
    sum += (cot_at(h) + cot_at(m.opposite_halfedge_handle(h))) * (xj - X.row(7).transpose());
  }
  const Vec3 direct = sum / (4 * A);
  const Vec3 via = (cotan_laplacian(m, MassType::Thesis) * X).row(7).transpose();
  EXPECT_LT((direct - via).norm(), 1e-10 * direct.norm());
}

TEST(Laplace, DegenerateTrianglesGiveFiniteWeights) {
  // A zero-area triangle (collinear corners) inside a fan.
  MatrixX3d V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 2, 0, 0, 1, 1, 0;
  MatrixX3i F(2, 3);
  F << 0, 1, 3, 1, 2, 3;
  Mesh m = make_mesh(V, F);
  MatrixX3d V2 = V;
  V2.row(3) << 1, 0, 0;  // squash: both triangles become degenerate
  set_positions(m, V2);
  EXPECT_TRUE(Eigen::MatrixXd(cotan_matrix(m)).allFinite());
  EXPECT_TRUE(Eigen::MatrixXd(cotan_laplacian(m)).allFinite());
}
