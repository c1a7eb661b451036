// Feature maps for feature-aware resizing (resize/feature_map.h): the tentacles of the stick, the
// bumps of the plate, the marked share and its warning, and resizing real models.

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/resize/resize.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

namespace {

double iou(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double inter = 0, uni = 0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    inter += std::min(a[i], b[i]);
    uni += std::max(a[i], b[i]);
  }
  return uni > 0 ? inter / uni : 0.0;
}

// The coarse tentacle stick, its true tentacles, and its automatic map (computed once: the ADF's
// eigenproblem is the slow part).
struct Stick {
  std::vector<Tentacle> info;
  TexturedShape shape;
  Eigen::VectorXd truth;
  FeatureMap adf;
  Stick() : shape(tentacle_stick(0, &info)) {
    truth = tentacle_truth(shape.base, info, TentacleOptions{}.radius);
    FeatureMapOptions o;
    o.method = FeatureMapMethod::Adf;
    adf = feature_map(shape.textured, o);
  }
};
FeatureMapOptions binary_auto() {
  FeatureMapOptions o;
  o.method = FeatureMapMethod::Auto;
  return o;
}

const Stick& stick() {
  static const Stick s;
  return s;
}

}  // namespace

TEST(FeatureMap, AdfFindsTheWholeTentaclesOfTheStick) {
  const Stick& s = stick();
  const double score = iou(s.adf.weights, s.truth);
  std::printf("  tentacle stick (level 0), adf: IoU %.3f with the true tentacles, %s\n", score,
              s.adf.summary.describe().c_str());
  EXPECT_GT(score, 0.8);  // the thresholded ADF of old marked only the tips: IoU 0.37
  EXPECT_EQ(s.adf.summary.regions, 9);
  EXPECT_TRUE(s.adf.summary.warning.empty()) << s.adf.summary.warning;
  // Auto is the ADF map wherever the ADF finds protrusions.
  EXPECT_EQ(feature_map(s.shape.textured, binary_auto()).method, FeatureMapMethod::Adf);
}

TEST(FeatureMap, AdfFromASimplificationFindsTheSameTentacles) {
  // The spectrum of a simplification to 3,000 of the stick's 9,382 vertices (a third: far coarser than
  // the default's share at 10^6 faces), extended back: the same nine tentacles, mostly the same vertices
  // as the ADF on the stick itself.
  const Stick& s = stick();
  FeatureMapOptions o;
  o.method = FeatureMapMethod::Adf;
  o.adf_full_vertices = 3000;
  o.adf_vertices = 3000;
  const FeatureMap coarse = feature_map(s.shape.textured, o);
  std::printf("  tentacle stick, adf from 3000 vertices: IoU %.3f with the true tentacles, %.3f with the full ADF's map\n",
              iou(coarse.weights, s.truth), iou(coarse.weights, s.adf.weights));
  EXPECT_GT(iou(coarse.weights, s.truth), 0.8);
  EXPECT_GT(iou(coarse.weights, s.adf.weights), 0.85);
  EXPECT_EQ(coarse.summary.regions, 9);
}

TEST(FeatureMap, AutoFallsBackToHeightOnAPlateAndFindsTheBumpsAndTheRidge) {
  const BumpyPlate b = ridge_plate(60);
  const FeatureMap fm = feature_map(b.mesh, binary_auto());
  EXPECT_EQ(fm.method, FeatureMapMethod::Height);  // the ADF peaks at the plate's border, not on the bumps
  const double score = iou(fm.weights, b.truth);
  std::printf("  ridge plate, auto: IoU %.3f with the true footprints, %s\n", score, fm.summary.describe().c_str());
  EXPECT_GT(score, 0.8);
  EXPECT_EQ(fm.summary.regions, 5);  // four bumps and the ridge
}

TEST(FeatureMap, WarnsWhenAlmostEverythingOrNothingIsMarked) {
  const Mesh m = icosphere(3);
  const Eigen::Index n = m.n_vertices();
  const FeatureSummary all = summarize_features(m, Eigen::VectorXd::Ones(n));
  EXPECT_NEAR(all.marked_fraction, 1.0, 1e-12);
  EXPECT_EQ(all.regions, 1);
  EXPECT_NE(all.warning.find("more than half"), std::string::npos) << all.warning;
  const FeatureSummary none = summarize_features(m, Eigen::VectorXd::Zero(n));
  EXPECT_EQ(none.marked_fraction, 0.0);
  EXPECT_NE(none.warning.find("less than 0.5%"), std::string::npos) << none.warning;
  // A cap of a quarter of the sphere: no warning, and the area share (not the vertex count) is reported.
  Eigen::VectorXd cap(n);
  const MatrixX3d X = positions(m);
  for (Eigen::Index i = 0; i < n; ++i) cap[i] = X(i, 2) > 0.5 ? 1.0 : 0.0;  // area share (1 − 0.5) / 2
  const FeatureSummary s = summarize_features(m, cap);
  EXPECT_NEAR(s.marked_fraction, 0.25, 0.03);
  EXPECT_TRUE(s.warning.empty()) << s.warning;
  EXPECT_THROW(summarize_features(m, Eigen::VectorXd::Ones(3)), InvalidInput);
}

TEST(FeatureMap, CliWarnsWhenEverythingIsMarked) {
  geotex::test::TempDir tmp;
  const Mesh m = icosphere(2);
  write_mesh(m, tmp / "s.ply");
  std::string ones;
  for (size_t i = 0; i < m.n_vertices(); ++i) ones += "1\n";
  geotex::test::write_file(tmp / "all.txt", ones);
  const auto r = geotex::test::run_cli("resize " + tmp / "s.ply" + " -o " + tmp / "r.ply" + " --scale 2,1,1 --features " +
                                       tmp / "all.txt");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("100.0% of the surface"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
}

TEST(FeatureMap, SignificantBasinsStopAtTheValleyAroundAPeak) {
  // A field with two bumps on a flat plate: the basins are the bumps' discs up to where the field
  // turns up again, not a level set; a bump too low against the spread of the field is no feature.
  const Mesh m = plane(40, 2.0);
  const MatrixX3d X = positions(m);
  Eigen::VectorXd g(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double r1 = (X.row(i).head<2>() - Eigen::RowVector2d(-0.4, 0)).norm();
    const double r2 = (X.row(i).head<2>() - Eigen::RowVector2d(0.5, 0.3)).norm();
    g[i] = std::exp(-r1 * r1 / 0.02) + 0.3 * std::exp(-r2 * r2 / 0.01) + 0.01 * std::sin(40 * X(i, 0)) * std::sin(40 * X(i, 1));
  }
  const Eigen::VectorXd f = significant_basins(m, g, 3.0);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double r1 = (X.row(i).head<2>() - Eigen::RowVector2d(-0.4, 0)).norm();
    if (r1 < 0.15) EXPECT_EQ(f[i], 1.0) << "inside the big bump";
    if (r1 > 0.5 && (X.row(i).head<2>() - Eigen::RowVector2d(0.5, 0.3)).norm() > 0.4) EXPECT_EQ(f[i], 0.0);
  }
  EXPECT_THROW(significant_basins(m, Eigen::VectorXd::Zero(3), 3.0), InvalidInput);
}

TEST(FeatureMap, BasinsJoinedByAHighPassAreOneFeature) {
  // A two-tipped bump (a hair bun): tip A stands 4.5 robust deviations above the median, tip B beside
  // it only 2.2, and the pass between them 2.0; a lone bump C of 2.0 elsewhere, on a ramp whose maxima
  // lie on the boundary. Without merging, B's basin is no feature; with passes above 1.5 (the
  // default), A and B are one feature, and C (whose pass to the rest lies on the ramp) is still none.
  const Mesh m = plane(80, 2.0);
  const MatrixX3d X = positions(m);
  Eigen::VectorXd g(X.rows());
  auto bump = [](double x, double y, double cx, double cy, double s) {
    return std::exp(-((x - cx) * (x - cx) + (y - cy) * (y - cy)) / s);
  };
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double x = X(i, 0), y = X(i, 1);
    g[i] = 0.5 * y + 2 * bump(x, y, -0.4, 0, 0.03) + bump(x, y, -0.05, 0, 0.03) + 0.8 * bump(x, y, 0.6, 0.3, 0.01);
  }
  auto at = [&](const Eigen::VectorXd& f, double x, double y) {
    Eigen::Index best = 0;
    (X.leftCols<2>().rowwise() - Eigen::RowVector2d(x, y)).rowwise().squaredNorm().minCoeff(&best);
    return f[best];
  };
  const Eigen::VectorXd apart = significant_basins(m, g, 3.0);
  EXPECT_EQ(at(apart, -0.4, 0), 1.0);
  EXPECT_EQ(at(apart, -0.05, 0), 0.0) << "tip B must be a basin of its own, below the significance";
  EXPECT_EQ(at(apart, 0.6, 0.3), 0.0);
  const Eigen::VectorXd joined = significant_basins(m, g, 3.0, FeatureMapOptions{}.merge_pass);
  EXPECT_EQ(at(joined, -0.4, 0), 1.0);
  EXPECT_EQ(at(joined, -0.05, 0), 1.0) << "tip B joins tip A over their high pass";
  EXPECT_EQ(at(joined, 0.6, 0.3), 0.0) << "bump C's pass lies on the ramp, at its foot";
  EXPECT_EQ(at(joined, 0.9, -0.9), 0.0);
}

// On the tentacle stick scaled ×2 along its axis and bent into an arc, every tentacle keeps its length
// and its angle to the local base (measured on its foot ring), with the automatic features.
TEST(FeatureMap, TentaclesKeepLengthAndAngleOnTheStretchedArc) {
  const Stick& s = stick();
  const Mesh& m = s.shape.textured;
  const MatrixX3d X = positions(m);
  SpaceMapOptions so;
  so.scale = Vec3(2, 1, 1);
  so.arc_radius = 6;
  const MatrixX3d C = apply_space_map(space_map(so, bounding_box(m)), X);
  ResizeOptions sliding;  // the binary map's method
  sliding.method = ResizeMethod::Sliding;
  const MatrixX3d Y = feature_aware_resize(m, C, s.adf.weights, sliding);
  const MatrixX3d Yd = feature_aware_resize(m, C, feature_map(m).weights);  // the defaults: importance, similarity
  double length = 0, angle = 0, plain_angle = 0, length_d = 0, angle_d = 0;
  for (const Tentacle& t : s.info) {
    const Eigen::VectorXd foot = tentacle_truth(s.shape.base, {t}, TentacleOptions{}.radius);
    const ProtrusionPose a = measure_protrusion(m, X, t.foot, foot), b = measure_protrusion(m, Y, t.foot, foot);
    const ProtrusionPose d = measure_protrusion(m, Yd, t.foot, foot);
    length = std::max(length, std::abs(b.length / a.length - 1));
    angle = std::max(angle, std::abs(b.angle_deg - a.angle_deg));
    length_d = std::max(length_d, std::abs(d.length / a.length - 1));
    angle_d = std::max(angle_d, std::abs(d.angle_deg - a.angle_deg));
    plain_angle = std::max(plain_angle, std::abs(measure_protrusion(m, C, t.foot, foot).angle_deg - a.angle_deg));
  }
  std::printf("  stick x2 + arc, defaults (importance, similarity): worst length change %.1f%%, angle change %.1f deg\n",
              100 * length_d, angle_d);
  {  // ×2 along the axis without the arc, the defaults
    const MatrixX3d C2 = apply_space_map(scale_map({2, 1, 1}, bounding_box(m).center()), X);
    const MatrixX3d Y2 = feature_aware_resize(m, C2, feature_map(m).weights);
    double l2 = 0, a2 = 0;
    for (const Tentacle& t : s.info) {
      const Eigen::VectorXd foot = tentacle_truth(s.shape.base, {t}, TentacleOptions{}.radius);
      const ProtrusionPose a = measure_protrusion(m, X, t.foot, foot), d = measure_protrusion(m, Y2, t.foot, foot);
      l2 = std::max(l2, std::abs(d.length / a.length - 1));
      a2 = std::max(a2, std::abs(d.angle_deg - a.angle_deg));
    }
    std::printf("  stick x2, defaults: worst length change %.1f%%, angle change %.1f deg\n", 100 * l2, a2);
  }
  std::printf("  stick x2 + arc: worst length change %.1f%%, worst angle change %.1f deg (plain map %.1f deg)\n",
              100 * length, angle, plain_angle);
  EXPECT_LT(length, 0.05);
  EXPECT_LT(angle, 5.0);
  EXPECT_GT(plain_angle, 15.0);
}

// A real model with scale (2, 1, 1): the box is scaled as asked, a sensible share is marked, and every
// feature region keeps its proportions (principal extents of its vertices, area-weighted).
TEST(FeatureMap, RealModelKeepsItsFeaturesAndItsBox) {
  GEOTEX_REQUIRE_DATA();
  const Mesh m = read_mesh(geotex::test::data_dir() / "spot.obj");
  const FeatureMap fm = feature_map(m, binary_auto());
  EXPECT_GT(fm.summary.marked_fraction, 0.01);
  EXPECT_LT(fm.summary.marked_fraction, 0.5);
  const MatrixX3d X = positions(m);
  const BoundingBox box = bounding_box(m);
  ResizeOptions sliding;  // the binary map's method
  sliding.method = ResizeMethod::Sliding;
  const MatrixX3d Y = feature_aware_resize(m, scale_map({2, 1, 1}, box.center()), fm.weights, sliding);
  const Vec3 ratio = (Y.colwise().maxCoeff() - Y.colwise().minCoeff()).transpose().cwiseQuotient(box.size());
  EXPECT_NEAR(ratio.x(), 2.0, 0.02);
  EXPECT_NEAR(ratio.y(), 1.0, 0.01);
  EXPECT_NEAR(ratio.z(), 1.0, 0.01);
  const auto before = region_extents(m, X, fm.weights), after = region_extents(m, Y, fm.weights);
  double worst = 0;
  for (size_t k = 0; k < before.size(); ++k)
    if (before[k].vertices.size() >= 20) worst = std::max(worst, aspect_change(before[k].extents, after[k].extents));
  std::printf("  spot.obj x2: %s; box ratio %.4f %.4f %.4f; worst feature aspect change %.1f%%\n",
              fm.summary.describe().c_str(), ratio.x(), ratio.y(), ratio.z(), 100 * worst);
  EXPECT_LT(worst, 0.1);
}

TEST(FeatureMap, AdfOfSeveralComponentsIsEachComponentsOwn) {
  // Two copies of the stick side by side and three loose triangles: each component gets its own
  // spectrum (one spectrum of the whole would spend its eigenpairs on the k zero modes of k components:
  // minutes for 10^5 disjoint triangles), its ADF weighted by its share of the area. So each copy's field
  // is the stick's alone times its share, and both copies mark the same vertices.
  const Stick& s = stick();
  const MatrixX3d X = positions(s.shape.textured);
  const MatrixX3i F = faces(s.shape.textured);
  const Eigen::Index n = X.rows(), m = F.rows();
  const double gap = 2 * (X.col(1).maxCoeff() - X.col(1).minCoeff());
  MatrixX3d Y(2 * n + 9, 3);
  MatrixX3i G(2 * m + 3, 3);
  Y.topRows(n) = X;
  Y.middleRows(n, n) = X.rowwise() + Eigen::RowVector3d(0, gap, 0);
  G.topRows(m) = F;
  G.middleRows(m, m) = F.array() + static_cast<int>(n);
  for (int t = 0; t < 3; ++t) {  // loose triangles: components of three vertices (a dense 3 by 3 problem)
    const Eigen::Index b = 2 * n + 3 * t;
    Y.row(b) = Eigen::RowVector3d(0.1 * t, -gap, 0);
    Y.row(b + 1) = Y.row(b) + Eigen::RowVector3d(0.05, 0, 0);
    Y.row(b + 2) = Y.row(b) + Eigen::RowVector3d(0, 0.04, 0.01);
    G.row(2 * m + t) << static_cast<int>(b), static_cast<int>(b + 1), static_cast<int>(b + 2);
  }
  const Mesh pair = make_mesh(Y, G);
  ASSERT_EQ(pair.n_faces(), static_cast<size_t>(2 * m + 3));
  FeatureMapOptions o;
  o.method = FeatureMapMethod::Adf;
  const FeatureMap both = feature_map(pair, o);
  const double total = face_areas(pair).sum(), share = face_areas(s.shape.textured).sum() / total;
  const Eigen::VectorXd alone = share * s.adf.field;
  const double scale = alone.cwiseAbs().maxCoeff();
  EXPECT_LT((both.field.head(n) - alone).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_LT((both.field.segment(n, n) - alone).cwiseAbs().maxCoeff(), 1e-6 * scale);
  EXPECT_TRUE(both.field.tail(9).allFinite());
  EXPECT_GT(both.field.tail(9).minCoeff(), 0);
  EXPECT_EQ(both.weights.head(n), both.weights.segment(n, n));
  std::printf("  two sticks: IoU %.3f of each copy's map with the stick's alone, %s\n",
              iou(both.weights.head(n), s.adf.weights), both.summary.describe().c_str());
  EXPECT_GT(iou(both.weights.head(n), s.adf.weights), 0.8);
}

// close_features (the importance map's close_gaps): a gap two or three rings wide between important
// bands takes their weight; a wide unimportant region keeps its zeros beyond the closing's reach; no
// weight goes down.
TEST(FeatureMap, ClosingFillsThinGapsAndKeepsWideUnimportantRegions) {
  const Mesh m = plane(40, 1.0);
  const MatrixX3d X = positions(m);
  const double x0 = X.col(0).minCoeff(), w = X.col(0).maxCoeff() - x0, h = w / 40;
  Eigen::VectorXd f(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double x = (X(i, 0) - x0) / w;  // 0..1
    f[i] = (x < 0.3 || (x > 0.36 && x < 0.6)) ? 1.0 : 0.0;  // a gap of about 2 edges at 0.3..0.36
  }
  const int k = 3;
  const Eigen::VectorXd g = close_features(m, f, k);
  int gap = 0, wide = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    EXPECT_GE(g[i], f[i]);
    const double x = (X(i, 0) - x0) / w;
    if (x >= 0.3 && x <= 0.36) {
      ++gap;
      EXPECT_DOUBLE_EQ(g[i], 1.0) << "gap vertex at x " << x;
    }
    if ((X(i, 0) - x0) >= 0.6 * w + 2 * k * h) {
      ++wide;
      EXPECT_DOUBLE_EQ(g[i], 0.0) << "wide region at x " << x;
    }
  }
  EXPECT_GT(gap, 40);
  EXPECT_GT(wide, 200);
  EXPECT_EQ(FeatureMapOptions{}.close_gaps, 0);  // off by default
}

namespace {
// A flat cut-out, like a gingerbread figure: a plus of four arms 0.2 wide on a 40 × 40 grid over [0, 1]².
Mesh flat_plus() {
  const int n = 40;
  MatrixX3d V((n + 1) * (n + 1), 3);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) V.row(i * (n + 1) + j) << double(i) / n, double(j) / n, 0.0;
  std::vector<Eigen::Vector3i> F;
  auto id = [&](int i, int j) { return i * (n + 1) + j; };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double x = (i + 0.5) / n, y = (j + 0.5) / n;
      if (std::abs(x - 0.5) > 0.1 && std::abs(y - 0.5) > 0.1) continue;
      F.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      F.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  // Only the vertices the faces use, renumbered.
  std::vector<int> used(V.rows(), -1);
  int k = 0;
  for (const auto& f : F)
    for (int c = 0; c < 3; ++c)
      if (used[f[c]] < 0) used[f[c]] = k++;
  MatrixX3d U(k, 3);
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (used[v] >= 0) U.row(used[v]) = V.row(v);
  MatrixX3i G(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t f = 0; f < F.size(); ++f)
    for (int c = 0; c < 3; ++c) G(static_cast<Eigen::Index>(f), c) = used[F[f][c]];
  return make_mesh(U, G);
}
}  // namespace

// Issue 25: the outline of a flat or open model is relief (importance_outline): on a flat cut-out the surface's
// smoothing hardly sees the arms' ends, the outline term gives them weight (0.84 against 0.10 without; an
// arm's straight side between two corners 0.73 against 0.39: the loop's smoothing reaches 2 s² steps); a closed
// mesh has no outline, and its map is the same with the term on or off.
TEST(FeatureMap, TheOutlineOfAFlatCutOutIsRelief) {
  const Mesh m = flat_plus();
  FeatureMapOptions on, off;
  off.importance_outline = false;
  const Eigen::VectorXd f_on = feature_map(m, on).weights, f_off = feature_map(m, off).weights;
  const MatrixX3d X = positions(m);
  double corner_on = 1, corner_off = 1, side_on = 0, side_off = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double x = X(i, 0), y = X(i, 1);
    const bool tip_corner = (std::abs(x) < 1e-9 || std::abs(x - 1) < 1e-9) && std::abs(std::abs(y - 0.5) - 0.1) < 1e-9;
    const bool mid_side = std::abs(std::abs(y - 0.5) - 0.1) < 1e-9 && std::abs(x - 0.2) < 1e-9;  // an arm's side
    if (tip_corner) corner_on = std::min(corner_on, f_on[i]), corner_off = std::min(corner_off, f_off[i]);
    if (mid_side) side_on = std::max(side_on, f_on[i]), side_off = std::max(side_off, f_off[i]);
  }
  std::printf("  flat plus: arm-end corners %.3f (without the outline term %.3f), an arm's straight side %.3f (%.3f)\n",
              corner_on, corner_off, side_on, side_off);
  EXPECT_GT(corner_on, 0.75);
  EXPECT_GT(corner_on, corner_off + 0.5);
  const Mesh closed = stick().shape.textured;
  EXPECT_EQ(feature_map(closed, on).weights, feature_map(closed, off).weights);
}

namespace {
// A flat disk of radius 1 with a bump at its centre, over K rings of M vertices; with \p seam its rings up to K/2 and from K/2 are two patches
// whose circle r = 1/2 is stored twice (unwelded, as the teapot's Bézier patches are).
Mesh flat_disk(bool seam) {
  const int K = 32, M = 128, mid = K / 2;
  std::vector<Vec3> V{{0, 0, 0.2}};
  std::vector<std::vector<int>> ring(K + 2);
  auto add_ring = [&](int slot, int k) {
    for (int j = 0; j < M; ++j) {
      const double r = double(k) / K, t = 2 * M_PI * j / M;
      ring[slot].push_back(static_cast<int>(V.size()));
      V.emplace_back(r * std::cos(t), r * std::sin(t), 0.2 * std::exp(-r * r / 0.005));  // a bump at the centre
    }
  };
  for (int k = 1; k <= K; ++k) add_ring(k, k);
  if (seam) add_ring(K + 1, mid);  // the outer patch's own copy of the middle circle
  std::vector<Eigen::Vector3i> F;
  for (int j = 0; j < M; ++j) F.emplace_back(0, ring[1][j], ring[1][(j + 1) % M]);
  for (int k = 1; k < K; ++k) {
    const std::vector<int>& a = (seam && k == mid) ? ring[K + 1] : ring[k];
    for (int j = 0; j < M; ++j) {
      const int j1 = (j + 1) % M;
      F.emplace_back(a[j], ring[k + 1][j], ring[k + 1][j1]);
      F.emplace_back(a[j], ring[k + 1][j1], a[j1]);
    }
  }
  return test::soup(V, F);
}
}  // namespace

TEST(FeatureMap, ASeamBetweenUnweldedPatchesIsNotAnOutline) {
  const Mesh welded = flat_disk(false), seamed = flat_disk(true);
  const FeatureMapOptions o;
  const Eigen::VectorXd fw = feature_map(welded, o).weights, fs = feature_map(seamed, o).weights;
  const MatrixX3d Xs = positions(seamed);
  double seam = 0, rim = 1, welded_mid = 0;
  for (Eigen::Index i = 0; i < Xs.rows(); ++i) {
    const double r = Xs.row(i).head<2>().norm();
    if (std::abs(r - 0.5) < 1e-9) seam = std::max(seam, fs[i]);
    if (std::abs(r - 1) < 1e-9) rim = std::min(rim, fs[i]);
  }
  const MatrixX3d Xw = positions(welded);
  for (Eigen::Index i = 0; i < Xw.rows(); ++i)
    if (std::abs(Xw.row(i).head<2>().norm() - 0.5) < 1e-9) welded_mid = std::max(welded_mid, fw[i]);
  std::printf("  disk: the seam r = 1/2 %.3f (the welded disk's circle there %.3f), the rim %.3f\n", seam, welded_mid, rim);
  EXPECT_LT(seam, welded_mid + 0.1);  // the seam reads as the welded disk's middle circle does: plain
  EXPECT_LT(seam, 0.3);
}
