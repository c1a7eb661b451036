#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "geotex/toolkit/editing.h"
#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/resize/resize.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;
using geotex::test::TempDir;

namespace {

MatrixX3d apply_map(const SpaceMap& map, const MatrixX3d& X) {
  MatrixX3d C(X.rows(), 3);
  for (Eigen::Index i = 0; i < X.rows(); ++i) C.row(i) = map(X.row(i).transpose()).transpose();
  return C;
}

struct Figures {
  double worst_aspect = 0, worst_height = 0, worst_tilt = 0;  // |aspect − 1|, |height/h0 − 1|, tilt (deg)
};

Figures measure(const BumpyPlate& b, const MatrixX3d& Y) {
  const MatrixX3d X = positions(b.mesh);
  Figures f;
  for (const Vec3& c : b.centres) {
    const BumpShape s0 = measure_bump(X, X, c, b.radius);
    const BumpShape s = measure_bump(X, Y, c, b.radius);
    f.worst_aspect = std::max(f.worst_aspect, std::abs(s.aspect / s0.aspect - 1));
    f.worst_height = std::max(f.worst_height, std::abs(s.height / s0.height - 1));
    f.worst_tilt = std::max(f.worst_tilt, s.tilt_deg);
  }
  return f;
}

ResizeOptions with(ResizeMethod m) {
  ResizeOptions o;
  o.method = m;
  return o;
}

}  // namespace

TEST(Resize, OneRingSimilaritiesRecoverAKnownTransformExactly) {
  const Mesh m = icosphere(2);
  const MatrixX3d X = positions(m);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, -1, 2).normalized()).toRotationMatrix();
  const MatrixX3d Y = ((1.7 * X * R.transpose()).rowwise() + Eigen::RowVector3d(1, 2, 3));
  for (const Similarity& T : one_ring_similarities(m, X, Y, true)) {
    EXPECT_NEAR(T.s, 1.7, 1e-12);
    EXPECT_LT((T.R - R).norm(), 1e-12);
  }
  for (const Similarity& T : one_ring_similarities(m, X, Y, false)) EXPECT_EQ(T.s, 1.0);
}

TEST(Resize, NoFeaturesReproducesTheSpaceMap) {
  const BumpyPlate b = bumpy_plate({.n = 30});
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(b.mesh.n_vertices());
  for (const SpaceMap& map : {scale_map({2, 1, 1}), bend_map(1.5), twist_map(1.0)}) {
    const MatrixX3d C = apply_map(map, positions(b.mesh));
    for (auto method : {ResizeMethod::Sliding, ResizeMethod::Thesis})
      EXPECT_LT((feature_aware_resize(b.mesh, C, none, with(method)) - C).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(Resize, AllFeaturesGivesARigidCopy) {
  const BumpyPlate b = bumpy_plate({.n = 30});
  const MatrixX3d X = positions(b.mesh);
  const Eigen::VectorXd all = Eigen::VectorXd::Ones(X.rows());
  // A rigid space map is reproduced exactly.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.9, Vec3(0.2, 1, 0.4).normalized()).toRotationMatrix();
  const SpaceMap rigid = [&](const Vec3& x) -> Vec3 { return R * x + Vec3(0.5, -1, 2); };
  for (auto method : {ResizeMethod::Sliding, ResizeMethod::Thesis}) {
    const MatrixX3d Y = feature_aware_resize(b.mesh, rigid, all, with(method));
    EXPECT_LT((Y - apply_map(rigid, X)).cwiseAbs().maxCoeff(), 1e-6);
  }
  // Under a (2, 1, 1) scaling, every-vertex-a-feature keeps the plate's shape: a rigid copy, not a
  // stretch. (Not so for the thesis' Eq. 9.2: Laplacian coordinates of a flat region do not see an
  // in-plane affine map, so its solution follows the weak pull to the stretched copy.)
  {
    const MatrixX3d Y = feature_aware_resize(b.mesh, scale_map({2, 1, 1}), all);
    const Similarity T = fit_similarity(X, Y, false);
    double worst = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) worst = std::max(worst, (T(X.row(i).transpose()) - Y.row(i).transpose()).norm());
    EXPECT_LT(worst, 1e-4) << "largest distance from the best rigid copy (plate side 2; the 1e-6 pull to the map remains)";
  }
}

TEST(Resize, ScalingKeepsBumpsRound) {
  const BumpyPlate b = bumpy_plate();
  const MatrixX3d X = positions(b.mesh);
  const Eigen::VectorXd f = features_from_height(b.mesh);
  const SpaceMap map = scale_map({2, 1, 1});
  const Figures plain = measure(b, apply_map(map, X));
  const Figures thesis = measure(b, feature_aware_resize(b.mesh, map, f, with(ResizeMethod::Thesis)));
  const MatrixX3d Y = feature_aware_resize(b.mesh, map, f);
  const Figures sliding = measure(b, Y);
  std::printf("  scale (2,1,1), automatic features; worst |aspect-1|, worst |height ratio-1| over %zu bumps:\n",
              b.centres.size());
  std::printf("    plain scaling  %.4f  %.4f\n    thesis (9.2)   %.4f  %.4f\n    sliding        %.4f  %.4f\n",
              plain.worst_aspect, plain.worst_height, thesis.worst_aspect, thesis.worst_height, sliding.worst_aspect,
              sliding.worst_height);
  EXPECT_GT(plain.worst_aspect, 0.9);  // 2:1
  EXPECT_LT(sliding.worst_aspect, 0.05);
  EXPECT_LT(sliding.worst_height, 0.05);
  EXPECT_LT(thesis.worst_aspect, plain.worst_aspect);
  // The frame follows the map: the plate is twice as wide.
  EXPECT_NEAR(Y.col(0).maxCoeff() - Y.col(0).minCoeff(), 4.0, 0.01);
  EXPECT_NEAR(Y.col(1).maxCoeff() - Y.col(1).minCoeff(), 2.0, 0.01);
}

TEST(Resize, BendingKeepsTheAngleBetweenBumpAndBase) {
  const BumpyPlate b = bumpy_plate();
  const MatrixX3d X = positions(b.mesh);
  const Eigen::VectorXd f = features_from_height(b.mesh);
  const SpaceMap map = bend_map(1.5);
  const Figures plain = measure(b, apply_map(map, X));
  const Figures thesis = measure(b, feature_aware_resize(b.mesh, map, f, with(ResizeMethod::Thesis)));
  const Figures sliding = measure(b, feature_aware_resize(b.mesh, map, f));
  std::printf("  bend kappa 1.5: worst tilt of a bump against its base (deg), worst |height ratio-1|:\n");
  std::printf("    plain map      %.2f  %.4f\n    thesis (9.2)   %.2f  %.4f\n    sliding        %.2f  %.4f\n",
              plain.worst_tilt, plain.worst_height, thesis.worst_tilt, thesis.worst_height, sliding.worst_tilt,
              sliding.worst_height);
  EXPECT_GT(plain.worst_tilt, 20.0);
  EXPECT_LT(sliding.worst_tilt, 3.0);
  EXPECT_LT(thesis.worst_tilt, 0.5 * plain.worst_tilt);
}

TEST(Resize, AutomaticFeaturesFindTheBumps) {
  const BumpyPlate b = bumpy_plate();
  const Eigen::VectorXd f = features_from_height(b.mesh);
  double inter = 0, uni = 0;
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    inter += std::min(f[i], b.truth[i]);
    uni += std::max(f[i], b.truth[i]);
  }
  std::printf("  height features vs true footprints: IoU %.3f\n", inter / uni);
  EXPECT_GT(inter / uni, 0.7);
}

TEST(Resize, RejectsBadInput) {
  const Mesh m = plane(4);
  const MatrixX3d X = positions(m);
  EXPECT_THROW(feature_aware_resize(m, X, Eigen::VectorXd::Zero(3)), InvalidInput);
  EXPECT_THROW(feature_aware_resize(m, X, Eigen::VectorXd::Constant(X.rows(), 2.0)), InvalidInput);
  EXPECT_THROW(feature_aware_resize(m, MatrixX3d(X.topRows(3)), Eigen::VectorXd::Zero(X.rows())), InvalidInput);
}

TEST(ResizeCli, ScalesWithAutomaticAndFileFeatures) {
  TempDir tmp;
  const BumpyPlate b = bumpy_plate({.n = 40});
  write_mesh(b.mesh, tmp / "b.ply");
  auto r = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "r.ply" + " --scale 2,1,1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const MatrixX3d Y = positions(read_mesh(tmp / "r.ply"));
  EXPECT_NEAR(Y.col(0).maxCoeff() - Y.col(0).minCoeff(), 4.0, 0.02);
  // A text file of weights, one per line.
  std::string text;
  for (Eigen::Index i = 0; i < b.truth.size(); ++i) text += std::to_string(b.truth[i]) + "\n";
  geotex::test::write_file(tmp / "f.txt", text);
  auto t = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "t.ply" + " --bend 1 --features " +
                                 tmp / "f.txt" + " --method thesis");
  EXPECT_EQ(t.exit_code, 0) << t.err;
  // A PLY with a vertex "feature" property.
  PlyExtras x;
  x.vertex_scalars["feature"] = std::vector<double>(b.truth.data(), b.truth.data() + b.truth.size());
  write_ply(b.mesh, tmp / "f.ply", x);
  auto p = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "p.ply" + " --twist 0.5 --features " + tmp / "f.ply");
  EXPECT_EQ(p.exit_code, 0) << p.err;
  // Errors.
  geotex::test::write_file(tmp / "short.txt", "1\n0\n");
  auto s = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "s.ply" + " --scale 2,1,1 --features " + tmp / "short.txt");
  EXPECT_NE(s.exit_code, 0);
  EXPECT_NE(s.err.find("weights"), std::string::npos) << s.err;
  EXPECT_NE(geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "s.ply" + " --scale 2,1").exit_code, 0);
  EXPECT_NE(geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "s.ply").exit_code, 0);  // no deformation
  EXPECT_EQ(geotex::test::run_cli("resize --help").exit_code, 0);
}
