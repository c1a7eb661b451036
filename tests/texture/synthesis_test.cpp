// Height-and-tilt texture synthesis (texture/synthesis.h).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/core/self_intersections.h"
#include "geotex/texture/measures.h"
#include "geotex/texture/synthesis.h"
#include "geotex/tools/shapes.h"
#include "../../src/texture/keep_out.h"
#include "test_util.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

struct Exemplar {
  Mesh base;
  Texture texture;
};

// A plate whose displacement is d(x, y) (3D, world frame) everywhere.
template <class D>
Exemplar plate(int n, double size, D d) {
  Exemplar e;
  e.base = plane(n, size);
  MatrixX3d X = positions(e.base);
  for (Eigen::Index i = 0; i < X.rows(); ++i) X.row(i) += d(X(i, 0), X(i, 1)).transpose();
  e.texture = extract_texture(e.base, X);
  return e;
}

void print(const SynthesisQuality& q, const std::string& what) {
  std::cout << fmt::format("[ {} ] histogram TV {:.3f} W1 {:.3f}; rms {:.4g} vs {:.4g}; features {} vs {}, spacing "
                           "{:.4g} vs {:.4g} ({:+.1f}%); lean error {:.1f} deg; seam step 99% {:.3f} max {:.3f} "
                           "(within {:.3f} / {:.3f}); coverage {:.4f}; folded {}\n",
                           what, q.histogram_tv, q.histogram_w1, q.target_rms, q.exemplar_rms, q.target_features,
                           q.exemplar_features, q.target_spacing, q.exemplar_spacing, 100 * q.spacing_change,
                           q.lean_angle_error_deg, q.seam_step99, q.seam_step_max, q.within_step99,
                           q.within_step_max, q.coverage, q.folded);
}

}  // namespace

TEST(Synthesis, AConstantExemplarGivesAConstantTexture) {
  const Exemplar e = plate(24, 2.0, [](double, double) { return Vec3(0.02, 0, 0.05); });
  const Mesh target = icosphere(3);
  SynthesisOptions o;
  o.scale = 0.5;
  o.refine_ratio = 0;
  const SynthesisResult r = synthesize_texture(e.base, e.texture, target, o);
  ASSERT_EQ(r.texture.height.size(), static_cast<Eigen::Index>(target.n_vertices()));
  // In the exemplar frame, x along its anchor (+x). Within 3 %: the exemplar disk's conformal map turns
  // +u by ~1° away from x over the disk, up to ~3° towards its rim (a polygonal disk of a grid), so the
  // exemplar itself leans so (and cut seams copy it, not averaged over patches; its size varies by ~1e-4
  // too). Which placement a vertex copies is a tie between equal costs here, broken by rounding: the
  // solver's wider supernodes (resize speed, 2026-12-07) moved one vertex to a 3.1° lean (2.01 %).
  const Vec3 expected = 0.5 * Vec3(0.02, 0, 0.05);
  for (Eigen::Index i = 0; i < r.local.rows(); ++i) {
    ASSERT_GE(r.owner[i], 0) << "vertex " << i << " not covered";
    ASSERT_LT((r.local.row(i).transpose() - expected).norm(), 3e-2 * expected.norm()) << "vertex " << i << ": " << r.local.row(i);
  }
  const double h = expected.norm();
  EXPECT_LT((r.texture.height.array() - h).abs().maxCoeff(), 2e-4 * h);
  // The result leans along the field: the textured point minus the base's is x·f + z·n.
  const MatrixX3d N = vertex_normals(r.target, NormalWeighting::Angle);
  const MatrixX3d D = r.textured - positions(r.target);
  double worst = 0;
  for (Eigen::Index i = 0; i < D.rows(); ++i)
    worst = std::max(worst, (D.row(i) - expected.x() * r.field.row(i) - expected.z() * N.row(i)).norm());
  EXPECT_LT(worst, 0.03 * h);
}

TEST(Synthesis, APeriodicExemplarKeepsItsPeriod) {
  const double P = 0.5, a = 0.04;
  const Exemplar e = plate(64, 4.0, [&](double x, double y) {
    return Vec3(0, 0, a * std::max(0.0, std::cos(2 * M_PI * x / P) * std::cos(2 * M_PI * y / P)));
  });
  // Onto a flat plate (a larger one), at scale 1: the bumps keep their period P (nearest neighbours at
  // P / √2: cos·cos has maxima at (0, 0) and (P/2, P/2)).
  const Mesh target = plane(90, 6.0);
  SynthesisOptions o;
  o.scale = 1;
  o.refine_ratio = 0;
  o.patch_radius = 0.3;
  o.blend_power = 8;
  o.candidates = 96;
  const SynthesisResult r = synthesize_texture(e.base, e.texture, target, o);
  const SynthesisQuality q = synthesis_quality(e.base, e.texture, r, o);
  print(q, "periodic");
  EXPECT_NEAR(q.exemplar_spacing, P / std::sqrt(2.0), 0.05 * P);
  EXPECT_LT(std::abs(q.target_spacing / (P / std::sqrt(2.0)) - 1), 0.10);
  EXPECT_LT(std::abs(q.spacing_change), 0.10);
  EXPECT_GT(q.coverage, 0.999);
  EXPECT_LT(q.histogram_tv, 0.15);
}

TEST(Synthesis, TheSameSeedGivesTheSameResult) {
  const Exemplar e = plate(40, 2.0, [](double x, double y) {
    return Vec3(0, 0, 0.05 * std::sin(7 * x) * std::sin(5 * y + x * x));
  });
  const Mesh target = icosphere(3);
  SynthesisOptions o;
  o.scale = 0.4;
  o.refine_ratio = 0;
  const SynthesisResult a = synthesize_texture(e.base, e.texture, target, o);
  const SynthesisResult b = synthesize_texture(e.base, e.texture, target, o);
  EXPECT_EQ(a.centers, b.centers);
  EXPECT_EQ((a.textured - b.textured).cwiseAbs().maxCoeff(), 0.0);
  o.seed = 2;
  const SynthesisResult c = synthesize_texture(e.base, e.texture, target, o);
  EXPECT_GT((a.textured - c.textured).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(Synthesis, TheMaskIsRespectedAndTheRestCovered) {
  const Exemplar e = plate(40, 2.0, [](double x, double y) {
    return Vec3(0, 0, 0.05 * std::sin(7 * x) * std::sin(5 * y + x * x));
  });
  const Mesh target = icosphere(3);
  const MatrixX3d X = positions(target);
  SynthesisGuides g;
  g.weight = (X.col(2).array() > 0).cast<double>();  // the northern half only
  SynthesisOptions o;
  o.scale = 0.4;
  o.refine_ratio = 0;
  o.progress = [last = -1.0](double f, std::string_view) mutable {
    EXPECT_GE(f, last);
    last = f;
  };
  const SynthesisResult r = synthesize_texture(e.base, e.texture, target, o, g);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    if (X(i, 2) <= 0) {
      EXPECT_EQ(r.local.row(i).norm(), 0.0) << "vertex " << i;
      EXPECT_LT(std::abs(r.texture.height[i]), 1e-9) << "vertex " << i;
    } else {
      EXPECT_GE(r.owner[i], 0) << "vertex " << i << " not covered";
    }
  }
  for (int c : r.centers) EXPECT_GT(X(c, 2), 0);
  const SynthesisQuality q = synthesis_quality(e.base, e.texture, r, o);
  print(q, "masked");
  EXPECT_GT(q.coverage, 0.999);
}

TEST(Synthesis, TentaclesFollowTheField) {
  const TexturedShape p = tentacle_plane(0);
  const Texture t = extract_texture(p.base, positions(p.textured));
  const Mesh target = icosphere(5, 1.0);  // as fine as the exemplar at this scale: no refinement
  SynthesisOptions o;
  o.scale = 0.6;
  o.direction = Vec3(0, 0, 1);
  const SynthesisResult r = synthesize_texture(p.base, t, target, o);
  const SynthesisQuality q = synthesis_quality(p.base, t, r, o);
  print(q, "tentacles on a sphere");
  for (const auto& w : r.warnings) std::cout << "warning: " << w << "\n";
  EXPECT_GT(q.coverage, 0.999);
  EXPECT_LT(q.lean_angle_error_deg, 10.0);
  EXPECT_LT(q.histogram_tv, 0.3);
  // Issue 20: no folded faces, seams about as smooth as the inside of patches (blended seams measured
  // 1.4x; this small case 1.10x with CHOLMOD, 1.18x with the sanitizer build's fallback solver, whose
  // rounding picks other placements), the tentacles' spacing kept.
  EXPECT_EQ(q.folded, 0u);
  EXPECT_LT(q.seam_step99, 1.25 * q.within_step99);
  EXPECT_LT(std::abs(q.spacing_change), 0.15);
  EXPECT_GT(q.target_rms, 0.8 * q.exemplar_rms);
}

// Without feathering or unfolding, a cut copies: every vertex holds exactly the exemplar displacement of
// the patch it belongs to (no average of two patches), and the seams' steps stay near the inside's.
TEST(Synthesis, CutSeamsCopyTheExemplarAndStaySmooth) {
  const Exemplar e = plate(40, 2.0, [](double x, double y) {
    return Vec3(0.01 * std::cos(3 * y), 0, 0.05 * std::sin(7 * x) * std::sin(5 * y + x * x));
  });
  const Mesh target = icosphere(4);
  SynthesisOptions o;
  o.scale = 0.4;
  o.refine_ratio = 0;
  o.feather = 0;
  o.unfold = false;
  const SynthesisResult r = synthesize_texture(e.base, e.texture, target, o);
  for (Eigen::Index i = 0; i < r.local.rows(); ++i) {
    ASSERT_GE(r.owner[i], 0) << "vertex " << i << " not covered";
    ASSERT_LT((r.local.row(i) - r.copied.row(i)).norm(), 1e-12) << "vertex " << i;
  }
  const SynthesisQuality copy = synthesis_quality(e.base, e.texture, r, o);
  // Feathered (the default) against blended: the cut's seams are smoother than the blend's, and no rougher
  // than the patches' inside.
  o.feather = 2;
  const SynthesisQuality cut = synthesis_quality(e.base, e.texture, synthesize_texture(e.base, e.texture, target, o), o);
  o.seams = SeamMethod::Blend;
  const SynthesisQuality blend =
      synthesis_quality(e.base, e.texture, synthesize_texture(e.base, e.texture, target, o), o);
  print(copy, "cut seams, not feathered");
  print(cut, "cut seams");
  print(blend, "blended seams");
  EXPECT_LT(cut.seam_step99, 1.1 * cut.within_step99);
  EXPECT_LT(cut.seam_step99 / cut.within_step99, blend.seam_step99 / blend.within_step99);
  EXPECT_GT(copy.target_rms, blend.target_rms);  // no averaging of unrelated patches
}

TEST(Synthesis, OutOfRangeOptionsAndWrongSizedInputsThrow) {
  const Exemplar e = plate(10, 1.0, [](double, double) { return Vec3(0, 0, 0.01); });
  const Mesh target = icosphere(1);
  SynthesisOptions o;
  o.patch_radius = 1.5;
  EXPECT_THROW(synthesize_texture(e.base, e.texture, target, o), InvalidInput);
  SynthesisGuides g;
  g.weight = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(synthesize_texture(e.base, e.texture, target, {}, g), InvalidInput);
  Texture bad = e.texture;
  bad.height.resize(2);
  EXPECT_THROW(synthesize_texture(e.base, bad, target), InvalidInput);
}

// Issue 27: the damage counter against an analytic case: two triangles crossing through each other's
// interiors (each crossed by an edge of the other), a third far away; a sphere crosses nothing.
TEST(SelfIntersections, CountsCrossingFacesOnly) {
  MatrixX3d V(9, 3);
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0,      // in z = 0
      0.5, 0.5, -1, 0.5, 0.5, 1, 1.5, -0.5, 0,  // crosses the first: its edge (3, 4) pierces it
      5, 5, 5, 6, 5, 5, 5, 6, 5;        // far away
  MatrixX3i F(3, 3);
  F << 0, 1, 2, 3, 4, 5, 6, 7, 8;
  const std::vector<char> hit = self_intersecting_faces(V, F);
  EXPECT_EQ(hit[0], 1);
  EXPECT_EQ(hit[1], 1);  // in the plane x + y = 1: the first's edge (0, 1) meets it at (1, 0, 0), inside
  EXPECT_EQ(hit[2], 0);
  const Mesh sphere = icosphere(4);
  const std::vector<char> none = self_intersecting_faces(positions(sphere), faces(sphere));
  EXPECT_EQ(std::count(none.begin(), none.end(), 1), 0);
}

namespace {
// A coarse target that needs refinement for the tentacle plate at the default share.
struct Tentacles {
  TexturedShape p = tentacle_plane(0);
  Texture t = extract_texture(p.base, positions(p.textured));
};
}  // namespace

// Issue 27: the estimate comes before the work (before any stage past the exemplar) and is within a
// factor 1.5 of the vertices the run ends with; a target that needs refinement gets it; the damage counts
// are recounts, and the shrunk share is what a recount against the same run without unfolding gives.
TEST(Synthesis, DefaultsOnACoarseSphereEstimateRefineAndCountTheDamage) {
  const Tentacles e;
  const Mesh target = icosphere(2);
  SynthesisOptions o;
  o.direction = Vec3(0, 0, 1);
  o.vertex_budget = 20'000;  // the automatic share keeps the test small (the default budget is 100,000)
  std::vector<std::string> events;
  o.progress = [&](double, std::string_view stage) {
    if (events.empty() || events.back() != stage) events.emplace_back(stage);
  };
  size_t estimated = 0;
  o.on_estimate = [&](const SynthesisEstimate& est) {
    events.emplace_back("estimate");
    estimated = est.vertices;
    EXPECT_TRUE(est.refine);
  };
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, o);
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events[0], "exemplar");
  EXPECT_EQ(events[1], "estimate");
  const double n = static_cast<double>(r.target.n_vertices());
  EXPECT_GT(r.added_vertices, 0u);
  EXPECT_GT(estimated, n / 1.5);
  EXPECT_LT(estimated, n * 1.5);
  // The damage count is the counter's on the result against the refined base, and placement avoids
  // crossings: none beyond the base's own (7 before it did, bench/synthesis.md).
  EXPECT_EQ(r.excess_self_intersecting, 0u);
  {
    const std::vector<char> hit = self_intersecting_faces(r.textured, faces(r.target));
    const std::vector<char> base = self_intersecting_faces(positions(r.target), faces(r.target));
    const size_t a = std::count(hit.begin(), hit.end(), 1), b = std::count(base.begin(), base.end(), 1);
    EXPECT_EQ(r.self_intersecting, a);
    EXPECT_EQ(r.base_self_intersecting, b);
    EXPECT_EQ(r.excess_self_intersecting, a > b ? a - b : 0);
  }
  EXPECT_NEAR(r.refined_share, r.added_vertices / n, 1e-12);
  // Recount the shrunk vertices: the same seed without unfolding places the same patches (and drops the
  // same features); the recount holds where nothing was zeroed after encoding, so both runs of the recount
  // leave the repair after encoding out (with the narrower dips of the seventh session it zeroed 727 vertices
  // here, and re-unfolded), and the removal of broken features too (it runs after unfolding: with and without
  // it the pieces left differ, 26 vertices here).
  SynthesisOptions kept = o;
  kept.repair_crossings = false;
  kept.remove_fragments = false;
  kept.progress = {};
  kept.on_estimate = {};
  const SynthesisResult k = synthesize_texture(e.p.base, e.t, target, kept);
  EXPECT_EQ(k.repaired_vertices, 0u);
  SynthesisOptions raw = kept;
  raw.unfold = false;
  const SynthesisResult u = synthesize_texture(e.p.base, e.t, target, raw);
  ASSERT_EQ(u.local.rows(), k.local.rows());
  size_t shrunk = 0;
  for (Eigen::Index i = 0; i < k.local.rows(); ++i) shrunk += k.local.row(i).norm() < 0.99 * u.local.row(i).norm();
  EXPECT_EQ(shrunk, k.unfolded_vertices);
  EXPECT_NEAR(k.shrunk_share, shrunk / n, 1e-12);
  double total = 0;
  for (const auto& [name, sec] : r.stage_seconds) {
    EXPECT_GE(sec, 0.0) << name;
    total += sec;
  }
  EXPECT_GT(total, 0.0);
}

// Issue 27: tentacles around a thin cylinder (radius 0.1, the tentacles about as tall) cross neither the
// cylinder nor each other (a recount by self_intersecting_faces() on the result), and most of the relief
// stays (dropping is the exception, not the rule).
TEST(Synthesis, NoSelfIntersectionOnAThinCylinder) {
  const Tentacles e;
  const Mesh target = cylinder(0.1, 1.0, 24, 24);
  SynthesisOptions o;
  o.direction = Vec3(0, 0, 1);
  o.vertex_budget = 20'000;
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, o);
  const MatrixX3i F = faces(r.target);
  const std::vector<char> hit = self_intersecting_faces(r.textured, F);
  const std::vector<char> base = self_intersecting_faces(positions(r.target), F);
  EXPECT_EQ(std::count(base.begin(), base.end(), 1), 0);
  EXPECT_EQ(std::count(hit.begin(), hit.end(), 1), 0);
  EXPECT_EQ(r.excess_self_intersecting, 0u);
  const double n = static_cast<double>(r.target.n_vertices());
  // Dropping and shrinking are the exception: measured 25 % dropped and 15 % shrunk here before features
  // were dropped whole and the unfolding's dips narrowed (bench/synthesis.md, sixth session; not re-measured).
  EXPECT_LT(static_cast<double>(r.dropped_vertices + r.repaired_vertices), 0.4 * n);
  EXPECT_LT(r.shrunk_share, 0.25);
  // The same run with placement unchecked crosses itself: the test can fail.
  SynthesisOptions unchecked = o;
  unchecked.avoid_crossings = false;
  unchecked.drop_collisions = false;
  unchecked.repair_crossings = false;
  EXPECT_GT(synthesize_texture(e.p.base, e.t, target, unchecked).excess_self_intersecting, 0u);
}

// Issue 27: tall, leaning tentacles on a sphere are seldom shrunk (the goal: at most 5 % of the
// vertices shrunk by over 1 %), not by dropping them instead: colliding features are dropped whole, not cut
// at the patch's rim into walls that fold, and the unfolding's dips are one fold wide. Before both, the
// same run shrank 14.3 % and dropped 13.1 % (bench/synthesis.md); measured after: 3.2 % and 9.9 %, and with
// dips a twentieth of the patch radius (at least the face's edge) instead of a tenth 1.6 % (seventh session).
namespace {
// The tentacle plate's runs onto icosphere(3): the field along z, at most 20,000 vertices.
SynthesisOptions tentacle_sphere_options() {
  SynthesisOptions o;
  o.direction = Vec3(0, 0, 1);
  o.vertex_budget = 20'000;
  return o;
}
}  // namespace

TEST(Synthesis, TentaclesOnASphereAreSeldomShrunk) {
  const Tentacles e;
  const Mesh target = icosphere(3);
  const SynthesisOptions o = tentacle_sphere_options();
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, o);
  const double n = static_cast<double>(r.target.n_vertices());
  EXPECT_LT(r.shrunk_share, 0.025);
  EXPECT_LT(static_cast<double>(r.dropped_vertices + r.repaired_vertices), 0.15 * n);
  EXPECT_EQ(r.excess_self_intersecting, 0u);
  Mesh textured = r.target;
  set_positions(textured, r.textured);
  EXPECT_LE(folded_faces(textured), folded_faces(r.target));
  double largest = 0;
  for (Eigen::Index i = 0; i < r.local.rows(); ++i) largest = std::max(largest, r.local.row(i).norm());
  size_t kept = 0;
  for (Eigen::Index i = 0; i < r.local.rows(); ++i) kept += r.local.row(i).norm() > 0.05 * largest;
  std::cout << fmt::format("[ tentacles on icosphere(3) ] shrunk {:.1f} %, dropped {:.1f} %, displaced {:.1f} %, "
                           "inward {:.2f} % (exemplar {:.2f} %)\n",
                           100 * r.shrunk_share, 100 * (r.dropped_vertices + r.repaired_vertices) / n,
                           100 * kept / n, 100 * r.inward_share, 100 * r.exemplar_inward_share);
  // Faces turned against the base (the "inward faces", ≤ 0.1 %): the leaning tentacles' undersides
  // are turned in the exemplar too; the synthesis turns no more than 0.1 % of the relief beyond its share.
  // Recounted here on the result's meshes (each face's normal against the base face's).
  const MatrixX3i Fi = faces(r.target);
  const MatrixX3d X = positions(r.target);
  double all = 0, against = 0;
  for (Eigen::Index f = 0; f < Fi.rows(); ++f) {
    bool relief = false;
    for (int k = 0; k < 3; ++k) relief |= (r.textured.row(Fi(f, k)) - X.row(Fi(f, k))).norm() > 0.05 * largest;
    if (!relief) continue;
    auto normal = [&](const MatrixX3d& P) {
      return Vec3((P.row(Fi(f, 1)) - P.row(Fi(f, 0))).cross(P.row(Fi(f, 2)) - P.row(Fi(f, 0))));
    };
    all += normal(r.textured).norm();
    against += normal(r.textured).dot(normal(X)) < 0 ? normal(r.textured).norm() : 0.0;
  }
  EXPECT_GT(r.exemplar_inward_share, 0.05);  // the tentacles lean: their undersides face the plate
  EXPECT_NEAR(r.inward_share, against / all, 0.01);
  EXPECT_LE(r.inward_share, r.exemplar_inward_share + 0.001);
}

// Issue 27: features are placed or dropped, not left broken. The connected regions displaced by over 5 % of the
// largest displacement (\p D #V by 3 on \p m), each by its peak |d| and footprint (the sum of its vertex
// areas); \p off_rim: only those off the boundary.
namespace {
std::vector<std::pair<double, double>> feature_peaks(const Mesh& m, const MatrixX3d& D, bool off_rim) {
  const Eigen::VectorXd fa = face_areas(m);
  Eigen::VectorXd va = Eigen::VectorXd::Zero(m.n_vertices());
  for (auto f : m.faces())
    for (auto v : m.fv_range(f)) va[v.idx()] += fa[f.idx()] / 3;
  double largest = 0;
  for (Eigen::Index i = 0; i < D.rows(); ++i) largest = std::max(largest, D.row(i).norm());
  std::vector<char> seen(D.rows(), 0);
  std::vector<std::pair<double, double>> peaks;
  for (Eigen::Index v0 = 0; v0 < D.rows(); ++v0) {
    if (seen[v0] || !(D.row(v0).norm() > 0.05 * largest)) continue;
    std::vector<int> queue{static_cast<int>(v0)};
    seen[v0] = 1;
    double peak = 0, area = 0;
    bool rim = false;
    for (size_t i = 0; i < queue.size(); ++i) {
      const auto vh = m.vertex_handle(queue[i]);
      peak = std::max(peak, D.row(queue[i]).norm());
      area += va[queue[i]];
      rim |= m.is_boundary(vh);
      for (auto w : m.vv_range(vh))
        if (!seen[w.idx()] && D.row(w.idx()).norm() > 0.05 * largest) seen[w.idx()] = 1, queue.push_back(w.idx());
    }
    if (!(off_rim && rim) && queue.size() >= 4) peaks.emplace_back(peak, area);
  }
  return peaks;
}
}  // namespace

// Tentacles on a sphere: after the run no displaced region is lower than half the exemplar's lowest whole
// tentacle or has a footprint under half its smallest (a short broken piece left by a drop, a seam or a rim; both
// measured on the exemplar's mesh, not its raster), nothing crosses beyond the base, nothing more folds; the
// same run without remove_fragments leaves some (the test can fail).
TEST(Synthesis, NoBrokenFeaturesOnASphere) {
  const Tentacles e;
  const Mesh target = icosphere(3);
  const auto own = feature_peaks(e.p.base, positions(e.p.textured) - positions(e.p.base), true);
  ASSERT_GE(own.size(), 2u);
  double lowest = own[0].first, smallest = own[0].second;
  for (const auto& [peak, area] : own) lowest = std::min(lowest, peak), smallest = std::min(smallest, area);
  auto broken = [&](const SynthesisResult& r) {
    size_t k = 0;
    for (const auto& [peak, area] : feature_peaks(r.target, r.local, false))
      k += peak < 0.5 * r.height_factor * lowest || area < 0.5 * r.scale * r.scale * smallest;
    return k;
  };
  SynthesisOptions o = tentacle_sphere_options();
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, o);
  EXPECT_EQ(broken(r), 0u);
  EXPECT_GT(r.fragments_removed, 0u);
  EXPECT_EQ(r.excess_self_intersecting, 0u);
  Mesh textured = r.target;
  set_positions(textured, r.textured);
  EXPECT_LE(folded_faces(textured), folded_faces(r.target));
  o.remove_fragments = false;
  const SynthesisResult left = synthesize_texture(e.p.base, e.t, target, o);
  std::cout << fmt::format("[ tentacles on icosphere(3) ] broken features {} without the pass, {} removed\n",
                           broken(left), r.fragments_removed);
  EXPECT_GT(broken(left), 0u);
}

// Issue 27: a run whose estimate is beyond the cap is refused before any work, naming the estimate.
TEST(Synthesis, RefusesAnEstimateBeyondTheCap) {
  const Tentacles e;
  SynthesisOptions o;
  o.exemplar_share = 0.001;  // a tiny disk: a very fine target
  o.max_vertices = 20'000;
  bool estimated = false;
  std::string last_stage;
  o.on_estimate = [&](const SynthesisEstimate&) { estimated = true; };
  o.progress = [&](double, std::string_view s) { last_stage = s; };
  try {
    synthesize_texture(e.p.base, e.t, icosphere(2), o);
    FAIL() << "not refused";
  } catch (const InvalidInput& x) {
    EXPECT_NE(std::string(x.what()).find("output vertices estimated"), std::string::npos) << x.what();
    EXPECT_NE(std::string(x.what()).find("max_vertices 20000"), std::string::npos) << x.what();
  }
  EXPECT_FALSE(estimated);
  EXPECT_EQ(last_stage, "exemplar");
  // The public estimate agrees with what the run would have been refused for.
  const SynthesisEstimate est = estimate_synthesis(e.p.base, e.t, icosphere(2), o);
  EXPECT_GT(est.vertices, 20'000u);
}

// The automatic keep-out (issue 27): a cube's edges are creases, its faces' middles are not; a sphere has
// none; a tube far narrower than the texture's span is a part smaller than the texture, a wide sphere is not.
TEST(SynthesisKeepOut, CreasesAndPartsSmallerThanTheTextureAreKeptOutAndNothingElse) {
  const Mesh cube = subdivided_cube(10, 1.0);
  const MatrixX3d X = positions(cube);
  const detail::KeepOut k = detail::keep_out(cube, 0.3, 60, true);
  int edges = 0, middles = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const Eigen::Array3d a = X.row(v).transpose().array().abs();
    const int at_side = (a > 0.499).count();  // the cube spans [-0.5, 0.5]^3
    if (at_side >= 2) {
      ++edges;
      EXPECT_LT(k.creases[v], 1e-9) << v;
      EXPECT_LT(k.weight[v], 1e-9) << v;
    }
    if (at_side == 1 && (a < 0.05).count() == 2) {  // a face's middle: 0.5 from every edge
      ++middles;
      EXPECT_DOUBLE_EQ(k.weight[v], 1.0) << v;
    }
  }
  EXPECT_GT(edges, 0);
  EXPECT_GT(middles, 0);
  EXPECT_NEAR(k.area.sum(), 6.0, 1e-9);  // the vertex areas add up to the surface's
  EXPECT_DOUBLE_EQ(detail::keep_out(cube, 0.3, 0, false).weight.minCoeff(), 1.0);  // both off: nothing kept out

  const detail::KeepOut ball = detail::keep_out(icosphere(4, 5.0), 1.0, 60, true);
  EXPECT_DOUBLE_EQ(ball.weight.minCoeff(), 1.0);
  const detail::KeepOut tube = detail::keep_out(cylinder(0.05, 4.0, 24, 80), 1.0, 60, true);
  EXPECT_LT(tube.thin.maxCoeff(), 1e-9);  // 4ρ / span = 0.2 of a disk's area
  EXPECT_DOUBLE_EQ(detail::keep_out(cylinder(0.05, 4.0, 24, 80), 1.0, 60, false).thin.minCoeff(), 1.0);
}

// Issue 27: where dropped features left room for a whole feature, a second pass centres a patch there with one
// of the exemplar's features at its centre (a Poisson-disk fill at the exemplar's spacing), kept only if it
// neither crosses nor folds: less of the sphere is bare than without it (measured 3.1 % against 3.9 %), and
// nothing crosses; with nothing displaced, all of it is bare.
TEST(Synthesis, HolesWhereAWholeTentacleFitsAreFilled) {
  const Tentacles e;
  const Mesh target = icosphere(3);
  const SynthesisOptions o = tentacle_sphere_options();
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, o);
  SynthesisOptions no_fill = o;
  no_fill.fill_holes = false;
  const SynthesisResult u = synthesize_texture(e.p.base, e.t, target, no_fill);
  std::cout << fmt::format("[ tentacles on icosphere(3) ] bare {:.1f} % with the fill ({} patches), {:.1f} % without\n",
                           100 * r.bare_share, r.filled_patches, 100 * u.bare_share);
  EXPECT_EQ(u.filled_patches, 0u);
  EXPECT_GT(r.filled_patches, 0u);
  EXPECT_GT(u.bare_share, 0.0);
  EXPECT_LT(r.bare_share, u.bare_share);
  EXPECT_EQ(r.excess_self_intersecting, 0u);
  Mesh textured = r.target;
  set_positions(textured, r.textured);
  EXPECT_LE(folded_faces(textured), folded_faces(r.target));
  // Nothing displaced: all bare.
  SynthesisOptions flat = o;
  flat.height_scale = 0;
  EXPECT_DOUBLE_EQ(synthesize_texture(e.p.base, e.t, target, flat).bare_share, 1.0);
}

// Issue 27: eyes with no crease round them, as closed pits smaller than the texture's span: a smooth dimple
// on a sphere is kept out (the old keep-out, creases and thin parts, kept nothing out there), the rest of
// the sphere is not, a saddle or a groove (a torus' inner side) is not, and the option turns it off.
namespace {
// \p sphere with a smooth dimple round +z: radius `a` (along the surface), depth `depth` at its centre.
Mesh dimpled(Mesh sphere, double a, double depth) {
  MatrixX3d X = positions(sphere);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double r = X.row(i).norm(), t = std::min(1.0, r * std::acos(std::clamp(X(i, 2) / r, -1.0, 1.0)) / a);
    X.row(i) *= 1 - depth * (1 - t * t) * (1 - t * t) / r;
  }
  set_positions(sphere, X);
  return sphere;
}
}  // namespace

TEST(SynthesisKeepOut, ClosedPitsSmallerThanTheTextureAreKeptOut) {
  const Mesh m = dimpled(icosphere(4), 0.3, 0.15);  // an eye socket: half as deep as it is wide
  const MatrixX3d X = positions(m);
  const detail::KeepOut k = detail::keep_out(m, 0.4, 60, true, 0.15);
  Eigen::Index top = 0, bottom = 0;  // the dimple's centre (on +z: its rim is higher) and the opposite pole
  X.col(2).minCoeff(&bottom);
  (X.col(2).array() / X.rowwise().norm().array()).maxCoeff(&top);
  EXPECT_LT(k.pits[top], 1e-9);
  EXPECT_LT(k.weight[top], 1e-9);
  EXPECT_DOUBLE_EQ(k.pits[bottom], 1.0);
  EXPECT_DOUBLE_EQ(k.creases.minCoeff(), 1.0);  // no crease: only the pit rule finds it
  double kept = 0, all = k.area.sum();
  for (Eigen::Index i = 0; i < X.rows(); ++i) kept += k.pits[i] < 0.5 ? k.area[i] : 0.0;
  EXPECT_LT(kept / all, 0.1);  // the dimple and a quarter span round it, not the sphere
  EXPECT_DOUBLE_EQ(detail::keep_out(m, 0.4, 60, true, 0).pits.minCoeff(), 1.0);              // off
  EXPECT_DOUBLE_EQ(detail::keep_out(icosphere(4), 0.4, 60, true, 0.15).pits.minCoeff(), 1.0);  // no pit
  EXPECT_DOUBLE_EQ(detail::keep_out(torus(1.0, 0.35, 96, 36), 0.3, 60, true, 0.15).pits.minCoeff(), 1.0);
}

namespace {
// Nothing grows at vertex \p kept (weight 0, no displacement), vertex \p open keeps its full weight, and no face
// crosses beyond the base's own.
void expect_kept_out_at(const SynthesisResult& r, Eigen::Index kept, Eigen::Index open) {
  EXPECT_LT(r.weight[kept], 1e-9);
  EXPECT_EQ(r.local.row(kept).norm(), 0.0);
  EXPECT_DOUBLE_EQ(r.weight[open], 1.0);
  EXPECT_EQ(r.excess_self_intersecting, 0u);
}
}  // namespace

TEST(Synthesis, AnEyeWithNoCreaseIsKeptOutByDefault) {
  const Tentacles e;
  const Mesh target = dimpled(icosphere(4), 0.25, 0.1);
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, tentacle_sphere_options());
  // The vertex nearest the dimple's centre (+z): the input's vertices come first in the refined target.
  Eigen::Index top = 0, bottom = 0;
  const MatrixX3d X = positions(target);
  X.col(2).minCoeff(&bottom);
  (X.col(2).array() / X.rowwise().norm().array()).maxCoeff(&top);
  std::cout << fmt::format("[ tentacles on a dimpled icosphere(4) ] kept out {:.1f} % (pits {:.1f} %), weight at the "
                           "dimple {:.2f}, displaced there {:.3g}\n",
                           100 * r.kept_out_share, 100 * r.kept_out_pits, r.weight[top], r.local.row(top).norm());
  expect_kept_out_at(r, top, bottom);
  EXPECT_GT(r.kept_out_share, 0.0);
  EXPECT_LT(r.kept_out_share, 0.1);
}

// Issue 27: eyeballs with no crease round them (cheburashka's), as domes smaller than the texture's span: a
// button-shaped bump sunk into a sphere, its top closed round by a convex ridge and a concave rim, is kept out
// (the creases, thin parts and pits keep nothing out there); the rest of the sphere, a plain sphere, a torus
// (convex outside, saddles inside) and spot (a cow's body, ears, horns and legs) keep no dome out; the option
// at 0 turns it off.
namespace {
// \p sphere with a button round +z: radial height h (1 − t⁸)² at t = (angle from +z) / a < 1, so its top is about
// as curved as the sphere, its edge a ridge (mean curvature about 1 + 9 h / a² at t ≈ 0.8) and its foot a valley
// (about 1 − 17 h / a² at t ≈ 0.95) meeting the sphere with no kink.
Mesh buttoned(Mesh sphere, double a, double h, const std::vector<Vec3>& at = {Vec3(0, 0, 1)}) {
  MatrixX3d X = positions(sphere);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const Vec3 x = X.row(i).transpose();
    for (const Vec3& c : at) {
      const double t = std::acos(std::clamp(x.dot(c) / (x.norm() * c.norm()), -1.0, 1.0)) / a, t8 = std::pow(t, 8);
      if (t < 1) X.row(i) *= 1 + h * (1 - t8) * (1 - t8) / X.row(i).norm();
    }
  }
  set_positions(sphere, X);
  return sphere;
}
}  // namespace

TEST(SynthesisKeepOut, DomesSmallerThanTheTextureAreKeptOut) {
  const Mesh m = buttoned(icosphere(5), 0.35, 0.08);
  const MatrixX3d X = positions(m);
  const detail::KeepOut k = detail::keep_out(m, 0.4, 60, true, 0.15, 1.0);
  Eigen::Index top = 0, bottom = 0;
  X.col(2).maxCoeff(&top);
  X.col(2).minCoeff(&bottom);
  EXPECT_LT(k.domes[top], 1e-9);
  EXPECT_LT(k.weight[top], 1e-9);
  EXPECT_DOUBLE_EQ(k.domes[bottom], 1.0);
  EXPECT_DOUBLE_EQ(k.creases[top] * k.thin[top] * k.pits[top], 1.0);  // only the dome rule finds it
  double kept = 0, all = k.area.sum();
  for (Eigen::Index i = 0; i < X.rows(); ++i) kept += k.domes[i] < 0.5 ? k.area[i] : 0.0;
  std::cout << fmt::format("[ a button on icosphere(5) ] domes keep out {:.1f} %\n", 100 * kept / all);
  EXPECT_LT(kept / all, 0.1);  // the button and a quarter span round it (its angle 0.35: 3 % of the sphere)
  EXPECT_GT(kept / all, 0.005);
  EXPECT_DOUBLE_EQ(detail::keep_out(m, 0.4, 60, true, 0.15, 0).domes.minCoeff(), 1.0);  // off
  for (double span : {0.1, 0.2, 0.4}) {
    EXPECT_DOUBLE_EQ(detail::keep_out(icosphere(5), span, 0, false, 0, 1.0).domes.minCoeff(), 1.0) << span;
    EXPECT_DOUBLE_EQ(detail::keep_out(torus(1.0, 0.35, 96, 36), span, 0, false, 0, 1.0).domes.minCoeff(), 1.0)
        << span;
  }
  const Mesh spot = read_mesh(std::filesystem::path(geotex::test::source_dir()) / "data" / "spot.obj");
  for (double span : {0.05, 0.1, 0.2})  // spot is 2.6 long; the tentacle plate's span on it is about 0.15
    EXPECT_DOUBLE_EQ(detail::keep_out(spot, span, 0, false, 0, 1.0).domes.minCoeff(), 1.0) << span;
}

// Issue 27: an eyeball is a lone dome on a calm surface; igea's hair curls are a field of such islands side by
// side (bench/synthesis.md, eleventh session). The same buttons as above, one at each of an icosahedron's 12
// vertices (1.1 rad apart, 3.2 button radii: the rims 0.4 rad apart), keep none out as domes; the lone button on
// the same sphere, at the same span, is kept out.
TEST(SynthesisKeepOut, AFieldOfDomesIsNotKeptOutALoneDomeIs) {
  const Mesh ico = icosphere(0);  // its 12 vertices: the buttons' axes
  std::vector<Vec3> at;
  for (auto v : ico.vertices()) at.push_back(Vec3(positions(ico).row(v.idx()).transpose()));
  const Vec3 lone = at[0];
  const Mesh field = buttoned(icosphere(5), 0.35, 0.08, at);
  const Mesh one = buttoned(icosphere(5), 0.35, 0.08, {lone});
  const detail::KeepOut kf = detail::keep_out(field, 0.4, 0, false, 0, 1.0);
  const detail::KeepOut k1 = detail::keep_out(one, 0.4, 0, false, 0, 1.0);
  Eigen::Index top = 0;
  (positions(one) * lone).maxCoeff(&top);
  double kept = 0;
  for (Eigen::Index i = 0; i < kf.domes.size(); ++i) kept += kf.domes[i] < 0.5 ? kf.area[i] : 0.0;
  std::cout << fmt::format("[ 12 buttons on icosphere(5) ] domes keep out {:.1f} %; the lone button: weight {:.2f}\n",
                           100 * kept / kf.area.sum(), k1.domes[top]);
  EXPECT_DOUBLE_EQ(kf.domes.minCoeff(), 1.0);
  EXPECT_LT(k1.domes[top], 1e-9);
}

TEST(Synthesis, AnEyeballWithNoCreaseIsKeptOutByDefault) {
  const Tentacles e;
  const Mesh target = buttoned(icosphere(5), 0.35, 0.08);
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, tentacle_sphere_options());
  Eigen::Index top = 0, bottom = 0;  // the input's vertices come first in the refined target
  const MatrixX3d X = positions(target);
  X.col(2).maxCoeff(&top);
  X.col(2).minCoeff(&bottom);
  std::cout << fmt::format("[ tentacles on a buttoned icosphere(5) ] kept out {:.1f} % (domes {:.1f} %), weight at "
                           "the button {:.2f}, displaced there {:.3g}\n",
                           100 * r.kept_out_share, 100 * r.kept_out_domes, r.weight[top], r.local.row(top).norm());
  expect_kept_out_at(r, top, bottom);
  EXPECT_GT(r.kept_out_domes, 0.0);
  EXPECT_LT(r.kept_out_share, 0.1);
  SynthesisOptions off = tentacle_sphere_options();  // the rules before the dome rule keep nothing out there
  off.keep_out_dome_ridge = 0;
  const SynthesisResult u = synthesize_texture(e.p.base, e.t, target, off);
  EXPECT_DOUBLE_EQ(u.weight[top], 1.0);
  EXPECT_EQ(u.kept_out_domes, 0.0);
}

// Issue 27: a target that crosses itself (two spheres overlapping, one mesh) keeps its own crossings as they are:
// both sides of each are left undisplaced (a displacement however small moves a crossing from face to face and
// the count beyond the base's jitters: the beetle), and the texture crosses nothing beyond them.
TEST(Synthesis, ATargetsOwnCrossingsAreLeftAsTheyAre) {
  const Tentacles e;
  const Mesh a = icosphere(3);
  MatrixX3d Vb = positions(a);
  Vb.col(0).array() += 1.2;
  const MatrixX3d Va = positions(a);
  const MatrixX3i Fa = faces(a);
  MatrixX3d V(2 * Va.rows(), 3);
  V << Va, Vb;
  MatrixX3i F(2 * Fa.rows(), 3);
  F << Fa, Fa.array() + static_cast<int>(Va.rows());
  const Mesh target = make_mesh(V, F);
  const SynthesisResult r = synthesize_texture(e.p.base, e.t, target, tentacle_sphere_options());
  const MatrixX3d X = positions(r.target);
  const MatrixX3i Ft = faces(r.target);
  const std::vector<char> own = self_intersecting_faces(X, Ft);
  ASSERT_GT(std::count(own.begin(), own.end(), 1), 0) << "the spheres cross each other";
  EXPECT_EQ(r.base_self_intersecting, static_cast<size_t>(std::count(own.begin(), own.end(), 1)));
  EXPECT_EQ(r.excess_self_intersecting, 0u);
  double largest = 0, own_largest = 0;
  for (Eigen::Index f = 0; f < Ft.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      largest = std::max(largest, r.local.row(Ft(f, k)).norm());
      if (own[f]) own_largest = std::max(own_largest, r.local.row(Ft(f, k)).norm());
    }
  EXPECT_GT(largest, 0.0) << "the rest is textured";
  EXPECT_EQ(own_largest, 0.0) << "the faces the base crosses itself at keep it as it is";
}
