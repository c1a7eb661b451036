#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <optional>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "geotex/toolkit/editing.h"
#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/self_intersections.h"
#include "geotex/core/weld.h"
#include "geotex/core/io.h"
#include "geotex/resize/resize.h"
#include "geotex/resize/untangle.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/simplify.h"
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
    for (auto method : {ResizeMethod::Similarity, ResizeMethod::Sliding, ResizeMethod::Thesis})
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
  for (auto method : {ResizeMethod::Similarity, ResizeMethod::Sliding, ResizeMethod::Thesis}) {
    const MatrixX3d Y = feature_aware_resize(b.mesh, rigid, all, with(method));
    EXPECT_LT((Y - apply_map(rigid, X)).cwiseAbs().maxCoeff(), 1e-6);
  }
  // Under a (2, 1, 1) scaling, every-vertex-a-feature keeps the plate's shape: a rigid copy, not a
  // stretch. (Not so for the thesis' Eq. 9.2: Laplacian coordinates of a flat region do not see an
  // in-plane affine map, so its solution follows the weak pull to the stretched copy.)
  {
    const MatrixX3d Y = feature_aware_resize(b.mesh, scale_map({2, 1, 1}), all, with(ResizeMethod::Sliding));
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
  const MatrixX3d Y = feature_aware_resize(b.mesh, map, f, with(ResizeMethod::Sliding));
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
  const Figures sliding = measure(b, feature_aware_resize(b.mesh, map, f, with(ResizeMethod::Sliding)));
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

// Eq. (9.3) as written: W [L; I] X = W [D^t; C] solved in the least-squares sense, with W the
// diagonal of the f_i and the w p_i. Reference: the dense least-squares solution of that stacked
// system by QR, per coordinate, on a small mesh with fractional weights (for 0/1 weights and w = 1
// squaring would change nothing).
TEST(Resize, ThesisPresetSolvesEquation93AsWritten) {
  const Mesh m = icosphere(1);  // 42 vertices
  const int n = static_cast<int>(m.n_vertices());
  const MatrixX3d X = positions(m);
  MatrixX3d C = apply_map(twist_map(0.8), apply_map(scale_map({1.7, 1.0, 0.8}), X));
  Eigen::VectorXd f(n);
  for (int i = 0; i < n; ++i) f[i] = 0.5 + 0.45 * std::sin(3.0 * i);  // in [0.05, 0.95]
  ResizeOptions o;
  ResizeOptions::table().apply_preset(o, "thesis");
  o.position_weight = 2.5;
  ASSERT_EQ(o.method, ResizeMethod::Thesis);
  ASSERT_TRUE(o.square_weights);
  ASSERT_FALSE(o.keep_feature_size);  // T_i similarities ("rotation and scale")
  const MatrixX3d Y = feature_aware_resize(m, C, f, o);

  const Eigen::MatrixXd L = Eigen::MatrixXd(umbrella_laplacian(m));
  const std::vector<Similarity> T = one_ring_similarities(m, X, C, true);
  MatrixX3d Dt(n, 3);
  const MatrixX3d D = L * X;
  for (int i = 0; i < n; ++i) Dt.row(i) = (T[i].linear() * D.row(i).transpose()).transpose();
  auto stacked_solution = [&](const Eigen::VectorXd& rows_f, const Eigen::VectorXd& rows_p) {
    Eigen::MatrixXd A(2 * n, n);
    A << rows_f.asDiagonal() * L, Eigen::MatrixXd(rows_p.asDiagonal());
    Eigen::MatrixXd B(2 * n, 3);
    B << rows_f.asDiagonal() * Dt, rows_p.asDiagonal() * C;
    return Eigen::MatrixXd(A.colPivHouseholderQr().solve(B));
  };
  const Eigen::VectorXd wp = o.position_weight * (Eigen::VectorXd::Ones(n) - f);
  const Eigen::MatrixXd ref93 = stacked_solution(f, wp);  // rows weighted by W: energy weights f², (w p)²
  EXPECT_LT((Y - ref93).cwiseAbs().maxCoeff(), 1e-5);
  // Without squaring, the energy of Eq. (9.2) itself: rows weighted by √f, √(w p).
  o.square_weights = false;
  const MatrixX3d Y92 = feature_aware_resize(m, C, f, o);
  const Eigen::MatrixXd ref92 = stacked_solution(f.cwiseSqrt(), wp.cwiseSqrt());
  EXPECT_LT((Y92 - ref92).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_GT((ref92 - ref93).cwiseAbs().maxCoeff(), 1e-3) << "the test case must tell the two apart";
}

TEST(Resize, OptionTablesDescribeEveryOptionAndTheThesisPreset) {
  ResizeOptions o;
  EXPECT_NO_THROW(ResizeOptions::table().check(o));
  EXPECT_NE(ResizeOptions::table().find("square_weights"), nullptr);
  EXPECT_NE(ResizeOptions::table().find("transition"), nullptr);
  EXPECT_THROW(ResizeOptions::table().apply_preset(o, "nonsense"), InvalidOption);
  o.position_weight = -1;
  EXPECT_THROW(feature_aware_resize(plane(3), MatrixX3d(positions(plane(3))), Eigen::VectorXd::Zero(16), o), InvalidInput);
  FeatureMapOptions fo;
  EXPECT_NO_THROW(FeatureMapOptions::table().check(fo));
  FeatureMapOptions::table().set(fo, "features", std::string("adf"));
  EXPECT_EQ(fo.method, FeatureMapMethod::Adf);
  EXPECT_THROW(FeatureMapOptions::table().set(fo, "features", std::string("magic")), InvalidOption);
  SpaceMapOptions so;
  EXPECT_TRUE(so.identity());
  EXPECT_THROW(SpaceMapOptions::table().set(so, "scale", Vec3(2, 0, 1)), InvalidOption);
}

TEST(Resize, ArcMapKeepsTheAxisLengthAndBendsIt) {
  const SpaceMap arc = arc_map(2.0);
  // The line z = 0 keeps its length and lies on the circle of radius 2 about (0, ·, 2).
  for (double x : {-3.0, -1.0, 0.0, 0.5, 2.0}) {
    const Vec3 y = arc(Vec3(x, 0.3, 0));
    EXPECT_NEAR((y - Vec3(0, 0.3, 2)).norm(), 2.0, 1e-12);
    EXPECT_NEAR(std::atan2(y.x(), 2 - y.z()), x / 2.0, 1e-12);
  }
  // A point above the axis (towards the centre) is on the smaller circle.
  EXPECT_NEAR((arc(Vec3(1, 0, 0.5)) - Vec3(0, 0, 2)).norm(), 1.5, 1e-12);
}

// Sliding without rings: around the features' rims, the largest crease (dihedral angle) of the
// result is no larger than the plain map's (which has none of its own beyond the input's).
TEST(Resize, BendsAndTwistsLeaveNoCreaseAroundFeatures) {
  const BumpyPlate b = ridge_plate();
  const MatrixX3d X = positions(b.mesh);
  FeatureMapOptions binary;
  binary.method = FeatureMapMethod::Auto;
  const FeatureMap fm = feature_map(b.mesh, binary);
  const double input = rim_crease_deg(b.mesh, X, fm.weights);
  for (const SpaceMap& map : {bend_map(1.5), twist_map(1.0), scale_map({2, 1, 1})}) {
    const MatrixX3d C = apply_map(map, X);
    const double plain = rim_crease_deg(b.mesh, C, fm.weights);
    const double sliding =
        rim_crease_deg(b.mesh, feature_aware_resize(b.mesh, C, fm.weights, with(ResizeMethod::Sliding)), fm.weights);
    std::printf("  largest crease at feature rims (deg): input %.1f, plain map %.1f, sliding %.1f\n", input, plain, sliding);
    EXPECT_LT(sliding, std::max(input, plain) + 1.0);
  }
}

TEST(Resize, WrongSizedOrOutOfRangeInputsThrow) {
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

// The command's flags come from ResizeRunOptions' table; every output is checked before any work.
TEST(ResizeCli, RefusesBadFlagsAndOutputsBeforeWork) {
  TempDir tmp;
  write_mesh(bumpy_plate({.n = 16}).mesh, tmp / "b.ply");
  const std::string in = geotex::test::read_file(tmp / "b.ply");
  for (const char* name : {"o.ply", "r.json", "f.ply"}) geotex::test::write_file(tmp / name, "old");
  const std::string outs = " -o " + tmp / "o.ply" + " --report " + tmp / "r.json" + " --save-features " + tmp / "f.ply";
  for (const std::string bad : {"--scale 2,1,1 --no-such-flag", "--scale 2,1,1 --transition -1",
                                "--scale 2,1,1 --features everything", "--scale 2,-1,1", "--scale 2,1,1 --preset best",
                                "--scale 2,1,1 --laplacian nope"}) {
    const auto r = geotex::test::run_cli("resize " + tmp / "b.ply" + outs + " " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << ": " << r.err;
    EXPECT_EQ(r.err.find("resize:"), std::string::npos) << bad << ": no work may start: " << r.err;
    for (const char* name : {"o.ply", "r.json", "f.ply"}) EXPECT_EQ(geotex::test::read_file(tmp / name), "old") << bad;
  }
  // An output that is the input, or another output, is refused before any work.
  for (const std::string args : {" -o " + tmp / "b.ply", " -o " + tmp / "o.ply" + " --report " + tmp / "b.ply",
                                 " -o " + tmp / "o.ply" + " --save-features " + tmp / "o.ply"}) {
    const auto r = geotex::test::run_cli("resize " + tmp / "b.ply" + args + " --scale 2,1,1");
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_EQ(r.err.find("resize:"), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(geotex::test::read_file(tmp / "b.ply"), in) << args;
    EXPECT_EQ(geotex::test::read_file(tmp / "o.ply"), "old") << args;
  }
}

// The map written by --save-features is the one used: read back with --features it gives the same
// result; the report and the printed summary say how much is marked.
TEST(ResizeCli, SavedFeatureMapRoundTripsAndIsReported) {
  TempDir tmp;
  const BumpyPlate b = bumpy_plate({.n = 16});
  write_mesh(b.mesh, tmp / "b.ply");
  const auto r = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "a.ply" + " --scale 2,1,1 --save-features " +
                                       tmp / "f.ply" + " --report " + tmp / "r.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("marked fraction "), std::string::npos) << r.err;  // said as the report names it
  const auto report = nlohmann::json::parse(geotex::test::read_file(tmp / "r.json"));
  EXPECT_GE(report["marked_fraction"].get<double>(), 0.0);  // the continuous map of a 16 × 16 plate marks little
  EXPECT_LE(report["marked_fraction"].get<double>(), 1.0);
  EXPECT_EQ(report["parameters"]["features"], "importance");
  EXPECT_EQ(report["parameters"]["scale"], nlohmann::json({2.0, 1.0, 1.0}));
  const auto s = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "s.ply" + " --scale 2,1,1 --features " +
                                       tmp / "f.ply");
  ASSERT_EQ(s.exit_code, 0) << s.err;
  EXPECT_EQ(positions(read_mesh(tmp / "a.ply")), positions(read_mesh(tmp / "s.ply")));
  // Everything marked: the result is close to the plain map, and the user is told.
  std::string ones;
  for (size_t i = 0; i < b.mesh.n_vertices(); ++i) ones += "1\n";
  geotex::test::write_file(tmp / "all.txt", ones);
  const auto w = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "w.ply" + " --scale 2,1,1 --features " +
                                       tmp / "all.txt");
  ASSERT_EQ(w.exit_code, 0) << w.err;
  EXPECT_NE(w.err.find("warning"), std::string::npos) << w.err;
}

// ---------------------------------------------------------------------------------------------
// The default: continuous importance weights, near-similarities where important (Similarity).

namespace {

bool small_meshes() { return geotex::test::kAddressSanitizer || std::getenv("GEOTEX_SANITIZE") != nullptr; }

// Singular values s1 ≥ s2 of the linear map taking face k of X (in its own plane) to Y.
Eigen::Vector2d face_stretch(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Y, Eigen::Index k) {
  const Vec3 e1 = (X.row(F(k, 1)) - X.row(F(k, 0))).transpose(), e2 = (X.row(F(k, 2)) - X.row(F(k, 0))).transpose();
  const Vec3 u = e1.normalized(), v = e1.cross(e2).cross(e1).normalized();
  Eigen::Matrix2d P;
  P << e1.dot(u), e2.dot(u), e1.dot(v), e2.dot(v);
  Eigen::Matrix<double, 3, 2> Q;
  Q << (Y.row(F(k, 1)) - Y.row(F(k, 0))).transpose(), (Y.row(F(k, 2)) - Y.row(F(k, 0))).transpose();
  return Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(Q * P.inverse()).singularValues();
}

// The worst anisotropy s1/s2 − 1 of the result \p Y and of the plain map \p C over the core of a painted map \p f
// (the faces with weight 1 at all three corners), and how many core faces there are.
struct CoreStretch {
  double worst = 0, plain = 0;
  int faces = 0;
};
CoreStretch core_stretch(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Y, const MatrixX3d& C,
                         const Eigen::VectorXd& f) {
  CoreStretch c;
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    if (std::min({f[F(k, 0)], f[F(k, 1)], f[F(k, 2)]}) < 1.0) continue;
    const Eigen::Vector2d sv = face_stretch(F, X, Y, k), sp = face_stretch(F, X, C, k);
    c.worst = std::max(c.worst, sv[0] / sv[1] - 1);
    c.plain = std::max(c.plain, sp[0] / sp[1] - 1);
    ++c.faces;
  }
  return c;
}

// Faces whose normal points against the plain map's.
int turned_over(const Mesh& m, const MatrixX3d& Y, const MatrixX3d& C) {
  const MatrixX3i F = faces(m);
  int count = 0;
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    auto nrm = [&](const MatrixX3d& P) {
      return Vec3((P.row(F(k, 1)) - P.row(F(k, 0))).cross(P.row(F(k, 2)) - P.row(F(k, 0))).transpose());
    };
    if (nrm(Y).dot(nrm(C)) < 0) ++count;
  }
  return count;
}

// A painted weight map: 1 within radius r of each bump's centre, falling smoothly to 0 at 1.8 r.
Eigen::VectorXd painted(const BumpyPlate& b, double r) {
  const MatrixX3d X = positions(b.mesh);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (const Vec3& c : b.centres) {
      const double t = std::clamp((1.8 * r - (X.row(i).head<2>() - c.head<2>().transpose()).norm()) / (0.8 * r), 0.0, 1.0);
      f[i] = std::max(f[i], t * t * (3 - 2 * t));
    }
  return f;
}

}  // namespace

TEST(ResizeSimilarity, DefaultsAreTheImportanceMapAndTheThesisPresetIsKept) {
  const ResizeRunOptions d;
  EXPECT_EQ(d.features.method, FeatureMapMethod::Importance);
  EXPECT_EQ(d.resize.method, ResizeMethod::Auto);  // axis-similarity on a box scale, similarity otherwise
  EXPECT_TRUE(d.resize.rigid_protrusions);         // where the rest can take the room (issue 25, twelfth session)
  ResizeRunOptions t;
  ResizeRunOptions::table().apply_preset(t, "thesis");
  EXPECT_EQ(t.resize.method, ResizeMethod::Thesis);
  EXPECT_TRUE(t.resize.square_weights);
  EXPECT_FALSE(t.resize.keep_feature_size);
  EXPECT_EQ(t.resize.laplacian, LaplacianType::Umbrella);
  EXPECT_EQ(t.features.method, FeatureMapMethod::Auto);  // the thesis' binary map of protrusions
  FeatureMapOptions fo;
  FeatureMapOptions::table().set(fo, "features", std::string("auto"));  // the binary map stays reachable
  EXPECT_EQ(fo.method, FeatureMapMethod::Auto);
}

// The importance map is continuous, in [0, 1], 0 on the flat plate far from the bumps and high on them.
TEST(ResizeSimilarity, ImportanceIsContinuousAndMarksTheBumps) {
  const BumpyPlate b = bumpy_plate({.n = small_meshes() ? 40 : 60});
  const FeatureMap fm = feature_map(b.mesh);
  ASSERT_EQ(fm.method, FeatureMapMethod::Importance);
  const Eigen::VectorXd& f = fm.weights;
  EXPECT_GE(f.minCoeff(), 0.0);
  EXPECT_LE(f.maxCoeff(), 1.0);
  const MatrixX3d X = positions(b.mesh);
  double inside = 0, far = 0, far_max = 0;
  int n_in = 0, n_far = 0, fractional = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    double d = 1e9;
    for (const Vec3& c : b.centres) d = std::min(d, (X.row(i).head<2>() - c.head<2>().transpose()).norm());
    if (d < 0.5 * b.radius) inside += f[i], ++n_in;
    // The flat plate away from the bumps, its rim and its corners (the corners of its square outline are relief
    // too: importance_outline; FeatureMap.TheOutlineOfAFlatCutOutIsRelief).
    const double corner = (X.row(i).head<2>().cwiseAbs() - Eigen::RowVector2d(1, 1)).norm();
    if (d > 2.0 * b.radius && X.row(i).head<2>().cwiseAbs().maxCoeff() < 0.9 && corner > 0.35)
      far_max = std::max(far_max, f[i]), far += f[i], ++n_far;
    if (f[i] > 0.05 && f[i] < 0.95) ++fractional;
  }
  std::printf("  importance: mean %.3f on the bumps' cores, mean %.3f (max %.3f) on the flat plate, %d fractional weights\n",
              inside / n_in, far / n_far, far_max, fractional);
  EXPECT_GT(inside / n_in, 0.8);
  EXPECT_LT(far / n_far, 0.1);
  EXPECT_LT(far_max, 0.3);  // the relief of the smoothed bumps reaches a little beyond their feet
  EXPECT_GT(fractional, 0) << "a continuous map, not a binary one";
  double jump = 0;  // no edge of its own: neighbours' weights differ by a fraction only
  for (auto e : b.mesh.edges()) jump = std::max(jump, std::abs(f[e.v0().idx()] - f[e.v1().idx()]));
  EXPECT_LT(jump, 0.5);
}

// A painted weight map (a weight file a user would paint) is honoured: inside its core the resize is a
// similarity (singular values equal within 5%), the plain stretch's 2:1 is gone; the box is exact and no
// face turns over. On a 48 × 48 plate and on a coarse 32 × 32 one (each core four edges across, its transition
// three): the cores' bumps make the plate's height, and the default (auto: axis-similarity on a box scale) let its
// rounds grow them ×1.15 and the box fit squeeze them back in z, 6.8% from a similarity on the 32 × 32 plate (3.0% on
// the 48 × 48 one) before such cores were held at the largest similarity the box allows (issue 25; bench/resize.md,
// thirteenth session).
TEST(ResizeSimilarity, PaintedWeightsGetSimilaritiesTheBoxIsExactAndNoFaceTurns) {
  for (int n : {48, 32}) {
    const BumpyPlate b = bumpy_plate({.n = n, .bumps = 2, .spacing = 1.0, .radius = 0.25});
    const Eigen::VectorXd f = painted(b, b.radius);
    const MatrixX3d X = positions(b.mesh);
    const MatrixX3i F = faces(b.mesh);
    for (const Vec3& s : {Vec3(2, 1, 1), Vec3(1, 2, 1), Vec3(1.5, 1, 1)}) {
      const MatrixX3d C = apply_map(scale_map(s), X);
      const MatrixX3d Y = feature_aware_resize(b.mesh, C, f);
      const auto [worst, plain, core] = core_stretch(F, X, Y, C, f);
      const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
      const Vec3 asked = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
      std::printf("  %d x %d, scale %.1f,%.1f,%.1f: %d core faces, worst s1/s2 - 1 = %.4f (plain %.3f), box error %.1e\n",
                  n, n, s.x(), s.y(), s.z(), core, worst, plain, (box - asked).cwiseAbs().maxCoeff());
      ASSERT_GT(core, 20);
      EXPECT_LT(worst, 0.05);
      EXPECT_GT(plain, s.maxCoeff() - 1.1);
      EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-9);
      EXPECT_EQ(turned_over(b.mesh, Y, C), 0);
    }
  }
}

// The split solver (default) minimizes the coupled solver's energy by alternation: on a painted plate
// stretched ×2 both land within a fraction of an edge of each other (RMS), the box exact and no face
// turned over either way.
TEST(ResizeSimilarity, SplitAndCoupledSolversAgree) {
  const BumpyPlate b = bumpy_plate({.n = small_meshes() ? 32 : 48, .bumps = 2, .spacing = 1.0, .radius = 0.25});
  const Eigen::VectorXd f = painted(b, b.radius);
  const MatrixX3d X = positions(b.mesh);
  const double h = mean_edge_length(b.mesh);
  for (const Vec3& s : {Vec3(2, 1, 1), Vec3(1, 2, 1)}) {
    const MatrixX3d C = apply_map(scale_map(s), X);
    ResizeOptions split = with(ResizeMethod::Similarity), coupled = with(ResizeMethod::Similarity);
    coupled.solver = SimilaritySolver::Coupled;
    const MatrixX3d Ys = feature_aware_resize(b.mesh, C, f, split), Yc = feature_aware_resize(b.mesh, C, f, coupled);
    const Eigen::VectorXd d = (Ys - Yc).rowwise().norm();
    const double rms = std::sqrt(d.squaredNorm() / d.size()) / h, plain = std::sqrt((C - Yc).rowwise().squaredNorm().mean()) / h;
    std::printf("  scale %.0f,%.0f,%.0f: split - coupled RMS %.3f h, max %.3f h (coupled - plain stretch RMS %.3f h)\n",
                s.x(), s.y(), s.z(), rms, d.maxCoeff() / h, plain);
    EXPECT_LT(rms, 0.25 * plain);
    EXPECT_EQ(turned_over(b.mesh, Ys, C), 0);
    const Vec3 box = (Ys.colwise().maxCoeff() - Ys.colwise().minCoeff()).transpose();
    const Vec3 asked = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
    EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-9);
  }
}

namespace {

// The default (split) solver against the coupled one on \p m (positions \p X) stretched ×2 along x and along z:
// near the coupled result (RMS under a quarter of its distance from the plain stretch), no face turned over,
// the box exact.
void expect_split_agrees_with_coupled(const Mesh& m, const MatrixX3d& X) {
  const Eigen::VectorXd f = feature_map(m).weights;
  const double h = mean_edge_length(m);
  for (const Vec3& s : {Vec3(2, 1, 1), Vec3(1, 1, 2)}) {
    const MatrixX3d C = apply_map(scale_map(s), X);
    ResizeOptions split = with(ResizeMethod::Similarity), coupled = with(ResizeMethod::Similarity);
    coupled.solver = SimilaritySolver::Coupled;
    const MatrixX3d Ys = feature_aware_resize(m, C, f, split), Yc = feature_aware_resize(m, C, f, coupled);
    const Eigen::VectorXd d = (Ys - Yc).rowwise().norm();
    const double rms = std::sqrt(d.squaredNorm() / d.size()) / h, plain = std::sqrt((C - Yc).rowwise().squaredNorm().mean()) / h;
    std::printf("  scale %.0f,%.0f,%.0f: split - coupled RMS %.3f h, max %.3f h (coupled - plain stretch RMS %.3f h)\n",
                s.x(), s.y(), s.z(), rms, d.maxCoeff() / h, plain);
    EXPECT_LT(rms, 0.25 * plain);
    EXPECT_EQ(turned_over(m, Ys, C), 0);
    const Vec3 box = (Ys.colwise().maxCoeff() - Ys.colwise().minCoeff()).transpose();
    const Vec3 asked = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
    EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-9);
  }
}

}  // namespace

// A closed shape whose box faces touch only a few spike tips: the split solver factors one matrix for x,
// y and z and adds each axis' pins back by the Woodbury identity (SplitSystem). Its result agrees with the
// coupled solver's as on the plate above (whose many rim pins keep three factors), the box is exact and
// no face turns over.
TEST(ResizeSimilarity, FewPinsShareOneFactorAndAgreeWithTheCoupledSolver) {
  const Mesh m = make_shape("spiky-sphere", 0).textured;
  const MatrixX3d X = positions(m);
  expect_split_agrees_with_coupled(m, X);
}

// The spiky sphere with its bottom cut flat: many vertices pinned along z (the flat bottom, more than
// SplitSystem shares by the Woodbury identity), a few spike tips along x and y. x and y then share one
// factor and z gets its own (two factors instead of three); the result agrees with the coupled solver's
// as above, the box is exact and no face turns over.
TEST(ResizeSimilarity, AFlatBottomsPinsGetTheirOwnFactorAndTheOtherAxesShareOne) {
  const Mesh sphere = make_shape("spiky-sphere", 0).textured;
  MatrixX3d X = positions(sphere);
  const double z0 = X.col(2).minCoeff() + 0.2 * (X.col(2).maxCoeff() - X.col(2).minCoeff());
  X.col(2) = X.col(2).cwiseMax(z0);
  Mesh m = sphere;
  set_positions(m, X);
  ASSERT_GT((X.col(2).array() == z0).count(), 64);  // the flat bottom: every vertex on it pinned along z
  expect_split_agrees_with_coupled(m, X);
}

// The default map on the tentacle stick ×2 along its axis (tentacles stick out in every direction): no face turned over against the plain stretch, the box exact, and the detail-weighted
// anisotropy log(s1/s2) (weights: area × how far a face stands out of a smoothed copy, not the map) at
// most half the plain stretch's.
TEST(ResizeSimilarity, TentacleStickNoFaceTurnsAndDetailKeepsItsShape) {
  const TexturedShape shape = tentacle_stick(0);
  const Mesh& m = shape.textured;
  const MatrixX3d X = positions(m);
  const MatrixX3i F = faces(m);
  const FeatureMap fm = feature_map(m);
  const BoundingBox box = bounding_box(m);
  const Eigen::VectorXd area = face_areas(m);
  // Detail independent of the map: how far each vertex stands out of a smoothed copy (40 lazy umbrella steps).
  MatrixX3d S = X;
  for (int step = 0; step < 40; ++step) {
    MatrixX3d next = S;
    for (auto v : m.vertices()) {
      Vec3 acc = Vec3::Zero();
      int k = 0;
      for (auto u : m.vv_range(v)) acc += S.row(u.idx()).transpose(), ++k;
      if (k > 0) next.row(v.idx()) = 0.5 * S.row(v.idx()) + 0.5 * acc.transpose() / k;
    }
    S = next;
  }
  const Eigen::VectorXd detail = (X - S).rowwise().norm();
  for (const Vec3& s : {Vec3(2, 1, 1)}) {  // (1, 1, 2): 0.26 of the plain stretch's, 0 turned (bench/resize.md)
    const MatrixX3d C = apply_map(scale_map(s, box.center()), X);
    const MatrixX3d Y = feature_aware_resize(m, C, fm.weights);
    double a_out = 0, a_plain = 0;
    for (Eigen::Index k = 0; k < F.rows(); ++k) {
      const double w = area[k] * (detail[F(k, 0)] + detail[F(k, 1)] + detail[F(k, 2)]);
      const Eigen::Vector2d sv = face_stretch(F, X, Y, k), sp = face_stretch(F, X, C, k);
      a_out += w * std::log(sv[0] / sv[1]);
      a_plain += w * std::log(sp[0] / sp[1]);
    }
    const Vec3 ext = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
    std::printf("  stick x%.0f,%.0f,%.0f: weighted anisotropy %.3f of the plain stretch's, %d faces turned\n", s.x(),
                s.y(), s.z(), a_out / a_plain, turned_over(m, Y, C));
    EXPECT_EQ(turned_over(m, Y, C), 0);
    EXPECT_LT((ext - box.size().cwiseProduct(s)).cwiseAbs().maxCoeff(), 1e-9 * box.size().maxCoeff());
    EXPECT_LT(a_out, 0.5 * a_plain);
  }
}

// A painted weight file is honoured by the command line as by the library.
TEST(ResizeCli, PaintedWeightFileIsHonoured) {
  TempDir tmp;
  const BumpyPlate b = bumpy_plate({.n = 30, .bumps = 2, .spacing = 1.0, .radius = 0.25});
  write_mesh(b.mesh, tmp / "b.ply");
  const Eigen::VectorXd f = painted(b, b.radius);
  std::string text;
  for (Eigen::Index i = 0; i < f.size(); ++i) text += fmt::format("{}\n", f[i]);
  geotex::test::write_file(tmp / "paint.txt", text);
  const auto r = geotex::test::run_cli("resize " + tmp / "b.ply" + " -o " + tmp / "r.ply" + " --scale 2,1,1 --features " +
                                       tmp / "paint.txt" + " --save-features " + tmp / "saved.txt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const MatrixX3d expected = feature_aware_resize(b.mesh, scale_map({2, 1, 1}, bounding_box(b.mesh).center()), f);
  EXPECT_LT((positions(read_mesh(tmp / "r.ply")) - expected).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(geotex::test::read_file(tmp / "saved.txt"), text);  // the weights used are the ones painted
}

TEST(Resize, ThesisOnAFanSolvesEquation93AsWritten) {
  // A fan of 700 triangles around one vertex: the apex's Laplacian row couples all 700 rim vertices,
  // a dense 700 x 700 block in LᵀFL (10^5: 3.7 GB, issue 30) that the least-squares solver keeps out of
  // its factor. The result is still the least-squares solution of Eq. (9.3), by dense QR.
  const int k = 700, n = k + 1;
  MatrixX3d X(n, 3);
  MatrixX3i F(k, 3);
  X.row(0) << 0, 0, 0.3;
  for (int i = 0; i < k; ++i) {
    const double t = 2 * M_PI * i / k;
    X.row(1 + i) << std::cos(t), std::sin(t), 0.05 * std::sin(5 * t);
    F.row(i) << 0, 1 + i, 1 + (i + 1) % k;
  }
  const Mesh m = make_mesh(X, F);
  ASSERT_EQ(static_cast<int>(m.n_faces()), k);
  const MatrixX3d C = apply_map(twist_map(0.8), apply_map(scale_map({1.7, 1.0, 0.8}), X));
  Eigen::VectorXd f(n);
  for (int i = 0; i < n; ++i) f[i] = 0.5 + 0.45 * std::sin(3.0 * i);
  ResizeOptions o;
  ResizeOptions::table().apply_preset(o, "thesis");
  const MatrixX3d Y = feature_aware_resize(m, C, f, o);
  const Eigen::MatrixXd L = Eigen::MatrixXd(umbrella_laplacian(m));
  const std::vector<Similarity> T = one_ring_similarities(m, X, C, !o.keep_feature_size);
  const MatrixX3d D = L * X;
  MatrixX3d Dt(n, 3);
  for (int i = 0; i < n; ++i) Dt.row(i) = (T[i].linear() * D.row(i).transpose()).transpose();
  const Eigen::VectorXd wp = o.position_weight * (Eigen::VectorXd::Ones(n) - f);
  Eigen::MatrixXd A(2 * n, n), B(2 * n, 3);
  A << f.asDiagonal() * L, Eigen::MatrixXd(wp.asDiagonal());
  B << f.asDiagonal() * Dt, wp.asDiagonal() * C;
  const Eigen::MatrixXd ref = A.colPivHouseholderQr().solve(B);
  EXPECT_LT((Y - ref).cwiseAbs().maxCoeff(), 1e-6 * ref.cwiseAbs().maxCoeff());
}

// ---------------------------------------------------------------------------------------------
// The axis warp (axis_warp.h): separable, monotone, the box exact; important regions scale uniformly.

namespace {

// The solved warp's own properties: every σ_{a,m} ≥ s_min (so g_a increases), ∫ σ_a = λ_a L_a.
void expect_warp_feasible(const AxisWarp& w, const Mesh& m, const Vec3& s, const AxisWarpOptions& o) {
  const MatrixX3d X = positions(m);
  const Vec3 ext = (X.colwise().maxCoeff() - X.colwise().minCoeff()).transpose();
  for (int a = 0; a < 3; ++a) {
    if (w.scales[a].size() == 0) continue;
    EXPECT_GE(w.scales[a].minCoeff(), o.min_scale * s.minCoeff() * (1 - 1e-12)) << "axis " << a;
    EXPECT_NEAR(w.length(a), s[a] * ext[a], 1e-12 * ext[a]) << "axis " << a;
    EXPECT_NEAR(w.map(a, X.col(a).maxCoeff()) - w.map(a, X.col(a).minCoeff()), s[a] * ext[a], 1e-12 * ext[a]);
  }
}

}  // namespace

// No face turns over and each coordinate's order is kept even at ×3 with weights 0 and 1 side by side;
// the box is exact and the QP's constraint and bounds hold.
TEST(ResizeAxis, MonotoneNoFaceTurnsAndTheBoxIsExactAtThreeTimes) {
  const BumpyPlate b = bumpy_plate({.n = 40, .bumps = 2, .spacing = 1.0, .radius = 0.25});
  const MatrixX3d X = positions(b.mesh);
  const Eigen::VectorXd f = b.truth;  // binary: the strongest contrast a map can have
  ResizeOptions o = with(ResizeMethod::Axis);
  for (const Vec3& s : {Vec3(3, 1, 1), Vec3(1, 3, 1), Vec3(1, 1, 3), Vec3(3, 1.5, 1)}) {
    const MatrixX3d C = apply_map(scale_map(s), X);
    const MatrixX3d Y = feature_aware_resize(b.mesh, C, f, o);
    EXPECT_EQ(turned_over(b.mesh, Y, C), 0);
    for (int a = 0; a < 3; ++a)
      for (Eigen::Index i = 0; i < X.rows(); ++i)
        for (Eigen::Index j : {Eigen::Index(0), X.rows() / 2, X.rows() - 1})
          if (X(i, a) < X(j, a)) EXPECT_LE(Y(i, a), Y(j, a));
    const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
    const Vec3 asked = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
    EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((Y.colwise().minCoeff() - C.colwise().minCoeff()).cwiseAbs().maxCoeff(), 1e-12);
    Vec3 lambda, lo;
    ASSERT_TRUE(box_scale_of(X, C, lambda, lo));
    EXPECT_LT((lambda - s).cwiseAbs().maxCoeff(), 1e-12);
    expect_warp_feasible(axis_warp(b.mesh, lambda, lo, f, o.axis), b.mesh, s, o.axis);
  }
}

// Painted bumps stretched sideways (×2 along x, the plate's plane): inside their core the warp is a
// similarity (singular values equal within 5%, the plain stretch's are 2:1), and stays one after
// axis-similarity's similarity stage (no face turned either); two bumps at the same
// height stay level (the same y and the same top); no importance at all gives the plain map.
TEST(ResizeAxis, PaintedBumpsGetSimilaritiesAndStayLevel) {
  // Room between the painted columns (a separable warp stretches whole slabs): footprints of radius 0.15.
  const BumpyPlate b = bumpy_plate({.n = 64, .bumps = 2, .spacing = 1.0, .radius = 0.15});
  const Eigen::VectorXd f = painted(b, b.radius);
  const MatrixX3d X = positions(b.mesh);
  const MatrixX3i F = faces(b.mesh);
  const MatrixX3d C = apply_map(scale_map({2, 1, 1}), X);
  const MatrixX3d Y = feature_aware_resize(b.mesh, C, f, with(ResizeMethod::Axis));
  for (auto method : {ResizeMethod::Axis, ResizeMethod::AxisSimilarity}) {  // the similarity stage keeps it
    const MatrixX3d Ym = method == ResizeMethod::Axis ? Y : feature_aware_resize(b.mesh, C, f, with(method));
    const auto [worst, plain, core] = core_stretch(F, X, Ym, C, f);
    std::printf("  %s ×2 x: %d core faces, worst s1/s2 - 1 = %.4f (plain %.3f)\n",
                enum_name(resize_method_names(), method).c_str(), core, worst, plain);
    ASSERT_GT(core, 20);
    EXPECT_LT(worst, 0.05);
    EXPECT_GT(plain, 0.9);
    EXPECT_EQ(turned_over(b.mesh, Ym, C), 0);
  }
  // The bumps with centres at the same y (a row of the 2 × 2 grid) keep equal centre y and equal tops.
  for (int r = 0; r < 2; ++r) {
    std::vector<double> ys, tops;
    for (const Vec3& c : b.centres) {
      if (std::abs(c.y() - b.centres[2 * r].y()) > 1e-9) continue;
      Eigen::Index best = 0;
      for (Eigen::Index i = 0; i < X.rows(); ++i)
        if ((X.row(i).head<2>() - c.head<2>().transpose()).norm() < (X.row(best).head<2>() - c.head<2>().transpose()).norm())
          best = i;
      ys.push_back(Y(best, 1)), tops.push_back(Y(best, 2));
    }
    ASSERT_EQ(ys.size(), 2u);
    EXPECT_NEAR(ys[0], ys[1], 1e-12);
    EXPECT_NEAR(tops[0], tops[1], 1e-12);
  }
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(X.rows());
  EXPECT_LT((feature_aware_resize(b.mesh, C, none, with(ResizeMethod::Axis)) - C).cwiseAbs().maxCoeff(), 1e-12);
}

// A painted region keeps its size: a sphere with its top cap painted, stretched ×2 up, keeps the cap's
// height and width (within 5%) while the plain stretch doubles its height; the unpainted part takes the
// stretch. Axis followed by similarity keeps the box and turns no face either.
TEST(ResizeAxis, APaintedCapKeepsItsSize) {
  const Mesh m = icosphere(4);
  const MatrixX3d X = positions(m);
  Eigen::VectorXd f(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) f[i] = std::clamp((X(i, 2) - 0.5) / 0.2, 0.0, 1.0);
  const MatrixX3d C = apply_map(scale_map({1, 1, 2}), X);
  for (auto method : {ResizeMethod::Axis, ResizeMethod::AxisSimilarity}) {
    const MatrixX3d Y = feature_aware_resize(m, C, f, with(method));
    double h0 = 0, h = 0, w0 = 0, w = 0;  // the fully painted cap's height and width, before and after
    double zmin0 = 1e9, zmin = 1e9, xmin = 1e9, xmax = -1e9, xmin0 = 1e9, xmax0 = -1e9;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
      if (f[i] < 1.0) continue;
      zmin0 = std::min(zmin0, X(i, 2)), zmin = std::min(zmin, Y(i, 2));
      xmin0 = std::min(xmin0, X(i, 0)), xmax0 = std::max(xmax0, X(i, 0));
      xmin = std::min(xmin, Y(i, 0)), xmax = std::max(xmax, Y(i, 0));
    }
    h0 = X.col(2).maxCoeff() - zmin0, h = Y.col(2).maxCoeff() - zmin;
    w0 = xmax0 - xmin0, w = xmax - xmin;
    std::printf("  %s: painted cap height %.3f -> %.3f, width %.3f -> %.3f\n",
                enum_name(resize_method_names(), method).c_str(), h0, h, w0, w);
    EXPECT_NEAR(h / h0, 1.0, 0.05);
    EXPECT_NEAR(w / w0, 1.0, 0.05);
    const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
    EXPECT_LT((box - Vec3(2, 2, 4)).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_EQ(turned_over(m, Y, C), 0);
  }
}

// No face turned over against the plain stretch on the shared models where the axis methods turned some
// (bench/resize.md, eleventh session): the beetle's skinny faces across cells of different slope (the warp
// alone: 2 at ×2 y, 3 at ×2 z; it now smooths its slope over the cells they span), and igea ×2 y, where
// the similarity stage after the warp turned 8 (it now follows the warp's edges with the follow weight and
// counts a face turned against the plain stretch too). The box stays exact.
TEST(ResizeAxis, NoFaceTurnsOnTheSharedModelsThatTurnedThem) {
  GEOTEX_REQUIRE_DATA();
  struct Run {
    const char* model;
    Vec3 scale;
    ResizeMethod method;
  };
  const Run runs[] = {{"beetle.obj", {1, 2, 1}, ResizeMethod::Axis},
                      {"beetle.obj", {1, 1, 2}, ResizeMethod::Axis},
                      {"beetle.obj", {1, 2, 1}, ResizeMethod::AxisSimilarity},
                      {"beetle.obj", {1, 1, 2}, ResizeMethod::AxisSimilarity},
                      {"igea.ply", {1, 2, 1}, ResizeMethod::AxisSimilarity}};
  for (const Run& r : runs) {
    const Mesh m = read_mesh(geotex::test::data_dir() / r.model);
    ResizeRunOptions o;
    o.map.scale = r.scale;
    o.resize.method = r.method;
    const ResizeResult res = resize_mesh(m, o);
    const int turned = turned_over(m, res.V, res.mapped);
    std::printf("  %s x(%g, %g, %g) %s: %d turned\n", r.model, r.scale.x(), r.scale.y(), r.scale.z(),
                enum_name(resize_method_names(), r.method).c_str(), turned);
    EXPECT_EQ(turned, 0) << r.model;
    const Vec3 box = (res.V.colwise().maxCoeff() - res.V.colwise().minCoeff()).transpose();
    const Vec3 asked = (res.mapped.colwise().maxCoeff() - res.mapped.colwise().minCoeff()).transpose();
    EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-9 * asked.norm()) << r.model;
  }
}

// axis_max_scale bounds every cell's stretch: on the tentacle stick ×2 across (its end slabs hold only
// tentacles and take σ above 4 without a bound), every σ_y ≤ 1.5 · 2 with max_scale 1.5, the lower bound and
// the box still hold, and no face turns.
TEST(ResizeAxis, MaxScaleBoundsEveryCellsStretch) {
  const TexturedShape s = tentacle_stick(1);
  const Mesh& m = s.textured;
  const MatrixX3d X = positions(m);
  const Eigen::VectorXd f = feature_map(m).weights;
  const Vec3 scale(1, 2, 1);
  const MatrixX3d C = apply_map(scale_map(scale, bounding_box(m).center()), X);
  Vec3 lambda, lo;
  ASSERT_TRUE(box_scale_of(X, C, lambda, lo));
  AxisWarpOptions capped;
  capped.max_scale = 1.5;
  const AxisWarp free = axis_warp(m, lambda, lo, f), bounded = axis_warp(m, lambda, lo, f, capped);
  std::printf("  stick x2 y: largest sigma_y %.3f without a bound, %.3f with max_scale 1.5\n", free.scales[1].maxCoeff(),
              bounded.scales[1].maxCoeff());
  EXPECT_GT(free.scales[1].maxCoeff(), 3.5);
  for (int a = 0; a < 3; ++a) EXPECT_LE(bounded.scales[a].maxCoeff(), 1.5 * lambda[a] * (1 + 1e-9)) << "axis " << a;
  expect_warp_feasible(bounded, m, scale, capped);
  EXPECT_EQ(turned_over(m, bounded.apply(X), C), 0);
}

// Faces across the stretch take it for free: a comb of important square plates across x (normals along x: no face
// of them changes under any σ_x) for x in [0, 1], then an important plate lying along x (normal along z) for x in
// [1, 2], stretched ×2 along x. The exact optimum of the anisotropy and in-plane size terms puts all of the stretch
// into the comb (σ_x = 3 there, 1 along the plate, as the pull to the plain stretch goes to 0); the size term that
// counts every axis fully makes the comb's plates resist σ_x by their area (50 times the plate's) and stretches the
// plate instead.
TEST(ResizeAxis, FacesAcrossTheStretchTakeItForFree) {
  const int plates = 50, n = 4;
  std::vector<Vec3> V;
  std::vector<Eigen::Vector3i> F;
  auto add_grid = [&](const Vec3& origin, const Vec3& u, const Vec3& v) {
    const int base = static_cast<int>(V.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) V.push_back(origin + u * (double(i) / n) + v * (double(j) / n));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const int a = base + j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
        F.emplace_back(a, b, d), F.emplace_back(a, d, c);
      }
  };
  for (int k = 0; k < plates; ++k) add_grid(Vec3(double(k) / plates, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1));
  add_grid(Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
  MatrixX3d X(V.size(), 3);
  MatrixX3i Fm(F.size(), 3);
  for (std::size_t i = 0; i < V.size(); ++i) X.row(i) = V[i].transpose();
  for (std::size_t k = 0; k < F.size(); ++k) Fm.row(k) = F[k].transpose();
  const Mesh m = make_mesh(X, Fm);
  const Eigen::VectorXd f = Eigen::VectorXd::Ones(m.n_vertices());
  const Vec3 scale(2, 1, 1), lo = X.colwise().minCoeff().transpose();
  AxisWarpOptions o;
  o.plain_weight = 1e-5;  // the weak pull to the plain stretch (1e-3) would hold the plate at σ_x 1.14
  AxisWarpOptions every_axis = o;
  every_axis.in_plane_size = false;
  const AxisWarp in_plane = axis_warp(m, scale, lo, f, o), full = axis_warp(m, scale, lo, f, every_axis);
  // σ_x = g_x' over the middle half of each part, away from the C¹ transition at x = 1.
  auto slope = [](const AxisWarp& w, double x0, double x1) { return (w.map(0, x1) - w.map(0, x0)) / (x1 - x0); };
  const double comb = slope(in_plane, 0.25, 0.75), plate = slope(in_plane, 1.25, 1.75);
  const double full_comb = slope(full, 0.25, 0.75), full_plate = slope(full, 1.25, 1.75);
  std::printf("  comb | plate: sigma_x %.3f | %.3f in the plane, %.3f | %.3f every axis\n", comb, plate, full_comb,
              full_plate);
  EXPECT_NEAR(plate, 1.0, 0.05);
  EXPECT_GT(comb, 2.9);  // the comb takes (nearly) all of the stretch: 4 − 1 over a length of 1
  EXPECT_GT(full_plate - 1, 10 * (plate - 1));
  // The plate keeps its shape (the plain stretch doubles it along x): every face beyond the transition (x ≥ 1.25)
  // has singular values equal within 5%.
  const MatrixX3d Y = in_plane.apply(X);
  for (Eigen::Index k = plates * 2 * n * n; k < Fm.rows(); ++k) {
    if (X(Fm(k, 0), 0) + X(Fm(k, 1), 0) + X(Fm(k, 2), 0) < 3 * 1.25) continue;
    const Eigen::Vector2d s = face_stretch(Fm, X, Y, k);
    EXPECT_LT(s[0] / s[1] - 1, 0.05) << "face " << k;
  }
  expect_warp_feasible(in_plane, m, scale, o);
  expect_warp_feasible(full, m, scale, every_axis);
}

// Stretch hidden off the axes: a flat plate over [−1, 1]² with a band of half importance along its diagonal (0.5
// within 0.15 of the line y = x and 1 of the plate's centre, falling smoothly to 0 over 0.2), stretched ×2 along x.
// Nearly every x slab holds a part of the band, so the axis warp cannot spare it; it can only stay similar if it
// turns and scales as a whole while the unimportant triangles beside it take the stretch across the axes. An edge of
// half importance weighs its similarity (f² = 0.25) against its pull to the warp's stretch (β): with that pull
// falling off with importance (follow_falloff), the band's core is nearer a similarity (lower mean and largest
// log(s1 / s2)) than with every edge following the warp (follow_falloff 0, the stage before), the rest takes more
// anisotropy than with every edge following and than the plain stretch, the box is exact and no face turns.
TEST(ResizeAxis, AHalfImportantDiagonalBandFollowsItsSimilarityNotTheWarp) {
  const BumpyPlate b = bumpy_plate({.n = 40, .bumps = 0});
  const Mesh& m = b.mesh;
  const MatrixX3d X = positions(m);
  const MatrixX3i F = faces(m);
  auto smooth = [](double t) {
    t = std::clamp(t, 0.0, 1.0);
    return t * t * (3 - 2 * t);
  };
  Eigen::VectorXd f(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double across = std::abs(X(i, 0) - X(i, 1)) / std::sqrt(2.0), along = std::abs(X(i, 0) + X(i, 1)) / std::sqrt(2.0);
    f[i] = 0.5 * smooth((0.35 - across) / 0.2) * smooth((1.2 - along) / 0.2);
  }
  const MatrixX3d C = apply_map(scale_map({2, 1, 1}), X);
  ResizeOptions falloff = with(ResizeMethod::AxisSimilarity), every_edge = falloff;
  ASSERT_GT(falloff.axis.follow_falloff, 0);
  every_edge.axis.follow_falloff = 0;
  const MatrixX3d Y = feature_aware_resize(m, C, f, falloff), Y0 = feature_aware_resize(m, C, f, every_edge);
  // Area-weighted mean and largest log(s1 / s2) of \p P over the faces whose corners' weights all pass \p keep.
  auto anisotropy = [&](const MatrixX3d& P, auto keep) {
    double sum = 0, area = 0, worst = 0;
    for (Eigen::Index k = 0; k < F.rows(); ++k) {
      if (!keep(f[F(k, 0)]) || !keep(f[F(k, 1)]) || !keep(f[F(k, 2)])) continue;
      const double a = 0.5 * (X.row(F(k, 1)) - X.row(F(k, 0))).cross(X.row(F(k, 2)) - X.row(F(k, 0))).norm();
      const Eigen::Vector2d s = face_stretch(F, X, P, k);
      sum += a * std::log(s[0] / s[1]), area += a, worst = std::max(worst, std::log(s[0] / s[1]));
    }
    return std::array<double, 3>{sum / area, worst, area};
  };
  auto core = [](double w) { return w >= 0.5 - 1e-12; };
  auto rest = [](double w) { return w <= 0; };
  const auto band = anisotropy(Y, core), band0 = anisotropy(Y0, core), plain = anisotropy(C, core);
  const double rest1 = anisotropy(Y, rest)[0], rest0 = anisotropy(Y0, rest)[0], rest_plain = anisotropy(C, rest)[0];
  std::printf("  band core log(s1/s2): mean %.4f / largest %.4f with the falloff, %.4f / %.4f every edge (plain "
              "%.3f); rest: mean %.3f, %.3f every edge, plain %.3f\n",
              band[0], band[1], band0[0], band0[1], plain[0], rest1, rest0, rest_plain);
  ASSERT_GT(band[2], 0.2);  // the core covers a fair share of the plate (area 4)
  EXPECT_LT(band[0], band0[0]);
  EXPECT_LT(band[1], band0[1]);
  EXPECT_LT(band[0], 0.25 * plain[0]);
  EXPECT_GT(rest1, rest0);
  EXPECT_GT(rest1, rest_plain);
  for (const MatrixX3d* P : {&Y, &Y0}) {
    EXPECT_EQ(turned_over(m, *P, C), 0);
    const Vec3 box = (P->colwise().maxCoeff() - P->colwise().minCoeff()).transpose();
    const Vec3 asked = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
    EXPECT_LT((box - asked).head<2>().cwiseAbs().maxCoeff(), 1e-12);
  }
}

// A bend, twist or deformed copy that is not a box scale is refused by the axis methods.
TEST(ResizeAxis, RefusesMapsThatAreNotABoxScale) {
  const BumpyPlate b = bumpy_plate({.n = 20});
  const MatrixX3d X = positions(b.mesh);
  const Eigen::VectorXd f = b.truth;
  for (const SpaceMap& map : {bend_map(1.5), twist_map(1.0)}) {
    const MatrixX3d C = apply_map(map, X);
    Vec3 s, lo;
    EXPECT_FALSE(box_scale_of(X, C, s, lo));
    for (auto method : {ResizeMethod::Axis, ResizeMethod::AxisSimilarity})
      EXPECT_THROW(feature_aware_resize(b.mesh, C, f, with(method)), InvalidInput);
  }
}

// The worst tentacle of the stick \p s (its tentacles \p info) between X and Y: {|length / length₀ − 1|,
// |lean − lean₀| in degrees}, measured on each tentacle's true foot ring as in
// FeatureMap.TentaclesKeepLengthAndAngleOnTheStretchedArc.
std::array<double, 2> worst_tentacle_change(const TexturedShape& s, const std::vector<Tentacle>& info,
                                            const MatrixX3d& X, const MatrixX3d& Y) {
  std::array<double, 2> w{0, 0};
  for (const Tentacle& t : info) {
    const Eigen::VectorXd foot = tentacle_truth(s.base, {t}, TentacleOptions{}.radius);
    const ProtrusionPose a = measure_protrusion(s.textured, X, t.foot, foot), b = measure_protrusion(s.textured, Y, t.foot, foot);
    w[0] = std::max(w[0], std::abs(b.length / a.length - 1));
    w[1] = std::max(w[1], std::abs(b.angle_deg - a.angle_deg));
  }
  return w;
}

// The tentacle stick (issue 25) ×2 along x, y and z with its automatic importance map. With the slab term
// (axis_slab_weight), the slabs beyond the stick's body, which hold only tentacles, keep the scale 1
// (without it they take 2–7: little area, so cheap), and axis-similarity keeps the tentacles' lengths
// better than the similarity method's per-vertex similarities (rigid_protrusions off): within 5% along the stick (×2 x), far closer across it (×2 y, z,
// where the box's extremes are tentacle tips). Worst tentacle, measured on its foot ring as in
// FeatureMap.TentaclesKeepLengthAndAngleOnTheStretchedArc.
TEST(ResizeAxis, FullSlabsKeepTheirScaleAndTheTentaclesTheirLength) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(1, &info);
  const Mesh& m = s.textured;
  const MatrixX3d X = positions(m);
  const Eigen::VectorXd f = feature_map(m).weights;
  auto worst = [&](const MatrixX3d& Y) { return worst_tentacle_change(s, info, X, Y); };
  ResizeOptions slab = with(ResizeMethod::AxisSimilarity);
  slab.axis.slab_weight = 1;
  // The slab term as tuned in the tenth session, with the similarity stage's β of then (0.002): at the
  // follow weight's default 0.03 the stick ×2 x measures 5.9% / 6.7 deg (bench/resize.md, eleventh session).
  slab.axis.follow_weight = 0.002;
  slab.rigid_protrusions = false;  // the warp's slabs alone (rigid protrusions: the test below)
  for (int a = 0; a < 3; ++a) {
    Vec3 scale = Vec3::Ones();
    scale[a] = 2;
    const MatrixX3d C = apply_map(scale_map(scale, bounding_box(m).center()), X);
    Vec3 lambda, lo;
    ASSERT_TRUE(box_scale_of(X, C, lambda, lo));
    if (a == 1) {  // the warp itself across the stick: nodes whose half-cell neighbourhood holds only tentacle
      const AxisWarp with_slabs = axis_warp(m, lambda, lo, f, slab.axis), without = axis_warp(m, lambda, lo, f);
      double off = 0, off_without = 0;
      int full = 0;
      for (Eigen::Index k = 0; k < with_slabs.scales[a].size(); ++k) {
        const double t = with_slabs.lo[a] + k * with_slabs.step[a];
        double sum = 0, count = 0;
        for (Eigen::Index i = 0; i < X.rows(); ++i)
          if (std::abs(X(i, a) - t) <= 0.5 * with_slabs.step[a]) sum += f[i], count += 1;
        if (count == 0 || sum / count < 0.999) continue;
        ++full;
        off = std::max(off, std::abs(with_slabs.scales[a][k] - 1));
        off_without = std::max(off_without, std::abs(without.scales[a][k] - 1));
      }
      std::printf("  stick x2 y: %d full nodes, worst |sigma - 1| %.3f with the slab term, %.3f without\n", full, off,
                  off_without);
      EXPECT_GE(full, 4);
      EXPECT_LT(off, 0.05);
      EXPECT_GT(off_without, 0.5);
    }
    // The similarity method's own per-vertex similarities (no rigid protrusions).
    ResizeOptions per_vertex = with(ResizeMethod::Similarity);
    per_vertex.rigid_protrusions = false;
    const MatrixX3d Ys = feature_aware_resize(m, C, f, per_vertex), Ya = feature_aware_resize(m, C, f, slab);
    const auto p = worst(C), rs = worst(Ys), ra = worst(Ya);
    std::printf("  stick x2 %c, worst tentacle length / lean change: plain %.1f%% / %.1f deg, similarity %.1f%% / %.1f deg, "
                "axis-similarity with slabs %.1f%% / %.1f deg\n",
                "xyz"[a], 100 * p[0], p[1], 100 * rs[0], rs[1], 100 * ra[0], ra[1]);
    EXPECT_EQ(turned_over(m, Ya, C), 0);
    EXPECT_LT(ra[0], a == 0 ? 0.05 : 0.6 * rs[0]);
    const Vec3 box = (Ya.colwise().maxCoeff() - Ya.colwise().minCoeff()).transpose();
    EXPECT_LT((box - (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose()).cwiseAbs().maxCoeff(), 1e-9);
  }
}

// Issue 25: the tentacle stick ×2 along x, y and z (levels 0 and 1: 9k and 38k vertices) with its automatic
// importance map and rigid protrusions, which are the default. Every tentacle is found (its true footprint
// inside one protrusion), keeps its length within 3% and its lean to its foot ring within 3° (measured on the
// true foot ring, as in FeatureMap.TentaclesKeepLengthAndAngleOnTheStretchedArc), no face turns over against the
// plain stretch, and the box is the asked one, with no options (auto: axis-similarity) and under similarity and
// axis-similarity. The methods' per-vertex similarities alone miss this on every axis (level 1, similarity:
// 2.1% / 4.1°, 79.4% / 16.4°, 66.0% / 16.7°; axis-similarity: up to 162% / 20°).
TEST(ResizeSimilarity, RigidProtrusionsKeepEveryTentaclesLengthAndLeanOnEveryAxis) {
  for (int level : {0, 1}) {
    std::vector<Tentacle> info;
    const TexturedShape s = tentacle_stick(level, &info);
    const Mesh& m = s.textured;
    const MatrixX3d X = positions(m);
    const Eigen::VectorXd f = feature_map(m).weights;
    const double radius = TentacleOptions{}.radius;
    const std::vector<RigidProtrusion> found = find_protrusions(m, X, f);
    int covered = 0;  // tentacles whose true footprint lies inside one found protrusion
    for (const Tentacle& t : info) {
      const Eigen::VectorXd foot = tentacle_truth(s.base, {t}, radius);
      for (const RigidProtrusion& p : found) {
        std::vector<char> in(X.rows(), 0);
        for (int v : p.vertices) in[v] = 1;
        int missing = 0, inside = 0;
        for (Eigen::Index i = 0; i < X.rows(); ++i) missing += foot[i] != 0 && !in[i], inside += foot[i] != 0 && in[i];
        covered += inside > 0 && missing == 0;
      }
    }
    std::printf("  stick level %d: %zu protrusions found, %d of %zu true footprints inside one\n", level, found.size(),
                covered, info.size());
    EXPECT_EQ(found.size(), info.size());
    EXPECT_EQ(covered, static_cast<int>(info.size()));
    auto worst = [&](const MatrixX3d& Y) { return worst_tentacle_change(s, info, X, Y); };
    for (int a = 0; a < 3; ++a) {  // no options at all: the default
      Vec3 scale = Vec3::Ones();
      scale[a] = 2;
      const MatrixX3d C = apply_map(scale_map(scale, bounding_box(m).center()), X);
      const MatrixX3d Y = feature_aware_resize(m, C, f);
      const auto r = worst(Y);
      const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
      const Vec3 want = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
      std::printf("  defaults, stick level %d x2 %c, worst tentacle length / lean change: %.2f%% / %.2f deg; turned %d, "
                  "box error %.1e\n", level, "xyz"[a], 100 * r[0], r[1], turned_over(m, Y, C),
                  (box - want).cwiseAbs().maxCoeff());
      EXPECT_LT(r[0], 0.03);
      EXPECT_LT(r[1], 3.0);
      EXPECT_EQ(turned_over(m, Y, C), 0);
      EXPECT_LT((box - want).cwiseAbs().maxCoeff(), 1e-9);
    }
    for (ResizeMethod method : {ResizeMethod::Similarity, ResizeMethod::AxisSimilarity})
    for (int a = 0; a < 3; ++a) {
      ResizeOptions rigid, without;
      rigid.method = without.method = method;
      rigid.rigid_protrusions = true;
      without.rigid_protrusions = false;
      Vec3 scale = Vec3::Ones();
      scale[a] = 2;
      const MatrixX3d C = apply_map(scale_map(scale, bounding_box(m).center()), X);
      const MatrixX3d Y = feature_aware_resize(m, C, f, rigid), Y0 = feature_aware_resize(m, C, f, without);
      const auto r = worst(Y), r0 = worst(Y0);
      const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
      const Vec3 want = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
      std::printf("  %s, stick level %d x2 %c, worst tentacle length / lean change: rigid protrusions %.2f%% / %.2f "
                  "deg, without %.1f%% / %.1f deg; turned %d, box error %.1e\n",
                  method == ResizeMethod::Similarity ? "similarity" : "axis-similarity", level, "xyz"[a], 100 * r[0],
                  r[1], 100 * r0[0], r0[1], turned_over(m, Y, C), (box - want).cwiseAbs().maxCoeff());
      EXPECT_LT(r[0], 0.03);
      EXPECT_LT(r[1], 3.0);
      EXPECT_EQ(turned_over(m, Y, C), 0);
      EXPECT_LT((box - want).cwiseAbs().maxCoeff(), 1e-9);
      EXPECT_LT((Y.colwise().minCoeff() - C.colwise().minCoeff()).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

// Issue 25: a cheburashka-like head, a sphere with two ears that are the box's x extremes and span more than
// half its width (57%), ×2 along x. Holding the ears at their size in the box would need the head to take
// more than the asked stretch; where the head is important (painted 0.8, the ears 1) the rigid placement
// gives no such room: the result is the method's own (rigid_protrusions off), the head's width at most the
// plain stretch's, and no face turned. Placed regardless (the placement's own steps), the head takes > 1.3×
// the asked stretch, so the test could fail. With an unimportant head (painted 0.1) the ears are placed at
// their size (the head, stretchable, takes the room) and the box is exact.
TEST(ResizeSimilarity, RigidProtrusionsGiveNoRoomFromAnImportantHead) {
  const Mesh sphere = icosphere(4);
  const MatrixX3d S = positions(sphere);
  std::vector<int> feet;
  for (double side : {-1.0, 1.0}) {
    Eigen::Index best;
    (S.rowwise() - Eigen::RowVector3d(side, 0, 0)).rowwise().squaredNorm().minCoeff(&best);
    feet.push_back(static_cast<int>(best));
  }
  std::vector<Tentacle> info;
  const TexturedShape ears = tentacles(sphere, {}, feet, {Vec3::UnitY(), Vec3::UnitY()}, {0.0, 0.0}, &info);
  const Mesh& m = ears.textured;
  const MatrixX3d X = positions(m);
  const Vec3 lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  std::vector<int> head;  // the sphere the ears grow from
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (X.row(i).norm() < 1.02) head.push_back(static_cast<int>(i));
  auto head_width = [&](const MatrixX3d& Y) {
    double a = 1e300, b = -1e300;
    for (int v : head) a = std::min(a, Y(v, 0)), b = std::max(b, Y(v, 0));
    return b - a;
  };
  auto painted_head = [&](double head_weight) {
    Eigen::VectorXd f(X.rows());
    for (Eigen::Index i = 0; i < X.rows(); ++i) f[i] = std::abs(X(i, 0)) > 1.15 ? 1.0 : head_weight;
    return f;
  };
  const MatrixX3d C = apply_map(scale_map({2, 1, 1}, bounding_box(m).center()), X);
  const double ear_share = 1 - 2.0 / (hi.x() - lo.x());  // the head: the unit sphere
  std::printf("  ears: %.0f%% of the width, %zu head vertices\n", 100 * ear_share, head.size());
  ASSERT_GT(ear_share, 0.5);
  for (double head_weight : {0.8, 0.1}) {
    const Eigen::VectorXd f = painted_head(head_weight);
    const std::vector<RigidProtrusion> found = find_protrusions(m, X, f);
    ASSERT_EQ(found.size(), 2u) << head_weight;
    ResizeOptions off;
    off.rigid_protrusions = false;
    const MatrixX3d Y = feature_aware_resize(m, C, f), Y0 = feature_aware_resize(m, C, f, off);
    const double stretch = head_width(Y) / head_width(C);  // the head's width over the plain stretch's
    const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
    const Vec3 want = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
    std::printf("  head painted %.1f: important share of the rest %.2f, head width %.3f of the plain stretch's, "
                "turned %d, box error %.1e\n", head_weight, important_share_of_rest(m, X, f, found), stretch,
                turned_over(m, Y, C), (box - want).cwiseAbs().maxCoeff());
    EXPECT_LT((box - want).cwiseAbs().maxCoeff(), 1e-9);
    if (head_weight > 0.5) {
      EXPECT_EQ(Y, Y0);
      EXPECT_LE(stretch, 1.0 + 1e-9);
      EXPECT_EQ(turned_over(m, Y, C), 0);
      // The placement's steps run regardless: the head would take the room.
      std::vector<RigidProtrusion> forced = found;
      set_protrusion_scales(X, C, forced, true);
      const std::optional<MatrixX3d> room =
          fit_box_around_protrusions(m, X, Y0, C.colwise().minCoeff(), C.colwise().maxCoeff(), forced);
      const MatrixX3d Z = place_protrusions(m, X, room ? *room : Y0, forced);
      std::printf("  placed regardless (factors %s): head width %.3f of the plain stretch's\n",
                  room ? "settle" : "do not settle", head_width(Z) / head_width(C));
      EXPECT_GT(std::abs(head_width(Z) / head_width(C) - 1), 0.3);
    } else {
      EXPECT_NE(Y, Y0);  // placed: each ear's shaft (|x| > 1.15) as long along x as it was (plain: ×2)
      for (double side : {-1.0, 1.0}) {
        double a0 = 1e300, b0 = -1e300, a = 1e300, b = -1e300;
        for (Eigen::Index i = 0; i < X.rows(); ++i)
          if (side * X(i, 0) > 1.15)
            a0 = std::min(a0, X(i, 0)), b0 = std::max(b0, X(i, 0)), a = std::min(a, Y(i, 0)), b = std::max(b, Y(i, 0));
        std::printf("  ear %+.0f: shaft length along x %.4f of the original's\n", side, (b - a) / (b0 - a0));
        EXPECT_NEAR((b - a) / (b0 - a0), 1.0, 0.01);
      }
    }
  }
}

// The room for protrusions held at their size (fit_box_around_protrusions()) goes along each axis where the rest's
// surface lies across it (room_profile()): on the tentacle stick stretched ×2 along y and along z, the rest's
// area-weighted anisotropy under the room is lower (by more than 5 %; measured 14 % and 10 %) than under one factor
// per axis giving the rest the same extents (the room before the profile: equal), and no face of the rest turns over.
TEST(ResizeSimilarity, RigidProtrusionRoomGoesWhereTheSurfaceLiesAcrossTheAxis) {
  const TexturedShape shape = tentacle_stick(0);
  const Mesh& m = shape.textured;
  const MatrixX3d X = positions(m);
  const MatrixX3i F = faces(m);
  const Eigen::VectorXd f = feature_map(m).weights;
  for (int axis : {1, 2}) {
    Vec3 scale = Vec3::Ones();
    scale[axis] = 2;
    const MatrixX3d B = apply_map(scale_map(scale, bounding_box(m).center()), X);
    std::vector<RigidProtrusion> found = find_protrusions(m, X, f);
    ASSERT_FALSE(found.empty());
    set_protrusion_scales(X, B, found, true);
    const std::optional<MatrixX3d> room =
        fit_box_around_protrusions(m, X, B, B.colwise().minCoeff(), B.colwise().maxCoeff(), found);
    ASSERT_TRUE(room.has_value());
    const MatrixX3d& M = *room;
    std::vector<char> in(X.rows(), 0);
    for (const RigidProtrusion& p : found)
      for (int v : p.vertices) in[v] = 1;
    Vec3 lo_b = Vec3::Constant(1e300), hi_b = -lo_b, lo_m = lo_b, hi_m = hi_b;
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if (!in[i]) {
        lo_b = lo_b.cwiseMin(B.row(i).transpose()), hi_b = hi_b.cwiseMax(B.row(i).transpose());
        lo_m = lo_m.cwiseMin(M.row(i).transpose()), hi_m = hi_m.cwiseMax(M.row(i).transpose());
      }
    const Vec3 l = (hi_m - lo_m).cwiseQuotient(hi_b - lo_b);  // one factor per axis: the same extents of the rest
    double profiled = 0, uniform = 0, total = 0;
    int turned = 0;
    for (Eigen::Index k = 0; k < F.rows(); ++k) {
      if (in[F(k, 0)] || in[F(k, 1)] || in[F(k, 2)]) continue;
      const Vec3 e1 = (B.row(F(k, 1)) - B.row(F(k, 0))).transpose(), e2 = (B.row(F(k, 2)) - B.row(F(k, 0))).transpose();
      const double area = 0.5 * e1.cross(e2).norm();
      if (!(area > 0)) continue;
      const Vec3 u = e1.normalized(), v = e1.cross(e2).cross(e1).normalized();
      Eigen::Matrix<double, 3, 2> U;
      U << l.cwiseProduct(u), l.cwiseProduct(v);
      const Eigen::Vector2d su = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(U).singularValues();
      const Eigen::Vector2d sp = face_stretch(F, B, M, k);
      total += area;
      profiled += area * std::log(sp[0] / sp[1]);
      uniform += area * std::log(su[0] / su[1]);
      const Vec3 n = (M.row(F(k, 1)) - M.row(F(k, 0))).cross(M.row(F(k, 2)) - M.row(F(k, 0))).transpose();
      turned += n.dot(e1.cross(e2)) < 0;
    }
    std::printf("  stick level 0 x2 %c, the rest under the room: area-weighted log(s1/s2) %.4f (one factor per axis "
                "%.3f, %.3f, %.3f: %.4f), turned %d\n", "xyz"[axis], profiled / total, l.x(), l.y(), l.z(),
                uniform / total, turned);
    EXPECT_LT(profiled, 0.95 * uniform);  // equal under one factor per axis
    EXPECT_EQ(turned, 0);
  }
}

// Issue 25: the seams of the tentacle stick's placed tentacles ×2 across (y and z), where the body takes the
// room (the method's result stretched per axis beyond the ask; fit_box_around_protrusions()) and the tentacles
// keep their size. The band of place_protrusions() folds less at its sharpest edges (95th percentile of
// |dihedral angle| over the band's edges) than the harmonic fill of the same displacement on the same band (the
// fill before, whose folds showed as streaks around the feet): over the four runs together, and on none by more
// than 5 % (level 0 ×2 z is near even: 0.204 against 0.201). (Before relax_turned_faces() the biharmonic band
// turns more faces against the room than the harmonic one, 15 / 23 against 1 / 0 at level 1; the relaxation
// leaves none against the plain stretch: RigidProtrusionsKeepEveryTentaclesLengthAndLeanOnEveryAxis.)
TEST(ResizeSimilarity, RigidProtrusionSeamsFoldLessThanAHarmonicFill) {
  double total = 0, total_harmonic = 0;
  for (int level : {0, 1}) {
    const TexturedShape s = tentacle_stick(level);
    const Mesh& m = s.textured;
    const MatrixX3d X = positions(m);
    const Eigen::VectorXd f = feature_map(m).weights;
    for (int axis : {1, 2}) {
      Vec3 scale = Vec3::Ones();
      scale[axis] = 2;
      const MatrixX3d C = apply_map(scale_map(scale, bounding_box(m).center()), X);
      ResizeOptions without;
      without.rigid_protrusions = false;
      const MatrixX3d Y0 = feature_aware_resize(m, C, f, without);
      std::vector<RigidProtrusion> found = find_protrusions(m, X, f);
      ASSERT_FALSE(found.empty());
      set_protrusion_scales(X, C, found, true);
      const std::optional<MatrixX3d> room =
          fit_box_around_protrusions(m, X, Y0, C.colwise().minCoeff(), C.colwise().maxCoeff(), found);
      ASSERT_TRUE(room.has_value());
      const MatrixX3d& Y = *room;
      const MatrixX3d Z = place_protrusions(m, X, Y, found);
      std::vector<char> in(X.rows(), 0);
      for (const RigidProtrusion& p : found)
        for (int v : p.vertices) in[v] = 1;
      std::vector<int> known;
      std::vector<char> band(X.rows(), 0);
      for (Eigen::Index i = 0; i < X.rows(); ++i) {
        band[i] = !in[i] && Z.row(i) != Y.row(i);
        if (!band[i]) known.push_back(static_cast<int>(i));
      }
      const MatrixX3d D = Z - Y;
      const MatrixX3d Zh = Y + MatrixX3d(extend_harmonic(m, known, D(known, Eigen::all)));
      // The seam's sharpest folds (the streaks): the 95th percentile of |dihedral angle| over the band's edges.
      auto sharpest = [&](const MatrixX3d& P) {
        Mesh copy = m;
        set_positions(copy, P);
        const Eigen::VectorXd angle = dihedral_angles(copy);
        std::vector<double> seam;
        for (auto e : copy.edges()) {
          const int a = copy.from_vertex_handle(copy.halfedge_handle(e, 0)).idx();
          const int b = copy.to_vertex_handle(copy.halfedge_handle(e, 0)).idx();
          if (band[a] || band[b]) seam.push_back(std::abs(angle[e.idx()]));
        }
        std::sort(seam.begin(), seam.end());
        return seam.empty() ? 0.0 : seam[static_cast<size_t>(0.95 * static_cast<double>(seam.size() - 1))];
      };
      const int seam_vertices = static_cast<int>(std::count(band.begin(), band.end(), 1));
      std::printf("  stick level %d x2 %c, seam of %d vertices: sharpest folds %.4f (harmonic fill "
                  "%.4f); turned %d (harmonic %d)\n", level, "xyz"[axis], seam_vertices, sharpest(Z), sharpest(Zh),
                  turned_over(m, Z, Y), turned_over(m, Zh, Y));
      EXPECT_GT(seam_vertices, 0);
      EXPECT_LT(sharpest(Z), 1.05 * sharpest(Zh));
      total += sharpest(Z), total_harmonic += sharpest(Zh);
    }
  }
  EXPECT_LT(total, total_harmonic);
}

// ---------------------------------------------------------------------------------------------
// The default method, auto: axis-similarity on a box scale (better than similarity on 28 of 29 ×2 x/y/z
// runs, no face turned; bench/resize.md, eleventh session), similarity on any other deformation (which the
// axis methods refuse). It runs exactly the method it resolves to, and the result says which.

TEST(Resize, AutoRunsAxisSimilarityOnABoxScaleAndSimilarityOnAnyOtherDeformation) {
  const BumpyPlate b = bumpy_plate({.n = 24, .bumps = 2, .spacing = 1.0, .radius = 0.25});
  const Eigen::VectorXd f = painted(b, b.radius);
  const MatrixX3d X = positions(b.mesh);
  const Vec3 centre = bounding_box(b.mesh).center();
  struct Case {
    const char* name;
    MatrixX3d C;
    ResizeMethod runs;
  };
  const std::vector<Case> cases = {
      {"scale 2,1,1", apply_map(scale_map({2, 1, 1}, centre), X), ResizeMethod::AxisSimilarity},
      {"scale 1,1.5,3", apply_map(scale_map({1, 1.5, 3}, centre), X), ResizeMethod::AxisSimilarity},
      {"bend", apply_map(bend_map(1.0), X), ResizeMethod::Similarity},
      {"twist", apply_map(twist_map(0.5), X), ResizeMethod::Similarity},
      {"scale, then bend", apply_map(bend_map(0.5), apply_map(scale_map({2, 1, 1}), X)), ResizeMethod::Similarity},
      {"mirror", apply_map(scale_map({-1, 1, 1}), X), ResizeMethod::Similarity}};
  for (const Case& c : cases) {
    EXPECT_EQ(resolved_resize_method(ResizeOptions{}, X, c.C), c.runs) << c.name;
    const MatrixX3d Y = feature_aware_resize(b.mesh, c.C, f);
    EXPECT_EQ(Y, feature_aware_resize(b.mesh, c.C, f, with(c.runs))) << c.name;
    const ResizeMethod other =
        c.runs == ResizeMethod::Similarity ? ResizeMethod::AxisSimilarity : ResizeMethod::Similarity;
    if (other == ResizeMethod::AxisSimilarity)
      EXPECT_THROW(feature_aware_resize(b.mesh, c.C, f, with(other)), InvalidInput) << c.name;
    else  // the two methods differ here: the test above could fail
      EXPECT_GT((Y - feature_aware_resize(b.mesh, c.C, f, with(other))).cwiseAbs().maxCoeff(), 1e-6) << c.name;
  }
  // A method asked for is the one run; rigid protrusions (a stage of both similarity methods) leave auto's choice.
  ResizeOptions thesis = with(ResizeMethod::Thesis), rigid;
  rigid.rigid_protrusions = true;
  EXPECT_EQ(resolved_resize_method(thesis, X, cases[0].C), ResizeMethod::Thesis);
  EXPECT_EQ(resolved_resize_method(rigid, X, cases[0].C), resolved_resize_method({}, X, cases[0].C));
  // Through resize_mesh, as the front ends run it: a space map and a deformed copy, the method reported.
  ResizeRunOptions scale, asked;
  scale.map.scale = {2, 1, 1};
  asked.map.scale = {2, 1, 1};
  asked.resize.method = ResizeMethod::AxisSimilarity;
  const ResizeResult r = resize_mesh(b.mesh, scale, nullptr, &f);
  EXPECT_EQ(r.method, ResizeMethod::AxisSimilarity);
  EXPECT_EQ(r.V, resize_mesh(b.mesh, asked, nullptr, &f).V);
  const MatrixX3d bent = apply_map(bend_map(1.0), X);
  ResizeRunOptions copy;
  const ResizeResult d = resize_mesh(b.mesh, copy, &bent, &f);
  EXPECT_EQ(d.method, ResizeMethod::Similarity);
  copy.resize.method = ResizeMethod::Similarity;
  EXPECT_EQ(d.V, resize_mesh(b.mesh, copy, &bent, &f).V);
  copy.resize.method = ResizeMethod::Sliding;
  EXPECT_EQ(resize_mesh(b.mesh, copy, &bent, &f).method, ResizeMethod::Sliding);
}

namespace {

// The largest dihedral angle (degrees) between two faces sharing an edge of \p F at the positions \p Y.
double largest_dihedral(const MatrixX3i& F, const MatrixX3d& Y) {
  std::vector<std::array<Eigen::Index, 3>> edges;  // (lo vertex, hi vertex, face)
  MatrixX3d N(F.rows(), 3);
  for (Eigen::Index k = 0; k < F.rows(); ++k) {
    const Vec3 a = Y.row(F(k, 0)), b = Y.row(F(k, 1)), c = Y.row(F(k, 2));
    N.row(k) = (b - a).cross(c - a).normalized().transpose();
    for (int j = 0; j < 3; ++j)
      edges.push_back({std::min<Eigen::Index>(F(k, j), F(k, (j + 1) % 3)),
                       std::max<Eigen::Index>(F(k, j), F(k, (j + 1) % 3)), k});
  }
  std::sort(edges.begin(), edges.end());
  double worst = 0;
  for (std::size_t e = 0; e + 1 < edges.size(); ++e)
    if (edges[e][0] == edges[e + 1][0] && edges[e][1] == edges[e + 1][1])
      worst = std::max(worst, std::acos(std::clamp(N.row(edges[e][2]).dot(N.row(edges[e + 1][2])), -1.0, 1.0)));
  return worst * 180 / M_PI;
}

}  // namespace

// An important round end across the stretch stays round: a sphere of importance 0.95 stretched ×2 along z is no
// sharper anywhere after axis-similarity's similarity stage than in the axis warp it starts from. Before the box's
// pins spread softly over the rings around a lone extreme (soft_pins()), the one vertex pinned at each pole was
// dragged out to the box's face alone and drew the pole into a cone: 41° between two faces against the warp's 18°
// and the plain stretch's 6° (the teapot ×2 z's prow; bench/resize.md, fifteenth session).
TEST(ResizeAxis, AnImportantRoundEndAcrossTheStretchStaysRound) {
  const Mesh m = icosphere(4);
  const MatrixX3d X = positions(m);
  const MatrixX3i F = faces(m);
  const Eigen::VectorXd f = Eigen::VectorXd::Constant(X.rows(), 0.95);
  const MatrixX3d C = apply_map(scale_map({1, 1, 2}, bounding_box(m).center()), X);
  const MatrixX3d warp = feature_aware_resize(m, C, f, with(ResizeMethod::Axis));
  const MatrixX3d Y = feature_aware_resize(m, C, f, with(ResizeMethod::AxisSimilarity));
  const double stage = largest_dihedral(F, Y), warped = largest_dihedral(F, warp), plain = largest_dihedral(F, C);
  std::printf("  sphere x2 z, largest dihedral angle: %.1f deg (axis warp %.1f, plain %.1f)\n", stage, warped, plain);
  EXPECT_GT(warped, plain);  // the warp sharpens the poles a little: the bound below is not the plain stretch's
  EXPECT_LE(stage, warped);
  EXPECT_EQ(turned_over(m, Y, C), 0);
  const Vec3 box = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose();
  const Vec3 asked = (C.colwise().maxCoeff() - C.colwise().minCoeff()).transpose();
  EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-12);
}

 // The command line's default is auto too: the same vertices as the method it resolves to, which the
// summary line and the report's "method" name; --method similarity still gives the similarity method.
TEST(ResizeCli, DefaultMethodIsAutoAndSaysWhichItRan) {
  TempDir tmp;
  const BumpyPlate b = bumpy_plate({.n = 16});
  write_mesh(b.mesh, tmp / "b.ply");
  const std::string in = "resize " + tmp / "b.ply";
  struct Case {
    const char* map;
    const char* runs;
    const char* other;
  };
  for (const Case& c : {Case{"--scale 2,1,1", "axis-similarity", "similarity"},
                        Case{"--bend 1", "similarity", "sliding"}}) {
    const auto d = geotex::test::run_cli(in + " -o " + tmp / "d.ply" + " --report " + tmp / "d.json" + " " + c.map);
    ASSERT_EQ(d.exit_code, 0) << d.err;
    EXPECT_NE(d.err.find(fmt::format("({}, auto)", c.runs)), std::string::npos) << c.map << ": " << d.err;
    const auto report = nlohmann::json::parse(geotex::test::read_file(tmp / "d.json"));
    EXPECT_EQ(report["method"], c.runs) << c.map;
    EXPECT_EQ(report["parameters"]["method"], "auto") << c.map;
    const auto e = geotex::test::run_cli(in + " -o " + tmp / "e.ply" + " --report " + tmp / "e.json" + " " + c.map +
                                         " --method " + c.runs);
    ASSERT_EQ(e.exit_code, 0) << e.err;
    EXPECT_EQ(positions(read_mesh(tmp / "d.ply")), positions(read_mesh(tmp / "e.ply"))) << c.map;
    EXPECT_NE(e.err.find(fmt::format("({})", c.runs)), std::string::npos) << c.map << ": " << e.err;
    EXPECT_EQ(nlohmann::json::parse(geotex::test::read_file(tmp / "e.json"))["method"], c.runs) << c.map;
    const auto o = geotex::test::run_cli(in + " -o " + tmp / "o.ply" + " " + c.map + " --method " + c.other);
    ASSERT_EQ(o.exit_code, 0) << o.err;
    EXPECT_NE(positions(read_mesh(tmp / "d.ply")), positions(read_mesh(tmp / "o.ply"))) << c.map;
  }
  const auto h = geotex::test::run_cli("resize --help");
  EXPECT_NE((h.out + h.err).find("auto (default: axis-similarity for a box scale"), std::string::npos);
}

// Issue 25: the similarity stage after the axis warp moves the teapot's lid, spout and handle by other similarities
// than its body, which they already touch, and ran them into it (×2 x: 178 faces crossed beyond the input's own;
// with its patches welded for the solve, ×2 y: 4). Untangled (default), nothing crosses beyond the input's own, the
// box is exact and no face turns; with untangle off the same run crosses (the repair is what removes them), and the
// report counts them either way, on the mesh welded for the solve (its seams are no crossings there). The repair
// moves the parts apart and blends back what that leaves; either way it stays local.
TEST(ResizeUntangle, TeapotPartsDoNotRunIntoTheBody) {
  GEOTEX_REQUIRE_DATA();
  const Mesh m = read_mesh(geotex::test::data_dir() / "teapot.obj");
  ResizeRunOptions o;
  o.map.scale = Vec3(1, 2, 1);
  const ResizeResult on = resize_mesh(m, o);
  o.resize.untangle = false;
  const ResizeResult off = resize_mesh(m, o);
  ASSERT_EQ(on.method, ResizeMethod::AxisSimilarity);
  const Weld w = weld_coincident(m);
  ASSERT_EQ(on.welded_vertices, w.merged);
  const MatrixX3i F = faces(w.mesh);
  const auto crossed = [&F, &w](const MatrixX3d& V) {
    const std::vector<char> hit = self_intersecting_faces(w.to_welded(V), F);
    return static_cast<size_t>(std::count(hit.begin(), hit.end(), 1));
  };
  const size_t own = crossed(positions(m));
  std::printf("  teapot x(1, 2, 1): own %zu, off %zu, on %zu (%s)\n", own, crossed(off.V), crossed(on.V),
              on.untangle.describe().c_str());
  EXPECT_GT(crossed(off.V), own);
  EXPECT_EQ(off.untangle.after, crossed(off.V));
  EXPECT_EQ(off.untangle.blended, 0u);
  EXPECT_LE(crossed(on.V), own);
  EXPECT_EQ(on.untangle.after, crossed(on.V));
  EXPECT_EQ(on.untangle.excess_before(), off.untangle.excess_after());
  EXPECT_GT(on.untangle.shifted + on.untangle.blended, 0u);  // moved apart, blended back, or both
  EXPECT_LT(std::max(on.untangle.shifted, on.untangle.blended), m.n_vertices());  // a local repair
  EXPECT_EQ(turned_over(m, on.V, on.mapped), 0);
  const Vec3 box = (on.V.colwise().maxCoeff() - on.V.colwise().minCoeff()).transpose();
  const Vec3 asked = (on.mapped.colwise().maxCoeff() - on.mapped.colwise().minCoeff()).transpose();
  EXPECT_LT((box - asked).cwiseAbs().maxCoeff(), 1e-12 * asked.norm());
  EXPECT_LT((on.V.colwise().minCoeff() - on.mapped.colwise().minCoeff()).cwiseAbs().maxCoeff(), 1e-12 * asked.norm());
}

namespace {

// Mean over the faces flagged in \p on of log(s1 / s2), s1 ≥ s2 the singular values of the map from \p X to \p Y on
// each face (in the face's plane): 0 where the map is a similarity (the ruler's anisotropy, geval.py).
double mean_anisotropy(const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Y, const std::vector<char>& on) {
  double sum = 0;
  int n = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!on[f]) continue;
    const Vec3 e1 = X.row(F(f, 1)) - X.row(F(f, 0)), e2 = X.row(F(f, 2)) - X.row(F(f, 0));
    const Vec3 u = e1.normalized(), v = e1.cross(e2).cross(e1).normalized();
    Eigen::Matrix2d P;
    P << e1.dot(u), e2.dot(u), e1.dot(v), e2.dot(v);
    Eigen::Matrix<double, 3, 2> Q;
    Q.col(0) = Y.row(F(f, 1)) - Y.row(F(f, 0));
    Q.col(1) = Y.row(F(f, 2)) - Y.row(F(f, 0));
    const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(Q * P.inverse()).singularValues();
    sum += std::log(s[0] / s[1]);
    ++n;
  }
  return n > 0 ? sum / n : 0;
}

// \p whole stored as two unwelded patches, as the teapot's Bézier patches are: the faces whose centroid lies above
// z = \p cut get their own copies (appended after the input's vertices) of the vertices they share with the rest, so
// that the seam is a boundary loop on either side with coincident vertices. \p origin: each vertex's index in \p whole.
Mesh split_in_two_patches(const Mesh& whole, std::vector<int>& origin, double cut = 0.0) {
  const MatrixX3d X = positions(whole);
  const MatrixX3i F = faces(whole);
  std::vector<char> upper(F.rows()), below(X.rows(), 0);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    upper[f] = (X(F(f, 0), 2) + X(F(f, 1), 2) + X(F(f, 2), 2)) / 3 > cut;
    if (!upper[f])
      for (int k = 0; k < 3; ++k) below[F(f, k)] = 1;
  }
  origin.resize(X.rows());
  std::iota(origin.begin(), origin.end(), 0);
  std::vector<int> copy(X.rows(), -1);
  MatrixX3i G = F;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; upper[f] && k < 3; ++k)
      if (below[F(f, k)]) {
        if (copy[F(f, k)] < 0) copy[F(f, k)] = static_cast<int>(origin.size()), origin.push_back(F(f, k));
        G(f, k) = copy[F(f, k)];
      }
  MatrixX3d Y(static_cast<Eigen::Index>(origin.size()), 3);
  for (size_t i = 0; i < origin.size(); ++i) Y.row(static_cast<Eigen::Index>(i)) = X.row(origin[i]);
  return make_mesh(Y, G);
}

// The largest distance between a vertex of \p V (rows of the split mesh) and the row of \p W (the whole mesh's) at its
// origin; on the split mesh's own rows (\p W = V), the largest gap at the seam.
double largest_gap(const MatrixX3d& V, const MatrixX3d& W, const std::vector<int>& origin) {
  double gap = 0;
  for (size_t i = 0; i < origin.size(); ++i)
    gap = std::max(gap, (V.row(static_cast<Eigen::Index>(i)) - W.row(origin[i])).norm());
  return gap;
}

}  // namespace

// Issue 25, fourteenth session: two balls side by side along x between a floor and a ceiling, stretched ×2 in z (the
// safe result: two ellipsoids apart). As the similarity stage does with an important part, each ball is kept round
// instead, scaled ×1.12 about its centre, so the two run into each other. The repair moves them apart where they
// cross: nothing crosses beyond the input's own (none), no face turns, and the balls stay nearer the round shape
// they were given (the map from it nearer a similarity) than blending back towards the stretch leaves them.
TEST(ResizeUntangle, BallsThatWidenIntoEachOtherAreMovedApart) {
  const Mesh ball = icosphere(4, 0.5), board = plane(8, 4.0);
  const MatrixX3d B = positions(ball), P = positions(board);
  const MatrixX3i Fb = faces(ball), Fp = faces(board);
  const Eigen::Index n = B.rows(), np = P.rows();
  const Vec3 centre[2] = {Vec3(-0.55, 0, 0), Vec3(0.55, 0.05, 0)};  // 0.1 apart (not mirror images)
  MatrixX3d X(2 * n + 2 * np, 3), Y(X.rows(), 3);
  MatrixX3i F(2 * Fb.rows() + 2 * Fp.rows(), 3);
  for (int k = 0; k < 2; ++k) {
    X.middleRows(k * n, n) = B.rowwise() + centre[k].transpose();
    Y.middleRows(k * n, n) = (1.12 * B).rowwise() + centre[k].transpose();
    F.middleRows(k * Fb.rows(), Fb.rows()) = Fb.array() + static_cast<int>(k * n);
    // The floor (z = −1) and the ceiling (z = 1) hold the box: the repair's refit onto it is then the identity.
    X.middleRows(2 * n + k * np, np) = P.rowwise() + Vec3(0, 0, 2 * k - 1).transpose();
    Y.middleRows(2 * n + k * np, np) = P.rowwise() + Vec3(0, 0, 4 * k - 2).transpose();
    F.middleRows(2 * Fb.rows() + k * Fp.rows(), Fp.rows()) = Fp.array() + static_cast<int>(2 * n + k * np);
  }
  const Mesh m = make_mesh(X, F);
  MatrixX3d safe = X;
  safe.col(2) *= 2;
  const auto crossed = [&F](const MatrixX3d& V) {
    const std::vector<char> hit = self_intersecting_faces(V, F);
    return static_cast<size_t>(std::count(hit.begin(), hit.end(), 1));
  };
  ASSERT_EQ(crossed(X), 0u);
  ASSERT_EQ(crossed(safe), 0u);
  ASSERT_GT(crossed(Y), 0u);  // the widened balls run into each other
  UntangleReport shifted, blended;
  const MatrixX3d S = untangle_resize(m, X, Y, safe, true, shifted);
  const MatrixX3d Bl = untangle_resize(m, X, Y, safe, true, blended, {}, UntangleRepair::Blend);
  const std::vector<char> all(F.rows(), 1);
  // Against Y (the similarity each ball kept): 0 where the repair left it a similarity.
  const double a_shift = mean_anisotropy(F, Y, S, all), a_blend = mean_anisotropy(F, Y, Bl, all);
  std::printf("  balls: %zu faces crossed; %s: anisotropy %.5f; %s: %.5f\n", crossed(Y), shifted.describe().c_str(),
              a_shift, blended.describe().c_str(), a_blend);
  EXPECT_EQ(crossed(S), 0u);
  EXPECT_EQ(crossed(Bl), 0u);
  EXPECT_GT(shifted.shifted, 0u);
  EXPECT_EQ(shifted.blended, 0u);  // moving apart was enough
  EXPECT_LT(a_shift, a_blend);
  EXPECT_EQ(turned_over(m, S, safe), 0);
}

// Issue 25: a model stored as unwelded patches (the teapot) is solved as the one surface it shows. The spiky sphere
// split in two at its equator, ×2 x by every method that solves for positions: the seam's copies stay exactly
// together, every vertex lands where the same method puts it on the sphere stored whole, and the importance map is
// the whole sphere's. (Solved apart, the patches opened at the seam: the teapot's hairline.)
TEST(ResizeWeld, UnweldedPatchesResizeAsTheWholeModelOnEveryMethod) {
  const Mesh shape = spiky(icosphere(3)).textured;
  const Mesh whole = make_mesh(positions(shape), faces(shape));
  std::vector<int> origin;
  const Mesh split = split_in_two_patches(whole, origin);
  const int copies = static_cast<int>(split.n_vertices() - whole.n_vertices());
  ASSERT_GT(copies, 20);
  ASSERT_EQ(boundary_loops(split).size(), 2u);
  for (ResizeMethod m : {ResizeMethod::Auto, ResizeMethod::Similarity, ResizeMethod::Axis, ResizeMethod::AxisSimilarity}) {
    ResizeRunOptions o;
    o.map.scale = Vec3(2, 1, 1);
    o.resize.method = m;
    const ResizeResult s = resize_mesh(split, o), w = resize_mesh(whole, o);
    const double unit = (w.V.colwise().maxCoeff() - w.V.colwise().minCoeff()).norm();
    const std::string name(enum_name(resize_method_names(), m));
    ASSERT_EQ(s.V.rows(), static_cast<Eigen::Index>(split.n_vertices())) << name;
    EXPECT_EQ(s.welded_vertices, copies) << name;
    EXPECT_EQ(s.weld_refused_groups, 0) << name;
    EXPECT_EQ(largest_gap(s.V, s.V, origin), 0.0) << name;  // the seam closed
    EXPECT_LE(largest_gap(s.V, w.V, origin), 1e-12 * unit) << name;
    EXPECT_LE(largest_gap(s.mapped, w.mapped, origin), 1e-12 * unit) << name;
    for (size_t i = 0; i < origin.size(); ++i) ASSERT_EQ(s.features[static_cast<Eigen::Index>(i)], w.features[origin[i]]);
    // The library's entry point welds the same way.
    const MatrixX3d direct = feature_aware_resize(split, s.mapped, s.features, o.resize);
    EXPECT_LE((direct - s.V).cwiseAbs().maxCoeff(), 1e-12 * unit) << name;
  }
}

// A weight painted on one side of a seam holds the welded vertex (the largest of its copies'), and the result's
// weights are the input's, per input vertex.
TEST(ResizeWeld, APaintedWeightOnOneSideOfTheSeamIsHonoured) {
  const Mesh shape = spiky(icosphere(3)).textured;
  const Mesh whole = make_mesh(positions(shape), faces(shape));
  std::vector<int> origin;
  const Mesh split = split_in_two_patches(whole, origin);
  const MatrixX3d X = positions(split);
  // The upper patch painted important up to and with its seam copies; the lower patch's seam vertices are not.
  Eigen::VectorXd f = Eigen::VectorXd::Zero(X.rows());
  const Eigen::Index n = static_cast<Eigen::Index>(whole.n_vertices());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    if (X(i, 2) > 0.3 || i >= n) f[i] = 1.0;
  Eigen::VectorXd held = Eigen::VectorXd::Zero(n), dropped = Eigen::VectorXd::Zero(n);  // on the whole sphere
  for (Eigen::Index i = 0; i < X.rows(); ++i) held[origin[i]] = std::max(held[origin[i]], f[i]);
  for (Eigen::Index i = 0; i < n; ++i) dropped[i] = f[i];
  ResizeRunOptions o;
  o.map.scale = Vec3(2, 1, 1);
  const ResizeResult s = resize_mesh(split, o, nullptr, &f);
  EXPECT_EQ(s.features, f);
  const ResizeResult w = resize_mesh(whole, o, nullptr, &held), d = resize_mesh(whole, o, nullptr, &dropped);
  const double unit = (w.V.colwise().maxCoeff() - w.V.colwise().minCoeff()).norm();
  EXPECT_EQ(largest_gap(s.V, s.V, origin), 0.0);
  EXPECT_LE(largest_gap(s.V, w.V, origin), 1e-12 * unit);
  EXPECT_GT(largest_gap(s.V, d.V, origin), 1e-6 * unit);  // the seam's paint mattered
}

// The command writes the input's vertices in the input's order with its faces, the seam closed, and the weights
// per input vertex (--save-features); the report counts the welded vertices.
TEST(ResizeWeld, TheCommandWritesTheInputsVerticesAndFacesWithTheSeamClosed) {
  TempDir tmp;
  const Mesh shape = spiky(icosphere(3)).textured;
  std::vector<int> origin;
  const Mesh split = split_in_two_patches(make_mesh(positions(shape), faces(shape)), origin, 0.2);
  write_mesh(split, tmp / "split.ply");
  const auto r = geotex::test::run_cli("resize " + tmp / "split.ply" + " -o " + tmp / "r.ply" + " --scale 1,1,2" +
                                       " --save-features " + tmp / "f.txt --report " + tmp / "r.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Mesh out = read_mesh(tmp / "r.ply");
  ASSERT_EQ(out.n_vertices(), split.n_vertices());
  EXPECT_EQ(faces(out), faces(split));
  const MatrixX3d V = positions(out);
  EXPECT_EQ(largest_gap(V, V, origin), 0.0);
  EXPECT_NEAR(V.col(2).maxCoeff() - V.col(2).minCoeff(), 2 * (positions(split).col(2).maxCoeff() -
                                                              positions(split).col(2).minCoeff()), 1e-9);
  const std::string saved = geotex::test::read_file(tmp / "f.txt");
  EXPECT_EQ(static_cast<size_t>(std::count(saved.begin(), saved.end(), '\n')), split.n_vertices());
  const nlohmann::json j = nlohmann::json::parse(geotex::test::read_file(tmp / "r.json"));
  EXPECT_EQ(j["welded_vertices"].get<size_t>(), split.n_vertices() - shape.n_vertices());
  EXPECT_NE(r.err.find("welded"), std::string::npos) << r.err;
}

namespace {

// \p shape and its mirror image through the plane x = its largest x (turned a little first, so that one vertex alone
// lies on it), shrunk by 0.6 about that vertex: two parts touching at one point, stored with a copy of it in each
// part, whose faces there make two separate fans (the teapot's handle on its body). \p a, \p b: the two copies.
Mesh two_parts_touching_at_a_point(const Mesh& shape, int& a, int& b) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const MatrixX3d X = positions(shape) * turn.transpose();
  const MatrixX3i F = faces(shape);
  const Eigen::Index n = X.rows();
  Eigen::Index top = 0;
  X.col(0).maxCoeff(&top);
  a = static_cast<int>(top);
  const Eigen::RowVector3d p = X.row(a);
  MatrixX3d Y(2 * n, 3);
  MatrixX3i G(2 * F.rows(), 3);
  Y.topRows(n) = X;
  for (Eigen::Index v = 0; v < n; ++v) {
    Eigen::RowVector3d q = X.row(v);
    q[0] = 2 * p[0] - q[0];
    Y.row(n + v) = p + 0.6 * (q - p);
  }
  Y.row(n + a) = p;  // exactly
  G.topRows(F.rows()) = F;
  for (Eigen::Index f = 0; f < F.rows(); ++f)  // mirrored: the other way round
    G.row(F.rows() + f) = Eigen::RowVector3i(F(f, 0), F(f, 2), F(f, 1)) + Eigen::RowVector3i::Constant(static_cast<int>(n));
  b = static_cast<int>(n) + a;
  return make_mesh(Y, G);
}

}  // namespace

// Issue 25: a part touching the body at one point stays attached. The weld leaves the point's copies apart (welded,
// the two parts' faces would meet there in two fans), and the similarity stage solved the two parts apart: the
// teapot's handle ended 2.2 mean edge lengths off its body at ×2 x. Tied in the solve, the copies end together, ×2
// along x (the axis through the two parts) by the default method and the others that solve for positions.
TEST(ResizeWeld, PartsTouchingAtAPointStayTogether) {
  int a = 0, b = 0;
  const Mesh m = two_parts_touching_at_a_point(spiky(icosphere(3)).textured, a, b);
  const double unit = mean_edge_length(m);
  const Weld w = weld_coincident(m);
  ASSERT_EQ(w.merged, 0);
  ASSERT_EQ(w.ties.size(), 1u);
  EXPECT_EQ(w.ties[0], (std::array<int, 2>{a, b}));
  for (ResizeMethod method : {ResizeMethod::Auto, ResizeMethod::Similarity}) {
    ResizeRunOptions o;
    o.map.scale = Vec3(2, 1, 1);
    o.resize.method = method;
    const ResizeResult r = resize_mesh(m, o);
    const std::string name(enum_name(resize_method_names(), method));
    const double gap = (r.V.row(a) - r.V.row(b)).norm();
    std::printf("  two parts at a point x(2, 1, 1), %s: gap %.2e mean edge lengths\n", name.c_str(), gap / unit);
    EXPECT_LE(gap, 1e-3 * unit) << name;
    EXPECT_EQ(turned_over(m, r.V, r.mapped), 0) << name;
    const MatrixX3d direct = feature_aware_resize(m, r.mapped, r.features, o.resize);  // the library's entry point
    EXPECT_LE((direct.row(a) - direct.row(b)).norm(), 1e-3 * unit) << name;
  }
}

// Units, placement and up axis do not change the default resize (issue 25, fifteenth session): the spiky sphere
// ×2 along y, in metres and millimetres, 10^4 diagonals off the origin, and turned y-up → z-up (asked ×2 along
// z), maps back onto the plain run within 1e-6 mean edge lengths. Far off the origin the similarity solve's error
// grew with the positions, and the feature map's protrusions moved with signed_volume()'s cancellation (here 0.016
// edge lengths) until the solve was centred and the volume summed about the box's centre.
TEST(ResizeInvariance, UnitsPlacementAndUpAxisLeaveTheDefaultResult) {
  const Mesh m = make_shape("spiky-sphere", 0).textured;
  const MatrixX3d X = positions(m);
  const double mel = mean_edge_length(m), diag = bounding_box(m).diagonal();
  ResizeRunOptions o;
  o.map.scale = {1, 2, 1};
  const MatrixX3d Y0 = resize_mesh(m, o).V;
  Eigen::Matrix3d rotx90;  // y → z, z → −y
  rotx90 << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  struct Similarity {
    const char* name;
    double s;
    Eigen::Matrix3d R;
    Vec3 t;
  };
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Similarity cases[] = {{"x1000", 1000, I, Vec3::Zero()},
                              {"x0.001", 0.001, I, Vec3::Zero()},
                              {"offset", 1, I, 1e4 * diag * Vec3(0.6, -0.48, 0.64)},
                              {"rotx90", 1, rotx90, Vec3::Zero()}};
  for (const Similarity& c : cases) {
    Mesh moved = m;
    set_positions(moved, (c.s * X * c.R.transpose()).rowwise() + c.t.transpose());
    ResizeRunOptions ot = o;
    ot.map.scale = c.R.cwiseAbs() * o.map.scale;  // the asked axes carried along
    const MatrixX3d Y = ((resize_mesh(moved, ot).V.rowwise() - c.t.transpose()) / c.s) * c.R;
    EXPECT_LT((Y - Y0).cwiseAbs().maxCoeff(), 1e-6 * mel) << c.name;
  }
}

// Issue 25, fifteenth session: with the weld off (ResizeOptions::weld false) an unwelded seam is solved as two patches
// and opens, as it did before the weld; on, it stays shut. Auto (axis-similarity) and similarity, ×2 x, through the
// library and the command line (--no-weld: the report's welded_vertices 0).
TEST(ResizeWeld, WithTheWeldOffAnUnweldedSeamOpens) {
  const Mesh shape = spiky(icosphere(3)).textured;
  std::vector<int> origin;
  const Mesh split = split_in_two_patches(make_mesh(positions(shape), faces(shape)), origin);
  const double unit = mean_edge_length(split);
  for (ResizeMethod method : {ResizeMethod::Auto, ResizeMethod::Similarity}) {
    ResizeRunOptions o;
    o.map.scale = Vec3(2, 1, 1);
    o.resize.method = method;
    const ResizeResult on = resize_mesh(split, o);
    o.resize.weld = false;
    const ResizeResult off = resize_mesh(split, o);
    const std::string name(enum_name(resize_method_names(), method));
    std::printf("  split sphere x2 x, %s: seam gap %.2e (weld on) / %.3f (off) mean edge lengths\n", name.c_str(),
                largest_gap(on.V, on.V, origin) / unit, largest_gap(off.V, off.V, origin) / unit);
    EXPECT_EQ(largest_gap(on.V, on.V, origin), 0.0) << name;
    EXPECT_GT(largest_gap(off.V, off.V, origin), 1e-2 * unit) << name;
    EXPECT_GT(on.welded_vertices, 0) << name;
    EXPECT_EQ(off.welded_vertices, 0) << name;
    const MatrixX3d direct = feature_aware_resize(split, off.mapped, off.features, o.resize);  // the library's entry
    EXPECT_LE((direct - off.V).cwiseAbs().maxCoeff(), 1e-12 * unit) << name;
  }
  TempDir tmp;
  write_mesh(split, tmp / "split.ply");
  const auto r = geotex::test::run_cli("resize " + tmp / "split.ply" + " -o " + tmp / "r.ply" +
                                       " --scale 2,1,1 --no-weld --report " + tmp / "r.json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(geotex::test::read_file(tmp / "r.json"));
  EXPECT_EQ(j["welded_vertices"].get<int>(), 0);
  const MatrixX3d V = positions(read_mesh(tmp / "r.ply"));
  EXPECT_GT(largest_gap(V, V, origin), 1e-2 * unit);
}

// Issue 25, fifteenth session: a rigid protrusion tied to another part stays where the similarity stage put it. A
// small ball touches the tip of one of the tentacle stick's tentacles at a point (welded per fan: tied); placed as one
// piece, that tentacle would pull its tip off the ball. The tie holds ×2 along each axis by the default method (its
// untangle off: it moves parts that cross apart, tied or not), and the other tentacles are still placed rigidly (their
// length and lean kept as in RigidProtrusionsKeepEveryTentaclesLengthAndLeanOnEveryAxis).
TEST(ResizeWeld, ARigidProtrusionTiedToAnotherPartIsLeftWhereTheSolvePutIt) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(0, &info);
  const MatrixX3d X0 = positions(s.textured);
  const MatrixX3i F0 = faces(s.textured);
  const int tip = info[0].foot;  // the footprint's centre is the tentacle's tip
  const Vec3 out = Vec3(vertex_normals(s.textured).row(tip).transpose()).normalized();
  const Mesh ball = icosphere(1, 0.15);
  const MatrixX3d B = positions(ball);
  Eigen::Index touch = 0;
  (B * out).minCoeff(&touch);  // the ball's vertex facing the tip
  const Eigen::Index n0 = X0.rows(), nb = B.rows();
  MatrixX3d X(n0 + nb, 3);
  X.topRows(n0) = X0;
  X.bottomRows(nb) = B.rowwise() + (X0.row(tip) - B.row(touch));
  MatrixX3i F(F0.rows() + ball.n_faces(), 3);
  F.topRows(F0.rows()) = F0;
  F.bottomRows(ball.n_faces()) = faces(ball).array() + static_cast<int>(n0);
  const Mesh m = make_mesh(X, F);
  const Weld w = weld_coincident(m);
  ASSERT_EQ(w.ties.size(), 1u);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(X.rows());
  f.head(n0) = feature_map(s.textured).weights;
  const double unit = mean_edge_length(m);
  const std::vector<Tentacle> others(info.begin() + 1, info.end());
  for (int a = 0; a < 3; ++a) {
    Vec3 scale = Vec3::Ones();
    scale[a] = 2;
    const MatrixX3d C = apply_map(scale_map(scale, bounding_box(m).center()), X);
    ResizeOptions o;
    o.untangle = false;  // the solve and the placement alone (the repairs hold ties too)
    const MatrixX3d Y = feature_aware_resize(m, C, f, o);
    const double gap = (Y.row(tip) - Y.row(n0 + touch)).norm();
    const MatrixX3d Ys = Y.topRows(n0);
    const auto r = worst_tentacle_change(s, others, X0, Ys);
    std::printf("  stick level 0 with a ball on a tip x2 %c: gap %.2e mean edge lengths; the other tentacles' worst "
                "length / lean change %.2f%% / %.2f deg\n", "xyz"[a], gap / unit, 100 * r[0], r[1]);
    EXPECT_LE(gap, 1e-3 * unit);
    EXPECT_LT(r[0], 0.03);
    EXPECT_LT(r[1], 3.0);
    EXPECT_EQ(turned_over(m, Y, C), 0);
  }
}

namespace {

// How far each tie's vertex ends from its point, against its offset from it in the input \p C:
// |(y_v − Σ w_k y_{c_k}) − (c_v − Σ w_k c_{c_k})|, the largest over \p ties (vertices of the welded mesh \p w, or of
// the input when \p w welds nothing).
double largest_tie_miss(const std::vector<SurfaceTie>& ties, const Weld& w, const MatrixX3d& Y, const MatrixX3d& C) {
  const MatrixX3d y = w.identity() ? Y : w.to_welded(Y), c = w.identity() ? C : w.to_welded(C);
  double miss = 0;
  for (const SurfaceTie& t : ties) {
    Vec3 d = (y.row(t.vertex) - c.row(t.vertex)).transpose();
    for (int k = 0; k < 3; ++k) d -= t.weights[k] * (y.row(t.corners[k]) - c.row(t.corners[k])).transpose();
    miss = std::max(miss, d.norm());
  }
  return miss;
}

// One ×2 resize along axis \p a of \p m by the default method, with the weld (and its ties) on and off: the two
// results and how far each leaves \p ties' rim vertices off their points (largest_tie_miss()).
struct SeatedRun {
  ResizeResult on, off;
  double miss_on = 0, miss_off = 0;
};
SeatedRun resize_weld_on_and_off(const Mesh& m, const std::vector<SurfaceTie>& ties, const Weld& w, int a) {
  const MatrixX3d X = positions(m);
  ResizeRunOptions o;
  o.map.scale = Vec3::Ones();
  o.map.scale[a] = 2;
  SeatedRun r;
  r.on = resize_mesh(m, o);
  o.resize.weld = false;
  r.off = resize_mesh(m, o);
  r.miss_on = largest_tie_miss(ties, w, r.on.V, X);
  r.miss_off = largest_tie_miss(ties, w, r.off.V, X);
  return r;
}

}  // namespace

// Issue 25, sixteenth session: a part resting on another with its rim on the other's faces (an open tube standing on
// a ball, its rim on the interior of the ball's faces) stays seated, ×2 along each axis by the default method with its
// repairs on; with the weld off (nothing tied) the resize opens the seat (the test could fail).
TEST(ResizeWeld, ARimRestingOnAnotherPartsFacesStaysOnThem) {
  const Mesh m = test::tube_on_a_ball(Vec3(1, 0.3, 0.2));
  const Weld w = weld_coincident(m);
  ASSERT_TRUE(w.identity());
  const std::vector<SurfaceTie> ties = rim_contacts(m);
  ASSERT_EQ(ties.size(), 16u);
  const double unit = mean_edge_length(m);
  double widest_off = 0;
  for (int a = 0; a < 3; ++a) {
    const auto [on, off, miss_on, miss_off] = resize_weld_on_and_off(m, ties, w, a);
    std::printf("  tube on a ball x2 %c: rim off its points %.2e (ties) / %.2f (weld off) mean edge lengths\n",
                "xyz"[a], miss_on / unit, miss_off / unit);
    EXPECT_LE(miss_on, 1e-3 * unit);
    EXPECT_EQ(turned_over(m, on.V, on.mapped), 0);
    widest_off = std::max(widest_off, miss_off);
  }
  EXPECT_GT(widest_off, 0.1 * unit);
}

// Issue 25, fifteenth and sixteenth sessions: the teapot's handle's lower end rests on its body's faces (rim vertices
// on the interior of the body's faces, one on a body vertex). Tied to their points on those faces in the similarity
// stage and held there through the repairs (the untangle's shift and blend, the protrusions' relaxation), the rim
// vertices keep their offsets from them, ×2 along each axis; with the weld off (the patches and parts solved apart,
// nothing tied) the handle's end leaves the body at ×2 x (the notch) and no vertex is welded.
TEST(ResizeWeld, RimsRestingOnAnotherPartStayOnIt) {
  GEOTEX_REQUIRE_DATA();
  const Mesh m = read_mesh(geotex::test::data_dir() / "teapot.obj");
  const Weld w = weld_coincident(m);
  const std::vector<SurfaceTie> ties = rim_contacts(w.mesh);
  ASSERT_GE(ties.size(), 16u);  // the handle's lower end's rim
  const double unit = mean_edge_length(m);
  for (int a = 0; a < 3; ++a) {
    const auto [on, off, miss_on, miss_off] = resize_weld_on_and_off(m, ties, w, a);
    std::printf("  teapot x2 %c: rims off their points %.2e (weld on) / %.2f (off) mean edge lengths\n", "xyz"[a],
                miss_on / unit, miss_off / unit);
    EXPECT_LE(miss_on, 1e-3 * unit);
    EXPECT_EQ(turned_over(m, on.V, on.mapped), 0);
    EXPECT_GT(on.welded_vertices, 0);
    EXPECT_EQ(off.welded_vertices, 0);
    if (a == 0) EXPECT_GT(miss_off, 0.1 * unit);  // the handle's lower end off the body (the test could fail)
  }
}
