// The default denoiser (denoise/auto_denoise.h): the noise estimate, noiseless inputs, connectivity and
// orientation, no invented creases, and the shared noisy/clean pairs as a test of the defaults (which
// were chosen on synthetic noise over the clean models only).

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/surfel.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/simplify.h"
#include "geotex/toolkit/smoothing.h"
#include "test_util.h"
#include "../../src/denoise/region_guard.h"
#include "../../src/denoise/region_noise.h"
#include "../../src/denoise/ring_fit.h"


using namespace geotex;

namespace {

Mesh with_noise(const Mesh& clean, double sigma, bool along_normal = false, uint64_t seed = 1) {
  NoiseOptions o;
  o.sigma = sigma;
  o.along_normal = along_normal;
  o.seed = seed;
  Mesh m = clean;
  set_positions(m, add_noise(clean, o));
  return m;
}

// \p clean with the noise \p o (geotex noise's options: a scanner's pattern or direction).
Mesh noisy_copy(const Mesh& clean, const NoiseOptions& o) {
  Mesh m = clean;
  set_positions(m, add_noise(clean, o));
  return m;
}

// Faces whose normal points away from the truth's (turned over), where the truth's face lies flat among its
// neighbours (real models have a few crumpled faces of their own).
int turned_over(const Mesh& result, const Mesh& truth) {
  const MatrixX3d A = face_normals(result), B = face_normals(truth);
  int n = 0;
  for (auto f : truth.faces()) {
    bool flat = true;
    for (auto g : truth.ff_range(f)) flat = flat && B.row(f.idx()).dot(B.row(g.idx())) > 0.5;
    n += flat && A.row(f.idx()).dot(B.row(f.idx())) < 0;
  }
  return n;
}

// Folds: edges whose two faces turn back on each other (normals more than 120° apart) where the
// truth's do not (real models have a few folded faces of their own).
int folds(const Mesh& result, const Mesh& truth) {
  const MatrixX3d A = face_normals(result), B = face_normals(truth);
  int n = 0;
  for (auto e : result.edges()) {
    if (result.is_boundary(e)) continue;
    const int f = result.face_handle(result.halfedge_handle(e, 0)).idx();
    const int g = result.face_handle(result.halfedge_handle(e, 1)).idx();
    n += A.row(f).dot(A.row(g)) < -0.5 && B.row(f).dot(B.row(g)) >= 0;
  }
  return n;
}

// Two meshes in one, apart along x (b's leftmost point one width of a right of a), b scaled to a's mean edge.
Mesh side_by_side(const Mesh& a, const Mesh& b) {
  const MatrixX3d Va = positions(a), Vb = positions(b) * (mean_edge_length(a) / mean_edge_length(b));
  const MatrixX3i Fa = faces(a), Fb = faces(b);
  MatrixX3d V(Va.rows() + Vb.rows(), 3);
  const double gap = Va.col(0).maxCoeff() - Va.col(0).minCoeff();
  V << Va, Vb.rowwise() + Eigen::RowVector3d(Va.col(0).maxCoeff() + gap - Vb.col(0).minCoeff(), 0, 0);
  MatrixX3i F(Fa.rows() + Fb.rows(), 3);
  F << Fa, Fb.array() + static_cast<int>(Va.rows());
  return make_mesh(V, F);
}

// Mean angle (degrees) between the normals of faces [from, to) of \p F placed at \p X and at \p V.
double part_error(const MatrixX3i& F, const MatrixX3d& V, const MatrixX3d& X, Eigen::Index from, Eigen::Index to) {
  double sum = 0;
  for (Eigen::Index f = from; f < to; ++f) {
    const auto n = [&](const MatrixX3d& P) {
      return Vec3((P.row(F(f, 1)) - P.row(F(f, 0))).cross(P.row(F(f, 2)) - P.row(F(f, 0))).normalized());
    };
    sum += std::acos(std::clamp(n(X).dot(n(V)), -1.0, 1.0)) * 180 / M_PI;
  }
  return sum / double(to - from);
}

// Spot (shipped in data/: eyes, nostrils, ears) beside a plain sphere of the same edge length, with noise σ;
// each part's error against the truth (spot's faces come first).
struct SpotBesideSphere {
  Mesh clean, noisy;
  Eigen::Index spot_faces, all_faces;
  SpotBesideSphere(int sphere_subdivisions, double sigma) {
    const Mesh cow = read_mesh(std::filesystem::path(geotex::test::source_dir()) / "data" / "spot.obj");
    clean = side_by_side(cow, icosphere(sphere_subdivisions));
    noisy = with_noise(clean, sigma);
    spot_faces = cow.n_faces();
    all_faces = clean.n_faces();
  }
  double spot_error(const MatrixX3d& X) const { return part_error(faces(clean), positions(clean), X, 0, spot_faces); }
  double sphere_error(const MatrixX3d& X) const {
    return part_error(faces(clean), positions(clean), X, spot_faces, all_faces);
  }
};

int labelled(const Eigen::VectorXd& labels) { return static_cast<int>((labels.array() > 0.5).count()); }

}  // namespace

TEST(NoiseEstimate, RecoversTheSigmaOfGeneratedShapes) {
  for (const auto& [name, clean] : {std::pair{"sphere", icosphere(4)}, std::pair{"cube", subdivided_cube(30)},
                                    std::pair{"torus", torus(1.0, 0.35, 96, 36)}}) {
    EXPECT_LT(estimate_noise(clean).normal_sigma, 0.01) << name;  // noiseless
    for (const double sigma : {0.1, 0.3, 0.7}) {
      const NoiseEstimate e = estimate_noise(with_noise(clean, sigma));
      EXPECT_NEAR(e.sigma / sigma, 1.0, 0.25) << name << " sigma " << sigma;
      const NoiseEstimate n = estimate_noise(with_noise(clean, sigma / 3, true));
      EXPECT_NEAR(n.normal_sigma / (sigma / 3), 1.0, 0.25) << name << " normal noise " << sigma / 3;
    }
  }
}

TEST(NoiseEstimate, RecoversTheSigmaOnTheSharedModels) {
  GEOTEX_REQUIRE_DATA();
  // Isotropic noise (geotex noise's default) from 0.2 to 0.7 mean edge lengths, and noise along the
  // normals at 0.1. (At 0.1 isotropic, the roughness of the coarse cow's own geometry reads as noise:
  // +40 %, see bench/denoise.md.)
  for (const char* name : {"fandisk.obj", "cow.obj", "spot.obj", "woody.obj", "cheburashka.obj", "stanford-bunny.obj",
                           "igea.ply"}) {
    const Mesh clean = read_mesh(test::data_dir() / name);
    for (const double sigma : std::string(name) == "igea.ply" ? std::vector<double>{0.5} : std::vector<double>{0.2, 0.5, 0.7}) {
      const NoiseEstimate e = estimate_noise(with_noise(clean, sigma));
      EXPECT_NEAR(e.sigma / sigma, 1.0, 0.25) << name << " sigma " << sigma;
    }
    const NoiseEstimate n = estimate_noise(with_noise(clean, 0.1, true));
    EXPECT_NEAR(n.normal_sigma / 0.1, 1.0, 0.25) << name << " along the normals, sigma 0.1";
  }
}

TEST(NoiseEstimate, ACoarseModelsFacetsAreNotReadAsNoise) {
  GEOTEX_REQUIRE_DATA();
  // The clean cow's facets grow from the two-ring fit to the three-ring one, noise does not: the clean cow reads
  // less than half of what the two-ring residual alone read (0.09), spot with noise keeps its estimate whole.
  const NoiseEstimate cow = estimate_noise(read_mesh(test::data_dir() / "cow.obj"));
  EXPECT_GT(cow.misfit_growth, 1.2);
  EXPECT_LT(cow.noise_share, 0.5);
  EXPECT_LT(cow.sigma, 0.05);
  const Mesh spot = read_mesh(test::data_dir() / "spot.obj");
  for (const double sigma : {0.02, 0.05}) {
    const NoiseEstimate e = estimate_noise(with_noise(spot, sigma));
    EXPECT_EQ(e.noise_share, 1.0) << "spot, sigma " << sigma;
  }
}

TEST(AutoDenoise, NoiselessMeshesStayWhereTheyAre) {
  std::vector<std::pair<std::string, Mesh>> meshes = {
      {"sphere", icosphere(4)}, {"cube", subdivided_cube(20)}, {"torus", torus(1.0, 0.35, 96, 36)}};
  if (!test::data_dir().empty()) meshes.emplace_back("fandisk", read_mesh(test::data_dir() / "fandisk.obj"));
  for (const auto& [name, m] : meshes) {
    const AutoDenoiseResult r = auto_denoise(m);
    const double moved = (r.positions - positions(m)).rowwise().norm().maxCoeff() / mean_edge_length(m);
    EXPECT_LT(moved, 1e-3) << name << ": a vertex moved by " << moved << " mean edge lengths";
  }
}

TEST(AutoDenoise, NoisySphereSmoothNoInventedCreasesNoFaceTurnedOver) {
  const Mesh clean = icosphere(4);
  const Mesh noisy = with_noise(clean, 0.5);
  const AutoDenoiseResult r = auto_denoise(noisy);
  ASSERT_EQ(r.positions.rows(), static_cast<Eigen::Index>(noisy.n_vertices()));
  EXPECT_EQ(r.edge_labels.size(), static_cast<Eigen::Index>(noisy.n_edges()));
  Mesh out = noisy;  // the input's connectivity and face orientation, the new positions
  set_positions(out, r.positions);
  EXPECT_FALSE(r.resolved.creased.has_value()) << "read per region, not given";
  ASSERT_EQ(r.creased.size(), static_cast<Eigen::Index>(noisy.n_faces()));
  EXPECT_LT(r.creased_share, 0.05) << "a sphere is smooth everywhere";
  EXPECT_EQ(labelled(r.edge_labels), 0) << "no crease on a sphere";
  EXPECT_GT(turned_over(noisy, clean), 0) << "the noise turned faces over";
  EXPECT_EQ(turned_over(out, clean), 0);
  EXPECT_EQ(folds(out, clean), 0);
  EXPECT_EQ(r.turned_over, 0);
  const double before = compare_meshes(noisy, clean).mean_normal_error_deg;
  const double after = compare_meshes(out, clean).mean_normal_error_deg;
  EXPECT_LT(after, 0.25 * before) << before << " -> " << after;
  EXPECT_FALSE(r.choices.empty());
}

TEST(AutoDenoise, NoisyCubeIsCreasedAndItsEdgesAreLabelled) {
  const Mesh clean = subdivided_cube(16);
  const Mesh noisy = with_noise(clean, 0.4);
  const AutoDenoiseResult r = auto_denoise(noisy);
  EXPECT_GT(r.creased_share, 0.95) << "a cube is creased everywhere";
  Mesh out = noisy;
  set_positions(out, r.positions);
  EXPECT_LT(compare_meshes(out, clean).mean_normal_error_deg, 2.5);
  EXPECT_EQ(folds(out, clean), 0);
  // Labels against the cube's edges (dihedral angle 90°).
  const Eigen::VectorXd D = dihedral_angles(clean);
  int hit = 0, sharp = 0, wrong = 0;
  for (Eigen::Index e = 0; e < D.size(); ++e) {
    const bool s = std::abs(D[e]) > 1.0;
    sharp += s;
    hit += s && r.edge_labels[e] > 0.5;
    wrong += !s && r.edge_labels[e] > 0.5;
  }
  EXPECT_GT(hit, 0.9 * sharp);
  EXPECT_LT(wrong, 0.1 * sharp);
}

// A mesh that is CAD and organic at once (issue 24): a cube beside a sphere of the same resolution.
// Read once for the whole mesh, one of the two gets the wrong treatment; read per region, each part gets
// its own: the cube's faces creased, the sphere's smooth, and each part's error no worse than the forced
// reading that is right for it (by more than 5%).
TEST(AutoDenoise, AMixedMeshGetsTheRightReadingOnEachPart) {
  const Mesh cube = subdivided_cube(16), clean = side_by_side(cube, icosphere(4));
  const MatrixX3d V = positions(clean);
  const MatrixX3i F = faces(clean), Fc = faces(cube);
  const Mesh noisy = with_noise(clean, 0.3);
  const auto error_on = [&](const MatrixX3d& X, Eigen::Index from, Eigen::Index to) { return part_error(F, V, X, from, to); };
  const AutoDenoiseResult r = auto_denoise(noisy);
  AutoDenoiseOptions forced;
  forced.creased = true;
  const MatrixX3d Xs = auto_denoise(noisy, forced).positions;
  forced.creased = false;
  const MatrixX3d Xm = auto_denoise(noisy, forced).positions;
  const Eigen::Index nc = Fc.rows(), nf = F.rows();
  EXPECT_GT(r.creased.head(nc).mean(), 0.9) << "the cube reads creased";
  EXPECT_LT(r.creased.tail(nf - nc).mean(), 0.1) << "the sphere reads smooth";
  const Eigen::VectorXd A = face_areas(noisy);
  EXPECT_NEAR(r.creased_share, A.head(nc).sum() / A.sum(), 0.05) << "the share is the cube's share of the area";
  const double cube_err = error_on(r.positions, 0, nc), sphere_err = error_on(r.positions, nc, nf);
  EXPECT_LE(cube_err, 1.05 * error_on(Xs, 0, nc)) << "cube: forced creased " << error_on(Xs, 0, nc);
  EXPECT_LE(sphere_err, 1.05 * error_on(Xm, nc, nf)) << "sphere: forced smooth " << error_on(Xm, nc, nf);
  // And the forced readings are each wrong on the other part (so the test can fail).
  EXPECT_GT(error_on(Xm, 0, nc), 1.5 * error_on(Xs, 0, nc));
  EXPECT_GT(error_on(Xs, nc, nf), 1.2 * error_on(Xm, nc, nf));
}

// Step 5b: relief is kept where it stands above the noise and smoothed away where the surface is plain: spot
// (a cow with eyes, nostrils, ears: relief a few edges across; shipped in data/) beside a plain sphere of the
// same edge length, with noise.
TEST(AutoDenoise, FineReliefIsKeptWherePresentAndAPlainPartIsSmoothed) {
  const SpotBesideSphere m(4, 0.1);
  const Eigen::Index nc = m.spot_faces, nf = m.all_faces;
  AutoDenoiseOptions o;
  o.creased = false;
  const AutoDenoiseResult r = auto_denoise(m.noisy, o);
  o.relief_floor = 0;  // the light fit everywhere
  const MatrixX3d light = auto_denoise(m.noisy, o).positions;
  o.relief_floor = 1e6;  // the mild fit everywhere
  const MatrixX3d mild = auto_denoise(m.noisy, o).positions;
  EXPECT_GT(r.relief.head(nc).mean(), r.relief.tail(nf - nc).mean() + 0.3) << "the relief map follows the relief";
  // The two fits disagree on each part (so the test can fail), and the default takes the better on each.
  EXPECT_LT(m.spot_error(light), 0.8 * m.spot_error(mild)) << "spot: the light fit keeps its relief";
  EXPECT_LT(m.sphere_error(mild), 0.8 * m.sphere_error(light)) << "sphere: the mild fit smooths it";
  EXPECT_LE(m.spot_error(r.positions), 1.1 * m.spot_error(light));
  EXPECT_LE(m.sphere_error(r.positions), 1.1 * m.sphere_error(mild));
  EXPECT_GT(r.relief_share, 0.0);
  EXPECT_LT(r.relief_share, 1.0);
}

TEST(AutoDenoise, NoisyRealModelsNoFaceTurnedOverNoFold) {
  GEOTEX_REQUIRE_DATA();
  // A scan (smooth) and a CAD part (creased). Faces are compared with the truth's where the truth is not
  // folded itself.
  for (const char* name : {"stanford-bunny.obj", "fandisk.obj"}) {
    const Mesh clean = read_mesh(test::data_dir() / name);
    const Mesh noisy = with_noise(clean, 0.3);
    const AutoDenoiseResult r = auto_denoise(noisy);
    Mesh out = noisy;
    set_positions(out, r.positions);
    EXPECT_GT(turned_over(noisy, clean), 0) << name << ": the noise turned faces over";
    EXPECT_GT(folds(noisy, clean), 0) << name << ": the noise folded the surface";
    EXPECT_EQ(turned_over(out, clean), 0) << name;
    EXPECT_EQ(folds(out, clean), 0) << name;
    EXPECT_EQ(r.turned_over, 0) << name;
    EXPECT_LT(compare_meshes(out, clean).mean_normal_error_deg, compare_meshes(noisy, clean).mean_normal_error_deg / 3)
        << name;
  }
}

TEST(AutoDenoise, OptionsAreCheckedByName) {
  const Mesh m = subdivided_cube(4);
  AutoDenoiseOptions o;
  o.keep_below = -1;
  try {
    auto_denoise(m, o);
    FAIL();
  } catch (const InvalidOption& e) {
    EXPECT_NE(std::string(e.what()).find("keep_below"), std::string::npos) << e.what();
  }
  EXPECT_THROW(auto_denoise(Mesh()), InvalidInput);
  // Given values are used as given, and reported back.
  o = {};
  o.creased = true;
  o.sigma = 0.3;
  o.label_angle_deg = 45;
  const AutoDenoiseResult r = auto_denoise(with_noise(m, 0.3), o);
  EXPECT_EQ(*r.resolved.creased, true);
  EXPECT_EQ(*r.resolved.sigma, 0.3);
  EXPECT_EQ(*r.resolved.label_angle_deg, 45.0);
}

// The shared noisy/clean pairs, never used to choose a default: the default must do at least as well as
// the best of six published denoisers run on the same machine (bench/denoise.md: guided mesh normal
// filtering on the three CAD pairs, non-iterative feature-preserving smoothing on the bunny).
TEST(AutoDenoise, SharedPairsAtOrBelowTheBestPeer) {
  GEOTEX_REQUIRE_DATA();
  struct Pair {
    const char* name;
    double best_peer_deg;
    bool creased;
  };
  for (const Pair& p : {Pair{"Fandisk0.3", 2.93, true}, Pair{"Block0.4", 4.09, true},
                        Pair{"Twelve0.5Impulsive", 3.84, true}, Pair{"Bunny0.2", 6.50, false}}) {
    const auto dir = test::data_dir() / "denoise" / p.name;
    const Mesh noisy = read_mesh(dir / "Noisy.obj"), truth = read_mesh(dir / "Original.obj");
    const AutoDenoiseResult r = auto_denoise(noisy);
    Mesh out = noisy;
    set_positions(out, r.positions);
    const double err = compare_meshes(out, truth).mean_normal_error_deg;
    RecordProperty(std::string(p.name) + "_normal_error_deg", fmt::format("{:.3f}", err));
    EXPECT_LE(err, p.best_peer_deg) << p.name;
    // Read per region: the CAD parts nearly all creased, the bunny nearly all smooth.
    if (p.creased) EXPECT_GT(r.creased_share, 0.9) << p.name;
    else EXPECT_LT(r.creased_share, 0.1) << p.name;
    EXPECT_EQ(folds(out, truth), 0) << p.name;
  }
}

// The option tables of the denoisers added here: every default valid and round-tripping through text,
// every preset valid (as options_test does for the others).
template <class O>
void expect_table_is_consistent(const char* what) {
  const auto& t = O::table();
  const O defaults{};
  for (const auto& f : t.fields()) {
    const OptionValue v = f.get(defaults);
    EXPECT_NO_THROW(check_option_value(f.info, v)) << what << ": default of " << f.info.name;
    O o;
    f.set(o, parse_option_value(f.info, format_option_value(v)));
    EXPECT_EQ(format_option_value(f.get(o)), format_option_value(v)) << what << ": " << f.info.name;
    EXPECT_FALSE(f.info.help.empty()) << what << ": " << f.info.name;
  }
  for (const auto& p : t.presets()) {
    O o;
    p.apply(o);
    EXPECT_NO_THROW(t.check(o)) << what << ": preset " << p.name;
  }
}

TEST(AutoDenoise, OptionTablesAreConsistent) {
  expect_table_is_consistent<AutoDenoiseOptions>("AutoDenoiseOptions");
  expect_table_is_consistent<SurfelDenoiseOptions>("SurfelDenoiseOptions");
  // Names usable as CLI flags and Python keywords.
  for (const auto& f : SurfelDenoiseOptions::table().fields())
    EXPECT_EQ(f.info.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_0123456789"), std::string::npos) << f.info.name;
  for (const auto& f : AutoDenoiseOptions::table().fields())
    EXPECT_EQ(f.info.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_0123456789"), std::string::npos) << f.info.name;
}

// Step 5c: where a region read smooth is plain and smoothly curved, it takes the sharp pass's stronger
// smoothing; where it has relief, it does not: spot beside a plain sphere of the same edge length, at a noise
// where the mild pass leaves the sphere rough.
TEST(AutoDenoise, APlainNoisySphereTakesTheStrongerSmoothingAndReliefDoesNot) {
  const SpotBesideSphere m(5, 0.5);
  const Eigen::Index nc = m.spot_faces, nf = m.all_faces;
  const AutoDenoiseResult r = auto_denoise(m.noisy);
  AutoDenoiseOptions o;
  o.strong_floor = 0;  // the previous release: the mild fit wherever the surface is read smooth
  const AutoDenoiseResult before = auto_denoise(m.noisy, o);
  EXPECT_EQ(before.strong.maxCoeff(), 0.0);
  // The sphere is read smooth (so the step applies) and mostly takes the stronger smoothing; spot hardly.
  EXPECT_LT(r.creased.tail(nf - nc).mean(), 0.5);
  EXPECT_GT(r.strong.tail(nf - nc).mean(), 0.3) << "the sphere";
  EXPECT_LT(r.strong.head(nc).mean(), 0.15) << "spot's relief";
  EXPECT_GT(r.strong_share, 0.0);
  EXPECT_LT(r.strong_share, 1.0);
  EXPECT_LT(m.sphere_error(r.positions), 0.9 * m.sphere_error(before.positions)) << "the sphere comes nearer the truth";
  EXPECT_LE(m.spot_error(r.positions), 1.03 * m.spot_error(before.positions)) << "spot is not made worse";
}

// Steps 5b-5c mix two fits by a weight per vertex, averaged over a few rings (kBlendRings): mixed by a weight
// that changes from vertex to vertex, two fits' positions wrinkle the surface between them, and a plain sphere
// kept only half of what the sharp fit gains over the mild one (0.51). The sphere beside spot, at a noise where
// the strong step applies in part: the default keeps more than 0.6 of that gain (0.65), and spot is not made
// worse than with the mild fit alone. The per-vertex share is tested, without the plain-part rule (which takes
// the whole sphere: APlainNoisyPrimitiveIsWithinTwoPercentOfTheCreasedReading).
TEST(AutoDenoise, MixingTwoFitsKeepsMostOfTheBetterOnesGain) {
  const SpotBesideSphere m(5, 0.5);
  AutoDenoiseOptions per_vertex;
  per_vertex.plain_departure = 0;
  const AutoDenoiseResult r = auto_denoise(m.noisy, per_vertex);
  AutoDenoiseOptions o;
  o.strong_floor = 0;  // the mild fit wherever the surface is read smooth
  const AutoDenoiseResult mild = auto_denoise(m.noisy, o);
  o = {};
  o.creased = true;  // the sharp fit everywhere
  const AutoDenoiseResult sharp = auto_denoise(m.noisy, o);
  const Eigen::Index nc = m.spot_faces, nf = m.all_faces;
  const Eigen::VectorXd part = r.strong.tail(nf - nc);
  ASSERT_GT(((part.array() > 0.05) && (part.array() < 0.95)).cast<double>().mean(), 0.1) << "the step applies in part";
  const double e_mild = m.sphere_error(mild.positions), e_sharp = m.sphere_error(sharp.positions);
  ASSERT_LT(e_sharp, 0.8 * e_mild) << "the sharp fit is the better one on the plain sphere";
  EXPECT_LT(m.sphere_error(r.positions), e_mild - 0.6 * (e_mild - e_sharp));
  EXPECT_LE(m.spot_error(r.positions), 1.01 * m.spot_error(mild.positions)) << "spot";
}

// Step 5, the creased reading held to the noise: at low noise the sharp fit flattens the curvature of a coarse
// organic mesh (it moves the input by far more than the noise), and the rule reads part of it creased all the
// same. Spot (coarse, organic) beside a cube (CAD) at σ 0.05: spot's creased reading is refused where it moves
// beyond the noise, and spot comes nearer the truth; the cube, whose look is CAD-like, is left as it was.
TEST(AutoDenoise, ACreasedReadingThatMovesAnOrganicPartBeyondTheNoiseIsRefused) {
  const Mesh cube = subdivided_cube(12), spot = read_mesh(std::filesystem::path(geotex::test::source_dir()) / "data" / "spot.obj");
  const Mesh clean = side_by_side(spot, cube), noisy = with_noise(clean, 0.05);
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const Eigen::Index ns = spot.n_faces(), nf = F.rows();
  const AutoDenoiseResult r = auto_denoise(noisy);
  AutoDenoiseOptions o;
  o.creased_budget = 0;  // the previous release: never refused
  const AutoDenoiseResult before = auto_denoise(noisy, o);
  EXPECT_EQ(before.refused.maxCoeff(), 0.0);
  EXPECT_GT(before.creased.head(ns).mean(), 0.01) << "without the budget part of spot is read creased";
  EXPECT_GT(r.refused.head(ns).mean(), 0.0) << "spot: some of it refused";
  EXPECT_LT(r.creased.head(ns).mean(), before.creased.head(ns).mean());
  EXPECT_LT(part_error(F, V, r.positions, 0, ns), 0.98 * part_error(F, V, before.positions, 0, ns))
      << "spot comes nearer the truth";
  EXPECT_EQ(r.refused.tail(nf - ns).maxCoeff(), 0.0) << "the cube: nothing refused";
  EXPECT_GT(r.creased.tail(nf - ns).mean(), 0.9) << "the cube reads creased";
  EXPECT_NEAR(part_error(F, V, r.positions, ns, nf), part_error(F, V, before.positions, ns, nf), 1e-9);
  EXPECT_GT(r.refused_share, 0.0);
  EXPECT_LT(r.refused_share, 0.5);
}

namespace {
// A generated CAD part, the level-3 cube (40 x 40 quads a side), with a range
// scanner's striped noise (issue 24): bands 8 edges apart across z, 30 % white beside them, σ 0.3.
struct StripedCube {
  Mesh clean = subdivided_cube(40), noisy = clean;
  explicit StripedCube(double wavelength = 8, const Vec3& axis = Vec3::UnitZ()) {
    NoiseOptions o;
    o.sigma = 0.3;
    o.pattern = NoisePattern::Striped;
    o.wavelength = wavelength;
    o.axis = axis;
    o.seed = 7;
    set_positions(noisy, add_noise(clean, o));
  }
  double error(const MatrixX3d& X) const {
    Mesh m = clean;
    set_positions(m, X);
    return compare_meshes(m, clean).mean_normal_error_deg;
  }
  double forced(bool creased) const {
    AutoDenoiseOptions o;
    o.creased = creased;
    return error(auto_denoise(noisy, o).positions);
  }
};
}  // namespace

// Striped scanner noise on a CAD part: the bands raise the sharp fit's residual as relief does, yet the part
// reads creased and the default removes most of the stripes, far nearer the truth than the smooth reading,
// without turning faces over.
TEST(AutoDenoise, StripedScannerNoiseOnACadPartIsReadCreased) {
  const StripedCube c;
  const AutoDenoiseResult r = auto_denoise(c.noisy);
  EXPECT_GT(r.creased_share, 0.9);
  const double e = c.error(r.positions), smooth = c.forced(false);
  EXPECT_LT(e, 0.5 * smooth) << "forced smooth " << smooth;
  EXPECT_LT(e, 0.5 * compare_meshes(c.noisy, c.clean).mean_normal_error_deg) << "the stripes are mostly removed";
  Mesh out = c.clean;
  set_positions(out, r.positions);
  EXPECT_EQ(turned_over(out, c.clean), 0);
}

// The goal on striped noise (issue 24): the default within 2 % of the better forced reading. The bands
// bend the creases and the rule read their neighbourhoods and scattered vertices smooth (the previous release,
// stripe_coherence 1, is more than 10 % above it here); the part's residual runs one way across it and it is read
// creased throughout (read_striped_parts_creased()).
TEST(AutoDenoise, StripedScannerNoiseOnACadPartWithinTwoPercentOfTheBetterForcedReading) {
  const StripedCube c;
  const AutoDenoiseResult r = auto_denoise(c.noisy);
  const double e = c.error(r.positions), best = std::min(c.forced(true), c.forced(false));
  EXPECT_LE(e, 1.02 * best);
  AutoDenoiseOptions previous;
  previous.stripe_coherence = 1;
  previous.stripe_share = 1;  // the sinusoid along a fitted axis (fifteenth session) reads these bands too
  EXPECT_GT(c.error(auto_denoise(c.noisy, previous).positions), 1.1 * best) << "so the test can fail";
  // White noise of the same level on the same part is not read as bands.
  const Mesh white = with_noise(c.clean, 0.3, true, 7);
  const AutoDenoiseResult w = auto_denoise(white), w_previous = auto_denoise(white, previous);
  EXPECT_NEAR(c.error(w.positions), c.error(w_previous.positions), 1e-12);
}

// Stripes 4 edges apart make the cube look organic to the look (its sharp fit keeps the short bands' angles), so no
// CAD rule applies and the previous release (stripe_coherence_organic 1) read it mostly smooth, more than 10 % above
// the better forced reading; its residual still runs one way across it, and it is read creased throughout. An
// organic model under white noise is not read as bands: its result is that of the previous release.
TEST(AutoDenoise, ShortStripesOnACadPartThatLooksOrganicAreReadCreased) {
  const StripedCube c(4);
  const AutoDenoiseResult r = auto_denoise(c.noisy);
  EXPECT_GT(r.creased_share, 0.9);
  const double e = c.error(r.positions), best = std::min(c.forced(true), c.forced(false));
  EXPECT_LE(e, 1.02 * best);
  AutoDenoiseOptions previous;
  previous.stripe_coherence_organic = 1;
  previous.stripe_share = 1;  // the sinusoid along a fitted axis (fifteenth session) reads these bands too
  EXPECT_GT(c.error(auto_denoise(c.noisy, previous).positions), 1.1 * best) << "so the test can fail";
  GEOTEX_REQUIRE_DATA();
  const Mesh spot = with_noise(read_mesh(test::data_dir() / "spot.obj"), 0.3, false, 7);
  EXPECT_EQ(auto_denoise(spot).positions, auto_denoise(spot, previous).positions);
}

// The number after \p key in the choices line that starts with \p line (-1: none).
double choice_number(const AutoDenoiseResult& r, const std::string& line, const std::string& key) {
  for (const auto& c : r.choices)
    if (c.rfind(line, 0) == 0 && c.find(key) != std::string::npos) return std::stod(c.substr(c.find(key) + key.size()));
  return -1;
}

// Stripes across an oblique axis are seen by the cube's faces running different ways, so the part-wide tensor's
// coherence stays below stripe_coherence and the previous release (stripe_share 1) read the cube partly smooth;
// the axis fitted in 3D sees one sinusoid explain most of the residual, and the cube is read creased throughout,
// within 2 % of the better forced reading. The same cube under white noise of the same level along the normals is
// not read as bands: its result is that of the previous release.
TEST(AutoDenoise, ObliqueStripesOnACubeAreReadCreasedAndWhiteNoiseIsNot) {
  const StripedCube c(6, Vec3(0.7, 0.1, 0.7));
  const AutoDenoiseResult r = auto_denoise(c.noisy);
  EXPECT_LT(choice_number(r, "stripes:", "coherence "), AutoDenoiseOptions{}.stripe_coherence) << "so the test can fail";
  EXPECT_GT(choice_number(r, "stripes:", "explains "), AutoDenoiseOptions{}.stripe_share);
  EXPECT_GT(r.creased_share, 0.9);
  const double e = c.error(r.positions), best = std::min(c.forced(true), c.forced(false));
  EXPECT_LE(e, 1.02 * best);
  AutoDenoiseOptions previous;
  previous.stripe_share = 1;
  EXPECT_GT(c.error(auto_denoise(c.noisy, previous).positions), 1.05 * best) << "so the test can fail";
  const Mesh white = with_noise(c.clean, 0.3, true, 7);
  const AutoDenoiseResult w = auto_denoise(white);
  EXPECT_LT(choice_number(w, "stripes:", "explains "), AutoDenoiseOptions{}.stripe_share);
  EXPECT_EQ(w.positions, auto_denoise(white, previous).positions);
}

// A smooth part's own shape can make the sharp fit's residual run one way under white noise (a cylinder: the fit's
// facets along its axis, coherence above stripe_coherence_organic here), but a white residual stays at the noise
// level and the part is not read as bands: the result is that of the previous release.
TEST(AutoDenoise, AWhiteNoisyCylinderIsNotReadAsStripes) {
  const Mesh noisy = with_noise(cylinder(0.5, 1.0, 96, 48), 0.1, false, 11);
  const AutoDenoiseResult r = auto_denoise(noisy);
  double coherence = -1;
  for (const auto& c : r.choices)
    if (c.rfind("stripes:", 0) == 0) coherence = std::stod(c.substr(c.find("coherence ") + 10));
  EXPECT_GT(coherence, AutoDenoiseOptions{}.stripe_coherence_organic) << "so the test can fail";
  AutoDenoiseOptions previous;
  previous.stripe_coherence_organic = 1;
  EXPECT_EQ(r.positions, auto_denoise(noisy, previous).positions);
}

// Step 5d: on a CAD-looking part read partly smooth, the mild fit can fold at high noise beside a flat panel
// (woody at σ 0.7: three faces 35-76° from the truth where the sharp fit has 4-6°); the reading's transitions
// take the sharp fit there. The default stays within 2 % of the better forced reading, and no face of a
// transition turns more than 60° from the sharp fit's.
TEST(AutoDenoise, ACadPartsTransitionsTakeTheSharpFitWhereTheMildOneFolds) {
  GEOTEX_REQUIRE_DATA();
  const Mesh clean = read_mesh(test::data_dir() / "woody.obj"), noisy = with_noise(clean, 0.7, false, 7);
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const AutoDenoiseResult r = auto_denoise(noisy);
  AutoDenoiseOptions o;
  o.creased = true;
  const AutoDenoiseResult sharp = auto_denoise(noisy, o);
  o.creased = false;
  const AutoDenoiseResult mild = auto_denoise(noisy, o);
  const auto error = [&](const MatrixX3d& X) { return part_error(F, V, X, 0, F.rows()); };
  EXPECT_LE(error(r.positions), 1.02 * std::min(error(sharp.positions), error(mild.positions)));
  int turned = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (!(r.creased[f] > 0 && r.creased[f] < 1)) continue;
    const auto n = [&](const MatrixX3d& P) {
      return Vec3((P.row(F(f, 1)) - P.row(F(f, 0))).cross(P.row(F(f, 2)) - P.row(F(f, 0))).normalized());
    };
    turned += n(r.positions).dot(n(sharp.positions)) < 0.5;
  }
  EXPECT_EQ(turned, 0) << "faces of the transitions more than 60 degrees from the sharp fit's";
}

// Step 5c on a plain, dense surface at high noise: the roughness gate fails at scattered vertices (the sharp
// fit's few facets), and a plain region is taken whole all the same once most of it passes. On the level-3 torus
// at σ 0.5 the default keeps more than 3/4 of what the sharp fit (the forced creased reading) gains over the
// smooth reading without the step (2/3 when the gate's share was used as it came).
TEST(AutoDenoise, APlainNoisyTorusTakesMostOfTheSharpFitsGain) {
  const Mesh clean = make_shape("torus", 3).base, noisy = with_noise(clean, 0.5);
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const auto error = [&](const AutoDenoiseResult& r) { return part_error(F, V, r.positions, 0, F.rows()); };
  AutoDenoiseOptions o;
  o.strong_floor = 0;  // the mild fit wherever the surface is read smooth
  const double e_mild = error(auto_denoise(noisy, o));
  o = {};
  o.creased = true;
  const double e_sharp = error(auto_denoise(noisy, o));
  ASSERT_LT(e_sharp, 0.8 * e_mild) << "the sharp fit is the better one on the plain torus";
  const AutoDenoiseResult r = auto_denoise(noisy);
  EXPECT_LT(r.creased_share, 0.1) << "read smooth";
  EXPECT_LT(error(r), e_mild - 0.75 * (e_mild - e_sharp));
}

// Step 5c on a plain part (plain_departure): a dense primitive at high noise, read smooth, is taken whole by the
// sharp fit once its typical departure from the mild fit is no more than the mild fit's own wobble, where the
// per-vertex share stopped at 0.7-0.9 of it (1.12-1.15× the forced creased reading). Spot beside a sphere at σ 0.5:
// the sphere within 2 % of the forced creased reading and nearer it than without the rule; spot, whose relief
// stands far above the wobble, exactly as without it (its part is not plain), and nearer the truth than the
// sharp fit. A level-3 torus at σ 0.5 alone: within 2 % of the forced creased reading.
TEST(AutoDenoise, APlainNoisyPrimitiveIsWithinTwoPercentOfTheCreasedReading) {
  const SpotBesideSphere m(5, 0.5);
  const AutoDenoiseResult r = auto_denoise(m.noisy);
  AutoDenoiseOptions o;
  o.plain_departure = 0;  // the per-vertex share only
  const AutoDenoiseResult before = auto_denoise(m.noisy, o);
  o = {};
  o.creased = true;
  const AutoDenoiseResult sharp = auto_denoise(m.noisy, o);
  const double e_sharp = m.sphere_error(sharp.positions), e_before = m.sphere_error(before.positions);
  ASSERT_GT(e_before, 1.02 * e_sharp) << "the per-vertex share alone falls short on the sphere";
  EXPECT_LT(m.sphere_error(r.positions), 1.02 * e_sharp) << "the sphere";
  EXPECT_LE(m.spot_error(r.positions), m.spot_error(before.positions)) << "spot as without the rule";
  EXPECT_LT(m.spot_error(r.positions), m.spot_error(sharp.positions)) << "spot's relief is kept";

  const Mesh clean = make_shape("torus", 3).base, noisy = with_noise(clean, 0.5);
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const double e_torus = part_error(F, V, auto_denoise(noisy).positions, 0, F.rows());
  EXPECT_LT(e_torus, 1.02 * part_error(F, V, auto_denoise(noisy, o).positions, 0, F.rows())) << "the torus";
}

TEST(AutoDenoise, ALowNoiseCoarseModelIsLeftAlmostAsItIs) {
  GEOTEX_REQUIRE_DATA();
  // At a noise too low to turn its faces over, the faces of a coarse model (the cow, 5.8k faces) that face away
  // from the smooth reading's targets are the targets' error, not folds: the default (given the noise level)
  // must not untangle them (which moved whole regions: 3.0° against the input's 1.9°). A fine model (spot)
  // at the same noise still gains.
  AutoDenoiseOptions o;
  o.sigma = 0.02;
  for (const char* name : {"cow.obj", "spot.obj"}) {
    const Mesh clean = read_mesh(test::data_dir() / name), noisy = with_noise(clean, *o.sigma);
    const AutoDenoiseResult r = auto_denoise(noisy, o);
    Mesh out = noisy;
    set_positions(out, r.positions);
    const double e_in = compare_meshes(noisy, clean).mean_normal_error_deg;
    const double e_out = compare_meshes(out, clean).mean_normal_error_deg;
    if (std::string(name) == "cow.obj")
      EXPECT_LT(e_out, 1.1 * e_in) << name << ": almost as the input";
    else
      EXPECT_LT(e_out, e_in) << name << ": nearer the truth than the input";
  }
}

// A scanner's depth noise runs along its viewing axis: on a cylinder seen obliquely the caps, facing the scanner,
// carry about three times the normal noise the mesh's estimate reads (its best-fitting rings, on the side). The
// creased budget measured against that estimate refused the caps the creased reading (the previous release: a
// fifth of the surface refused, 1.7x the forced creased reading); against the noise along each normal
// (depth_anisotropy) it refuses almost none and comes nearer the truth. The white-noise twin is the previous
// release's result.
TEST(AutoDenoise, DepthNoiseOnACurvedCadPartIsNotRefusedTheCreasedReading) {
  const Mesh clean = make_shape("cylinder", 2).base;
  const Mesh noisy = noisy_copy(
      clean, {.sigma = 0.2, .direction = NoiseDirection::Depth, .axis = Vec3(0.3, 0.4, 0.866), .seed = 7});
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const auto error = [&](const MatrixX3d& X) { return part_error(F, V, X, 0, F.rows()); };
  AutoDenoiseOptions previous;
  previous.depth_anisotropy = 0;
  const AutoDenoiseResult r = auto_denoise(noisy), before = auto_denoise(noisy, previous);
  EXPECT_GT(before.refused_share, 0.1) << "so the test can fail";
  EXPECT_LT(r.refused_share, 0.02);
  EXPECT_LT(error(r.positions), 0.85 * error(before.positions));
  AutoDenoiseOptions creased;
  creased.creased = true;
  EXPECT_LT(error(r.positions), 1.3 * error(auto_denoise(noisy, creased).positions));
  const Mesh white = with_noise(clean, 0.2, false, 7);
  EXPECT_EQ(auto_denoise(white).positions, auto_denoise(white, previous).positions);
}

// Woody (694 vertices) was below the striped parts' minimum size: stripes 4 edges apart along y (seed 11) were read
// mostly smooth, 1.7x the better forced reading. Read as bands now, within 2 % of it; under white noise woody's
// residual runs no one way and its result is that of the code without the stripe rules.
TEST(AutoDenoise, StripesOnASmallCadPartAreReadCreased) {
  GEOTEX_REQUIRE_DATA();
  const Mesh clean = read_mesh(test::data_dir() / "woody.obj");
  NoiseOptions n;
  n.sigma = 0.3;
  n.pattern = NoisePattern::Striped;
  n.wavelength = 4;
  n.axis = Vec3(0, 1, 0);
  n.seed = 11;
  Mesh noisy = clean;
  set_positions(noisy, add_noise(clean, n));
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const auto error = [&](const MatrixX3d& X) { return part_error(F, V, X, 0, F.rows()); };
  AutoDenoiseOptions o, off;
  o.creased = true;
  const double creased = error(auto_denoise(noisy, o).positions);
  o.creased = false;
  const double best = std::min(creased, error(auto_denoise(noisy, o).positions));
  off.stripe_coherence = off.stripe_coherence_organic = off.stripe_share = 1;
  EXPECT_LE(error(auto_denoise(noisy).positions), 1.02 * best);
  EXPECT_GT(error(auto_denoise(noisy, off).positions), 1.1 * best) << "so the test can fail";
  const Mesh white = with_noise(clean, 0.3, false, 7);
  EXPECT_EQ(auto_denoise(white).positions, auto_denoise(white, off).positions);
}

TEST(AutoDenoise, ALowNoiseCoarseModelIsLeftNearerItselfWithTheNoiseEstimated) {
  GEOTEX_REQUIRE_DATA();
  // The same with the noise level estimated (the default). The coarse cow's facets are no longer all read as
  // noise (misfit_growth.h), no vertex moves beyond the noise's reach there, and a change that turns the faces
  // beyond what the noise explains is given back (region_guard.h): at σ 0.02 the estimate was 4.6 σ and the
  // result 4.4 times the noisy input's error; now the estimate stays below 2.5 σ and the result below 2 times
  // (geotex.add_noise's seeds 1 / 3 / 7 / 11: 1.8 / 1.24 / 1.04 / 1.0, 2.5 / 1.7 / 1.05 / 1.0 without the
  // guard; the growth varies with the noise on a mesh of 2.9k vertices, bench/denoise.md). Spot, a fine model,
  // keeps its estimate whole and still gains.
  for (const char* name : {"cow.obj", "spot.obj"}) {
    const Mesh clean = read_mesh(test::data_dir() / name), noisy = with_noise(clean, 0.02);
    const AutoDenoiseResult r = auto_denoise(noisy, {});
    Mesh out = noisy;
    set_positions(out, r.positions);
    const double e_in = compare_meshes(noisy, clean).mean_normal_error_deg;
    const double e_out = compare_meshes(out, clean).mean_normal_error_deg;
    if (std::string(name) == "cow.obj") {
      EXPECT_LT(r.noise.sigma, 2.5 * 0.02) << name;
      EXPECT_LT(e_out, 2 * e_in) << name << ": nearer its input";
      // At σ 0.05 the change beyond what the noise explains is given back (region_guard.h): 1.59 times the
      // input's error before, 1.24 times with it.
      const Mesh noisier = with_noise(clean, 0.05);
      Mesh out5 = noisier;
      set_positions(out5, auto_denoise(noisier, {}).positions);
      EXPECT_LT(compare_meshes(out5, clean).mean_normal_error_deg, 1.4 * compare_meshes(noisier, clean).mean_normal_error_deg)
          << name << " at sigma 0.05: nearer its input";
    } else {
      EXPECT_EQ(r.noise.noise_share, 1.0) << name;
      EXPECT_LT(e_out, e_in) << name << ": nearer the truth than the input";
    }
  }
}

// A coarse organic model nearly clean: cheburashka decimated to 1500 vertices (geotex::simplify, QEM, the vertices
// kept where they are) at σ 0.02. The estimate reads the whole residual as the model's facets (noise share 0), but
// the noise map read its coarsest regions' misfit as noise, and the mesh ran at their level: 1.75-1.86 times the
// noisy input's error (seeds 3 / 7 / 11). Each region's excess is read with the mesh's noise share now
// (region_levels()): the model is left as it is.
TEST(AutoDenoise, ACoarseOrganicModelNearlyCleanIsNotMadeWorse) {
  GEOTEX_REQUIRE_DATA();
  const Mesh clean = simplify(read_mesh(test::data_dir() / "cheburashka.obj"), 1500).mesh;
  for (uint64_t seed : {3, 7, 11}) {
    const Mesh noisy = with_noise(clean, 0.02, false, seed);
    Mesh out = noisy;
    set_positions(out, auto_denoise(noisy, {}).positions);
    EXPECT_LE(compare_meshes(out, clean).mean_normal_error_deg, 1.01 * compare_meshes(noisy, clean).mean_normal_error_deg)
        << "seed " << seed;
  }
}

// The regions' levels where the mesh's residual was read as facets: a region read above twice the whole keeps its
// excess in proportion to the estimate's noise share (none of it at share 0; half of it at 1/2).
TEST(RegionNoise, ARegionsExcessIsReadWithTheMeshsNoiseShare) {
  detail::RegionNoise map;
  map.whole = 0.1;
  map.level = (Eigen::VectorXd(3) << 0.1, 0.3, 0.5).finished();
  NoiseEstimate noise;
  noise.normal_sigma = noise.rms_normal_sigma = 0.1;
  for (double share : {1.0, 0.5, 0.0}) {
    noise.noise_share = share;
    const Eigen::VectorXd level = detail::region_levels(map, noise, 0.0);
    EXPECT_EQ(level[0], 0.0) << share;
    EXPECT_NEAR(level[1], share * (0.3 - 0.1), 1e-12) << share;
    EXPECT_NEAR(level[2], share * (0.5 - 0.1), 1e-12) << share;
  }
}

// Low-frequency scanner noise (a smooth field over 4 edges along the normals) on a CAD part and on an organic model:
// the noise estimate follows most of it and the mild fit keeps the rest as relief, so the rule read both smooth (the
// previous release, low_frequency_residual 0, more than 5 % above the better forced reading). Both fits move the
// part far beyond the noise estimated, and it is read creased throughout (read_low_frequency_parts_creased()). White
// noise at a low level on the same models (where the sharp fit flattens spot's shape far beyond the noise) is not
// read so: the results are the previous release's.
TEST(AutoDenoise, LowFrequencyNoiseIsWithinTwoPercentOfTheBetterForcedReading) {
  GEOTEX_REQUIRE_DATA();
  AutoDenoiseOptions previous, sharp, mild;
  previous.low_frequency_residual = 0;
  sharp.creased = true;
  mild.creased = false;
  for (const char* name : {"fandisk.obj", "spot.obj"}) {
    const Mesh clean = read_mesh(test::data_dir() / name);
    const Mesh noisy = noisy_copy(
        clean, {.sigma = 0.5, .pattern = NoisePattern::LowFrequency, .wavelength = 4, .seed = 7});
    const auto error = [&](const AutoDenoiseResult& r) {
      Mesh m = clean;
      set_positions(m, r.positions);
      return compare_meshes(m, clean).mean_normal_error_deg;
    };
    const double best = std::min(error(auto_denoise(noisy, sharp)), error(auto_denoise(noisy, mild)));
    EXPECT_LE(error(auto_denoise(noisy)), 1.02 * best) << name;
    EXPECT_GT(error(auto_denoise(noisy, previous)), 1.05 * best) << name << ": so the test can fail";
    const Mesh white = with_noise(clean, 0.05, false, 7);
    EXPECT_EQ(auto_denoise(white).positions, auto_denoise(white, previous).positions) << name;
  }
}

// Per part: fandisk under the low-frequency field beside spot under white noise, one mesh. The noise estimate of the
// whole mesh is raised by spot's white noise, against which fandisk's field does not stand out; fandisk's own
// estimate does, so fandisk is read creased throughout and lands within 2 % of the forced creased reading there (the
// previous release more than 10 % above it), while spot keeps its smooth reading (no worse than the previous release).
TEST(AutoDenoise, LowFrequencyNoiseOnOnePartOfAMixedMeshIsReadOnThatPart) {
  GEOTEX_REQUIRE_DATA();
  const Mesh fandisk = read_mesh(test::data_dir() / "fandisk.obj");
  const Mesh clean = side_by_side(fandisk, read_mesh(test::data_dir() / "spot.obj"));
  NoiseOptions n;
  n.sigma = 0.5;
  n.pattern = NoisePattern::LowFrequency;
  n.wavelength = 4;
  n.seed = 7;
  MatrixX3d X = add_noise(clean, n);
  const Eigen::Index nv = fandisk.n_vertices(), nf = fandisk.n_faces(), all = clean.n_faces();
  X.bottomRows(X.rows() - nv) = positions(with_noise(clean, 0.2, false, 7)).bottomRows(X.rows() - nv);
  Mesh noisy = clean;
  set_positions(noisy, X);
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  AutoDenoiseOptions previous, sharp;
  previous.low_frequency_residual = 0;
  sharp.creased = true;
  const MatrixX3d R = auto_denoise(noisy).positions, P = auto_denoise(noisy, previous).positions;
  const double creased = part_error(F, V, auto_denoise(noisy, sharp).positions, 0, nf);
  EXPECT_LE(part_error(F, V, R, 0, nf), 1.02 * creased);
  EXPECT_GT(part_error(F, V, P, 0, nf), 1.1 * creased) << "so the test can fail";
  EXPECT_LE(part_error(F, V, R, nf, all), 1.005 * part_error(F, V, P, nf, all));
}

// Step 6c's share (region_guard.h) on the coarse cow at σ 0.05: a result that removes exactly the noise (the truth
// itself) is kept nearly whole, a result that moves a patch far beyond what the noise explains is held there, and
// a vertex whose region the result leaves as it is keeps the (empty) change whole.
TEST(RegionGuard, KeepsTheNoiseRemovedAndHoldsAChangeBeyondIt) {
  GEOTEX_REQUIRE_DATA();
  const Mesh clean = read_mesh(test::data_dir() / "cow.obj"), noisy = with_noise(clean, 0.05);
  const Neighborhoods N = one_ring_neighborhoods(noisy);
  const MatrixX3i F = faces(noisy);
  const MatrixX3d X = positions(noisy), truth = positions(clean), Nv = vertex_normals(noisy);
  const double h = mean_edge_length(noisy), s = 0.05 / std::sqrt(3.0) * h;
  const Eigen::VectorXd kept = detail::region_guard_share(N, F, X, truth, s);
  EXPECT_GT(kept.mean(), 0.8) << "the noise removed is what the noise explains";
  // Every tenth vertex moved along its normal by 10 noise deviations: shape, not noise.
  MatrixX3d bent = X;
  for (Eigen::Index v = 0; v < X.rows(); v += 10) bent.row(v) += 10 * s * Nv.row(v);
  const Eigen::VectorXd held = detail::region_guard_share(N, F, X, bent, s);
  double moved = 0;
  int n_moved = 0;
  for (Eigen::Index v = 0; v < X.rows(); v += 10) moved += held[v], ++n_moved;
  EXPECT_LT(moved / n_moved, 0.5 * kept.mean()) << "a change far beyond the noise is held";
  EXPECT_EQ(detail::region_guard_share(N, F, X, X, s).minCoeff(), 1.0) << "no change, nothing held";
}

// A sliver's noise does not excuse a turn of its well-shaped neighbours. On a flat 12 × 12 plate, a column of
// vertices moved next to its left neighbour makes a column of slivers (width 0.03 edges: their normals' noise
// ν² ~ 0.2 against 4 s² on a right triangle); a vertex beside them lifted by 20 noise deviations turns its faces by
// ~0.2 rad. On the regular plate the guard holds that lift; before the faces were weighted by 1 / ν_f, the slivers'
// noise in the same region sums excused it entirely (t = 1), though the error read is each face's own angle.
TEST(RegionGuard, ASliversNoiseDoesNotExcuseItsNeighboursTurn) {
  constexpr int n = 12;
  const double h = 1.0 / n, s = 0.01 * h;
  for (bool slivers : {false, true}) {
    const Mesh m = plane(n, 1.0);
    MatrixX3d X = positions(m);
    Eigen::Index lifted = -1;
    for (Eigen::Index v = 0; v < X.rows(); ++v) {
      if (slivers && std::abs(X(v, 0)) < 1e-9) X(v, 0) = -h + 0.03 * h;
      if (std::abs(X(v, 0) - h) < 1e-9 && std::abs(X(v, 1)) < 1e-9) lifted = v;
    }
    ASSERT_GE(lifted, 0);
    MatrixX3d P = X;
    P(lifted, 2) += 20 * s;
    const Eigen::VectorXd t = detail::region_guard_share(one_ring_neighborhoods(m), faces(m), X, P, s);
    EXPECT_LT(t[lifted], 0.5) << (slivers ? "beside the slivers" : "on the regular plate");
  }
}

// The guard's shrinkage gives a change beyond what the noise explains back towards the input: the coarse cow at
// σ 0.02 / 0.05, smoothed (an implicit cotangent step of λ 0.1, which rounds its facets as the smooth reading's
// targets do: 2.9 / 1.3 times the input's error), guarded with the true σ, ends nearer the truth than the
// smoothing, with most of the gap to the input closed. (Not all: a Laplacian step keeps part of the noise, and the
// shrinkage assumes a result independent of it; bench/denoise.md, fifteenth session.)
TEST(RegionGuard, AChangeBeyondTheNoiseIsGivenBackTowardsTheInput) {
  GEOTEX_REQUIRE_DATA();
  const Mesh clean = read_mesh(test::data_dir() / "cow.obj");
  for (double sigma : {0.02, 0.05}) {
    const Mesh noisy = with_noise(clean, sigma);
    SmoothingOptions o;
    o.lambda = 0.1;
    const MatrixX3d X = positions(noisy), P = smooth(noisy, o);
    const double s = sigma / std::sqrt(3.0) * mean_edge_length(noisy);
    const Eigen::VectorXd t = detail::region_guard_share(one_ring_neighborhoods(noisy), faces(noisy), X, P, s);
    const auto error = [&](const MatrixX3d& Y) {
      Mesh m = noisy;
      set_positions(m, Y);
      return compare_meshes(m, clean).mean_normal_error_deg;
    };
    const double e_in = error(X), e_smooth = error(P), e_guard = error(X + t.asDiagonal() * (P - X));
    ASSERT_GT(e_smooth, 1.2 * e_in) << sigma << ": the smoothing rounds the facets";
    EXPECT_LT(e_guard - e_in, 0.5 * (e_smooth - e_in)) << sigma;
  }
}

// Low-frequency scanner noise on a CAD-looking part: on the flat faces the sharp fit restores, its residual stands
// above the mild fit's (the hand-made rule reads such a part creased up to z5 0.3, an organic one up to -0.5), so the
// field leaves z5 higher than on an organic part (the level-3 cube under the field over 4 edges: 0.57). Measured
// against the rule's threshold for the part's look, the part is read creased throughout and lands within 2 % of the
// forced creased reading (z5 against one bound for every look, 0.5, left it half smooth: 1.5x); nearer the truth than
// it, since the noise estimate missed the field and step 6 keeps all of the change there, not the share the estimate
// gives (89 %). Without the rule (low_frequency_residual 0) the default is more than 10 % above the forced creased
// reading, so the test can fail. White noise on the cube is not read so: the result is the one without the rule.
TEST(AutoDenoise, LowFrequencyNoiseOnACadPartIsReadCreasedThroughout) {
  const Mesh clean = subdivided_cube(40);
  const Mesh noisy = noisy_copy(
      clean, {.sigma = 0.5, .pattern = NoisePattern::LowFrequency, .wavelength = 4, .seed = 7});
  const auto error = [&](const MatrixX3d& X) {
    Mesh m = clean;
    set_positions(m, X);
    return compare_meshes(m, clean).mean_normal_error_deg;
  };
  AutoDenoiseOptions previous, sharp;
  previous.low_frequency_residual = 0;
  sharp.creased = true;
  const AutoDenoiseResult r = auto_denoise(noisy);
  const double creased = error(auto_denoise(noisy, sharp).positions);
  EXPECT_GT(r.creased_share, 0.99);
  EXPECT_LT(error(r.positions), creased);
  EXPECT_GT(error(auto_denoise(noisy, previous).positions), 1.1 * creased) << "so the test can fail";
  const Mesh white = with_noise(clean, 0.05, false, 7);
  EXPECT_EQ(auto_denoise(white).positions, auto_denoise(white, previous).positions);
}

// One noise level per mesh reads a mesh half noisy and half clean at the clean half's level (the better-fitting half
// of the rings): fandisk under white σ 0.3 beside spot untouched. The noise per region reads two levels: fandisk's
// near its σ / √3 along the normals, spot's below a quarter of it.
TEST(RegionNoise, AMeshHalfNoisyHalfCleanReadsTwoLevels) {
  GEOTEX_REQUIRE_DATA();
  const Mesh fandisk = read_mesh(test::data_dir() / "fandisk.obj");
  const Mesh clean = side_by_side(fandisk, read_mesh(test::data_dir() / "spot.obj"));
  const Eigen::Index nv = fandisk.n_vertices(), nf = fandisk.n_faces();
  MatrixX3d X = positions(clean);
  X.topRows(nv) = positions(with_noise(clean, 0.3, false, 11)).topRows(nv);
  Mesh noisy = clean;
  set_positions(noisy, X);
  const AutoDenoiseResult r = auto_denoise(noisy);
  ASSERT_EQ(r.noise_map.size(), X.rows());
  const auto median = [](Eigen::VectorXd x) {
    std::nth_element(x.data(), x.data() + x.size() / 2, x.data() + x.size());
    return x[x.size() / 2];
  };
  const double noisy_level = median(r.noise_map.head(nv)), clean_level = median(r.noise_map.tail(X.rows() - nv));
  EXPECT_NEAR(noisy_level, 0.3 / std::sqrt(3.0), 0.35 * 0.3 / std::sqrt(3.0));  // isotropic σ: σ / √3 along n
  EXPECT_LT(clean_level, noisy_level / 4);
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  EXPECT_LT(part_error(F, V, r.positions, 0, nf), 0.5 * part_error(F, V, X, 0, nf));  // fandisk denoised
}

// Depth noise along the cylinder's own axis moves the side's vertices along the side: its rings carry no normal
// noise, fit best, and one level per mesh read the whole cylinder noise-free (the input returned, 14.6°). The caps,
// facing the scanner, are noisy; their regions read so, and are denoised at their level.
TEST(RegionNoise, DepthNoiseAlongACylindersAxisIsNotReadNoiseFree) {
  const Mesh clean = make_shape("cylinder", 2).base;
  const Mesh noisy = noisy_copy(
      clean, {.sigma = 0.3, .direction = NoiseDirection::Depth, .axis = Vec3(0, 0, 1), .seed = 11});
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean), X = positions(noisy);
  const AutoDenoiseResult r = auto_denoise(noisy);
  EXPECT_LT(part_error(F, V, r.positions, 0, F.rows()), 0.5 * part_error(F, V, X, 0, F.rows()));
  double cap = 0, side = 0;
  int caps = 0, sides = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (std::abs(std::abs(V(v, 2)) - 0.5) < 1e-9) cap += r.noise_map[v], ++caps;
    else side += r.noise_map[v], ++sides;
  EXPECT_GT(cap / caps, 4 * side / sides) << "the caps read noisier than the side";
}

// The noise per region reads the estimate's own samples and fits (one sampling, one reduction per denoise call): the
// estimate is estimate_noise()'s, each sample's fit is its two-ring cubic's, and the map's whole is the estimate's
// normal_sigma before the noise_share, on white noise and on depth noise whose regions read apart.
TEST(RegionNoise, ReadsTheEstimatesOwnSamplesAndFits) {
  const Mesh cube = with_noise(subdivided_cube(30), 0.3);
  const Mesh cylinder = noisy_copy(make_shape("cylinder", 2).base,
                                   {.sigma = 0.3, .direction = NoiseDirection::Depth, .axis = Vec3(0, 0, 1), .seed = 11});
  for (const auto& [name, mesh] : {std::pair{"cube", &cube}, std::pair{"cylinder", &cylinder}}) {
    const detail::NoiseReading reading = detail::read_noise(*mesh, 2000);
    const NoiseEstimate e = estimate_noise(*mesh, 2000);
    EXPECT_EQ(reading.estimate.normal_sigma, e.normal_sigma) << name;
    EXPECT_EQ(reading.estimate.rms_normal_sigma, e.rms_normal_sigma) << name;
    EXPECT_EQ(reading.estimate.samples, e.samples) << name;
    ASSERT_EQ(reading.fits.size(), reading.samples.size()) << name;
    ASSERT_GT(reading.samples.size(), 1000u) << name;
    EXPECT_LT(reading.samples.size(), mesh->n_vertices()) << name << ": strided";
    std::vector<int> mark(mesh->n_vertices(), -1), ring;
    std::vector<Vec3> P;
    size_t fitted = 0;
    for (size_t s = 0; s < reading.samples.size(); ++s) {
      const auto [res, rss] = detail::leave_one_out_fit<10>(*mesh, mesh->vertex_handle(reading.samples[s]),
                                                            e.mean_edge, {2, 200, 1e-10}, static_cast<int>(s), mark,
                                                            ring, P);
      EXPECT_EQ(reading.fits[s], std::pair(rss, res)) << name << " sample " << s;
      fitted += res >= 0;
    }
    EXPECT_EQ(e.samples, static_cast<int>(std::max<size_t>(1, fitted / 2))) << name << ": the better-fitting half";
    const detail::RegionNoise map = detail::region_noise(one_ring_neighborhoods(*mesh), reading);
    EXPECT_NEAR(map.whole, e.normal_sigma / e.noise_share, 1e-12 * map.whole) << name;
    EXPECT_EQ(map.level.size(), static_cast<Eigen::Index>(mesh->n_vertices())) << name;
  }
}

// A flat cap under depth noise (issue 24, sixteenth session): the noise along the normal is largest where the
// surface faces the scanner, and the per-vertex reading took a cylinder's caps creased in spots only. The caps are
// planes of the sharp fit on which the input lies to within its noise, so each reads creased throughout, and the
// result is as near the truth as the better forced reading; the previous release (plane_misfit 0) read part of
// them smooth and stayed well above it.
TEST(AutoDenoise, ACylindersFlatCapsUnderDepthNoiseReadCreasedThroughout) {
  const Mesh clean = make_shape("cylinder", 2).base;
  const Mesh noisy = noisy_copy(
      clean, {.sigma = 0.3, .direction = NoiseDirection::Depth, .axis = Vec3(0.6, 0.2, 0.77).normalized(), .seed = 11});
  const MatrixX3i F = faces(clean);
  const MatrixX3d V = positions(clean);
  const auto error = [&](const AutoDenoiseOptions& o) { return part_error(F, V, auto_denoise(noisy, o).positions, 0, F.rows()); };
  const AutoDenoiseResult r = auto_denoise(noisy);
  const auto on_cap = [&](int v) { return std::abs(std::abs(V(v, 2)) - 0.5) < 1e-9; };  // the caps at z = ±0.5
  const auto caps_creased = [&](const AutoDenoiseResult& x) {
    int on_caps = 0, creased = 0;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      if (on_cap(F(f, 0)) && on_cap(F(f, 1)) && on_cap(F(f, 2)))
        ++on_caps, creased += x.creased[f] >= 0.5;
    return double(creased) / on_caps;
  };
  EXPECT_GT(caps_creased(r), 0.95);
  AutoDenoiseOptions creased, smooth, previous;
  creased.creased = true, smooth.creased = false, previous.plane_misfit = 0;
  const double best = std::min(error(creased), error(smooth));
  EXPECT_LE(part_error(F, V, r.positions, 0, F.rows()), 1.05 * best);
  const AutoDenoiseResult before = auto_denoise(noisy, previous);
  EXPECT_LT(caps_creased(before), 0.9) << "so the test can fail";
  EXPECT_GT(part_error(F, V, before.positions, 0, F.rows()), 1.1 * best) << "so the test can fail";
}
