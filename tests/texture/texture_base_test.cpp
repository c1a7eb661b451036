// The base shape under a textured surface (texture/base_shape.h, thesis Sec. 8.3.1).

#include <algorithm>
#include <cmath>
#include <iostream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/texture/measures.h"
#include "geotex/texture/texture.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

namespace {

// How the base treats the stick's tentacles: the smallest |d| at a foot against the tentacle's length
// (1: the whole tentacle is texture), and the base's radial offset from the capsule in the footprints.
struct StickBase {
  double tip_ratio = 1e9, offset_lo = 1e9, offset_hi = -1e9;
};
StickBase measure_stick(const TexturedShape& s, const std::vector<Tentacle>& info, const MatrixX3d& B) {
  StickBase m;
  const MatrixX3d X = positions(s.textured);
  for (const auto& t : info) m.tip_ratio = std::min(m.tip_ratio, (X.row(t.foot) - B.row(t.foot)).norm() / t.length);
  const Eigen::VectorXd inside = tentacle_truth(s.base, info, TentacleOptions().radius);
  for (Eigen::Index i = 0; i < B.rows(); ++i)
    if (inside[i] > 0) {  // the feet are on the cylinder: radius 1 about the x axis
      const double r = std::hypot(B(i, 1), B(i, 2)) - 1;
      m.offset_lo = std::min(m.offset_lo, r);
      m.offset_hi = std::max(m.offset_hi, r);
    }
  return m;
}

}  // namespace

TEST(TextureBase, TentaclesLieOutsideTheRobustBaseAndDisplacementsFollowTheNormal) {
  std::vector<Tentacle> info;
  const TexturedShape s = tentacle_stick(0, &info);
  const BaseShape robust = base_shape(s.textured);
  BaseShapeOptions thesis;
  BaseShapeOptions::table().apply_preset(thesis, "thesis");
  const BaseShape smoothed = base_shape(s.textured, thesis);
  const StickBase a = measure_stick(s, info, robust.positions), b = measure_stick(s, info, smoothed.positions);
  std::cout << fmt::format(
      "[ tentacle stick L0 base ] robust: tip |d| / length >= {:.3f}, footprint radial offset [{:.3f}, {:.3f}], median "
      "off-normal {:.2f} deg, {} fits | thesis smoothing: {:.3f}, [{:.3f}, {:.3f}], {:.2f} deg, {} steps{}\n",
      a.tip_ratio, a.offset_lo, a.offset_hi, robust.median_off_normal_deg, robust.passes, b.tip_ratio, b.offset_lo,
      b.offset_hi, smoothed.median_off_normal_deg, smoothed.passes, smoothed.stopped ? "" : " (step cap)");
  // The whole of every tentacle is texture: the base under it stays on the capsule (within 3 % of the
  // capsule's radius), so each tip is its full length away.
  EXPECT_GT(a.tip_ratio, 0.97);
  EXPECT_GT(a.offset_lo, -0.03);
  EXPECT_LT(a.offset_hi, 0.03);
  EXPECT_LT(robust.median_off_normal_deg, 1.0);
  Mesh base = s.textured;
  set_positions(base, robust.positions);
  EXPECT_EQ(folded_faces(base), 0u);
  // The thesis' smoothing stops at its step cap with part of each tentacle in the base.
  EXPECT_FALSE(smoothed.stopped);
  EXPECT_LT(b.tip_ratio, 0.9);
  // What base_shape() reports per vertex is what off_normal_angles() measures.
  EXPECT_LT((robust.off_normal_deg - off_normal_angles(base, positions(s.textured))).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GE(robust.projected.minCoeff(), 0.0);
  EXPECT_LE(robust.projected.maxCoeff(), 1.0);
  EXPECT_LT(robust.projected.sum(), 0.95 * robust.projected.size());  // protrusions keep the fit
}

TEST(TextureBase, OnAScanDisplacementsFollowTheNormalAndTheRoundTripIsExact) {
  // A scan-like input: a spiky sphere with noise on every vertex.
  const TexturedShape s = make_shape("spiky-sphere", 1);
  NoiseOptions no;
  no.sigma = 0.1;
  Mesh scan = s.textured;
  set_positions(scan, add_noise(s.textured, no));
  const BaseShape robust = base_shape(scan);
  BaseShapeOptions thesis;
  BaseShapeOptions::table().apply_preset(thesis, "thesis");
  const BaseShape smoothed = base_shape(scan, thesis);
  std::cout << fmt::format("[ noisy spiky sphere L1 ] median off-normal: robust {:.2f} deg, thesis smoothing {:.2f} deg\n",
                           robust.median_off_normal_deg, smoothed.median_off_normal_deg);
  EXPECT_LT(robust.median_off_normal_deg, 2.0);
  EXPECT_GT(smoothed.median_off_normal_deg, 10.0);
  Mesh base = scan;
  set_positions(base, robust.positions);
  TextureCodec codec(base);
  EXPECT_LT((codec.apply(codec.extract(positions(scan))) - positions(scan)).rowwise().norm().maxCoeff(),
            1e-3 * mean_edge_length(base));
  // The base lies near the true one, the spikes are texture.
  const double h = mean_edge_length(s.base);
  std::vector<double> e;
  for (Eigen::Index i = 0; i < robust.positions.rows(); ++i) e.push_back((robust.positions.row(i) - positions(s.base).row(i)).norm() / h);
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  EXPECT_LT(e[e.size() / 2], 0.3);
}

TEST(TextureBase, OptionsAreCheckedAndIsolatedVerticesStay) {
  const TexturedShape s = make_shape("spiky-sphere", 0);
  BaseShapeOptions o;
  o.scale = 0;
  EXPECT_THROW(base_shape(s.textured, o), InvalidInput);
  o = {};
  o.outlier = std::nan("");
  EXPECT_THROW(base_shape(s.textured, o), InvalidInput);
  // An isolated vertex has no normal: it keeps its place (zero displacement).
  MatrixX3d V(positions(s.textured).rows() + 1, 3);
  V << positions(s.textured), Eigen::RowVector3d(5, 5, 5);
  const Mesh m = make_mesh(V, faces(s.textured));
  const BaseShape b = base_shape(m);
  EXPECT_EQ((b.positions.row(V.rows() - 1) - V.row(V.rows() - 1)).norm(), 0.0);
}

TEST(TextureBaseData, ScanDisplacementsFollowTheBaseNormal) {
  GEOTEX_REQUIRE_DATA();
  const Mesh m = read_mesh(geotex::test::data_dir() / "cheburashka.obj");
  const BaseShape robust = base_shape(m);
  BaseShapeOptions thesis;
  BaseShapeOptions::table().apply_preset(thesis, "thesis");
  const BaseShape smoothed = base_shape(m, thesis);
  std::cout << fmt::format("[ cheburashka ] median off-normal: robust {:.2f} deg ({} vertices kept the fit to stay "
                           "unfolded), thesis smoothing {:.2f} deg\n",
                           robust.median_off_normal_deg, robust.unfolded, smoothed.median_off_normal_deg);
  EXPECT_LT(robust.median_off_normal_deg, 2.0);
  EXPECT_LT(robust.median_off_normal_deg, 0.2 * smoothed.median_off_normal_deg);
}

// Components are fitted independently (issue 30: 10^5 disjoint triangles took minutes to set up): the
// base of 300 translated copies of a bumpy patch is the copies of the patch's base, translated.
TEST(BaseShape, CopiesOfAPatchGiveCopiesOfItsBase) {
  SpikeOptions spikes;
  spikes.count = 3;
  const Mesh patch = spiky(plane(10, 1.0), spikes).textured;
  const MatrixX3d P = positions(patch);
  const MatrixX3i Fp = faces(patch);
  const int copies = 300;
  const Eigen::Index n = P.rows(), m = Fp.rows();
  MatrixX3d V(copies * n, 3);
  MatrixX3i F(copies * m, 3);
  for (int k = 0; k < copies; ++k) {
    V.middleRows(k * n, n) = P.rowwise() + Eigen::RowVector3d(3.0 * (k % 20), 3.0 * (k / 20), 0.0);
    F.middleRows(k * m, m) = Fp.array() + static_cast<int>(k * n);
  }
  const MatrixX3d B1 = extract_base_shape(patch);
  const MatrixX3d B = extract_base_shape(make_mesh(V, F));
  double worst = 0;
  for (int k = 0; k < copies; ++k) {
    const MatrixX3d Bk = B.middleRows(k * n, n).rowwise() - Eigen::RowVector3d(3.0 * (k % 20), 3.0 * (k / 20), 0.0);
    worst = std::max(worst, (Bk - B1).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-9);
}

// Issue 26: an automatic base per component and at any aspect.
namespace {
Mesh side_by_side(const std::vector<std::pair<Mesh, Eigen::RowVector3d>>& parts) {
  Eigen::Index nv = 0, nf = 0;
  for (const auto& [m, t] : parts) nv += m.n_vertices(), nf += m.n_faces();
  MatrixX3d V(nv, 3);
  MatrixX3i F(nf, 3);
  Eigen::Index v0 = 0, f0 = 0;
  for (const auto& [m, t] : parts) {
    const MatrixX3d P = positions(m);
    const MatrixX3i Fm = faces(m);
    V.middleRows(v0, P.rows()) = P.rowwise() + t;
    F.middleRows(f0, Fm.rows()) = Fm.array() + static_cast<int>(v0);
    v0 += P.rows(), f0 += Fm.rows();
  }
  return make_mesh(V, F);
}
}  // namespace

TEST(TextureBase, ASmallSeparatePieceKeepsItsOwnShapeAndTheWholeRoundTrips) {
  // A spiky sphere beside a 20-face icosahedron of an edge's size (a button on a character): the
  // piece is shape, its base is itself (no texture); the sphere's spikes are still texture.
  SpikeOptions spikes;
  spikes.count = 12;
  const Mesh sphere = spiky(icosphere(3), spikes).textured;
  const double h = mean_edge_length(sphere);
  const Mesh button = icosphere(0, 1.5 * h);
  const Mesh both = side_by_side({{sphere, Eigen::RowVector3d::Zero()}, {button, Eigen::RowVector3d(2, 0, 0)}});
  const TextureExtraction r = texture_extraction(both, nullptr);
  const MatrixX3d X = positions(both), B = positions(r.base);
  const Eigen::Index ns = sphere.n_vertices();
  EXPECT_LT((B.bottomRows(X.rows() - ns) - X.bottomRows(X.rows() - ns)).cwiseAbs().maxCoeff(), 1e-6 * h);
  EXPECT_GT((B.topRows(ns) - X.topRows(ns)).rowwise().norm().maxCoeff(), h);  // the spikes are lifted off
  EXPECT_LT(r.max_error, 1e-3);
}

TEST(TextureBase, AFlatOpenModelKeepsItsOutlineAndHasNoTexture) {
  // A flat square (woody, an alligator: no relief): the base is the model itself. Before, the fit drew
  // the outline inwards and read the shrinkage as texture lying in the plane (90 deg off the normal).
  const Mesh flat = plane(30, 2.0);
  const TextureExtraction r = texture_extraction(flat, nullptr);
  const double h = mean_edge_length(flat);
  EXPECT_LT((positions(r.base) - positions(flat)).rowwise().norm().maxCoeff(), 1e-3 * h);
  EXPECT_NEAR(r.base_area_ratio, 1.0, 1e-3);
  EXPECT_TRUE(r.warnings.empty());
  BaseShapeOptions loose;  // without the outline held, the old fit: the square shrinks
  loose.hold_boundary = false;
  loose.size_share = 0;
  TextureExtractOptions o;
  o.base = loose;
  EXPECT_LT(texture_extraction(flat, nullptr, o).base_area_ratio, 0.99);
}

TEST(TextureBase, AnAutomaticBaseThatRemovesMuchOfTheSurfaceIsWarnedAbout) {
  // The warning follows the base's area ratio, on both sides of the threshold.
  TentacleOptions t;
  const std::vector<Mesh> meshes = {icosphere(3), tentacles(icosphere(3), t).textured};
  for (const Mesh& m : meshes) {
    const TextureExtraction r = texture_extraction(m, nullptr);
    EXPECT_EQ(!r.warnings.empty(), r.base_area_ratio < kBaseAreaWarning) << r.base_area_ratio;
  }
  const TextureExtraction plain = texture_extraction(meshes[0], nullptr);
  EXPECT_GT(plain.base_area_ratio, 0.99);
  const TextureExtraction hairy = texture_extraction(meshes[1], nullptr);
  EXPECT_LT(hairy.base_area_ratio, kBaseAreaWarning) << "the test needs a texture that is most of the surface";
}

TEST(TextureBase, EachComponentsBaseIsTheBaseItHasAlone) {
  // Issue 26: a spiky sphere beside finer flat sheets and small spheres (a character's pieces). The sheets
  // are their own fit; before, their zero distances set the whole mesh's protrusion bound, every vertex of
  // the sphere became a protrusion and its base collapsed (area 0). Each component's base is now the one it
  // has alone.
  SpikeOptions spikes;
  spikes.count = 12;
  const Mesh sphere = spiky(icosphere(3), spikes).textured;
  std::vector<std::pair<Mesh, Eigen::RowVector3d>> parts = {{sphere, Eigen::RowVector3d::Zero()}};
  for (int k = 0; k < 4; ++k) parts.push_back({plane(40, 0.3), Eigen::RowVector3d(-3, 0.7 * k, 0)});
  for (int k = 0; k < 6; ++k) parts.push_back({icosphere(1, 0.05), Eigen::RowVector3d(3, 0.4 * k, 0)});
  const MatrixX3d B = extract_base_shape(side_by_side(parts));
  const MatrixX3d B1 = extract_base_shape(sphere);
  EXPECT_LT((B.topRows(B1.rows()) - B1).cwiseAbs().maxCoeff(), 1e-6 * mean_edge_length(sphere));
}
