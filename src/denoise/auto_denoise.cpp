// The default denoiser (auto_denoise.h): the noise level and the kind of surface read from the input,
// the surfel passes of ch. 7 chosen by them, the vertex fit, the change kept in proportion to the noise,
// and the edge process of ch. 6 for the labels. The constants were chosen on synthetic noise over the
// shared clean models (bench/denoise.md), never on the shared noisy pairs.

#include "geotex/denoise/auto_denoise.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <unordered_map>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/mesh.h"
#include "geotex/core/progress.h"
#include "geotex/denoise/coherent_change.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/normal_fit.h"
#include "geotex/denoise/reading_model.h"
#include "geotex/denoise/surfel.h"
#include "misfit_growth.h"
#include "plane_regions.h"
#include "region_guard.h"
#include "mixed_levels.h"
#include "region_noise.h"
#include "stripes.h"

namespace geotex {

const EnumNames<ReadingRule>& reading_rule_names() {
  static const EnumNames<ReadingRule> n = {
      {"combined", ReadingRule::Combined}, {"rule", ReadingRule::Rule}, {"learned", ReadingRule::Learned}};
  return n;
}

const OptionTable<AutoDenoiseOptions>& AutoDenoiseOptions::table() {
  using O = AutoDenoiseOptions;
  static const auto t = OptionTable<O>()
      .add("sigma", &O::sigma, "noise level in mean edge lengths, as geotex noise --sigma; auto: estimated",
           non_negative())
      .add("creased", &O::creased, "the surface has sharp creases (CAD-like) or not (organic), everywhere; auto: read per region from the input")
      .add("mild_iterations", &O::mild_iterations, "sweeps of the mild surfel pass (every input)", between(0, 1000),
           "Sec. 7.4.3.5")
      .add("sharp_iterations", &O::sharp_iterations, "threshold steps of the sharp surfel pass (the creased reading)",
           between(0, 1000), "Sec. 7.4.3.4")
      .add("fit_iterations", &O::fit_iterations, "vertex updates fitting the positions to the normals",
           between(0, 100000))
      .add("light_iterations", &O::light_iterations,
           "sweeps of the light mild pass, whose fit keeps the smooth reading's fine relief where it stands above the noise",
           between(0, 1000), "Sec. 7.4.3.5")
      .add("light_fit_iterations", &O::light_fit_iterations, "vertex updates of the light fit", between(0, 100000))
      .add("relief_floor", &O::relief_floor,
           "noise floor of the relief kept, in units of the local noise energy: 0 keeps the light fit everywhere, "
           "large values the mild fit everywhere", between(0, 1e6))
      .add("creased_budget", &O::creased_budget,
           "the creased reading is refused on organic-looking parts where the sharp fit moves the input by more than "
           "this many noise variances along the normals (median over a 1-ring); 0 never", between(0, 1e6))
      .add("depth_anisotropy", &O::depth_anisotropy,
           "the creased budget is measured against the noise along each normal where the noise runs along one axis "
           "(a scanner's depth noise): the mild fit's move fitted as n^T S n, read so where S's smallest eigenvalue is "
           "below this x its largest; 0 never", between(0, 1))
      .add("stripe_coherence", &O::stripe_coherence,
           "a CAD-looking part is read creased throughout where the gradient of the sharp fit's residual points one "
           "way across it (scanner stripes) with at least this coherence; 1 never", between(0, 1))
      .add("stripe_coherence_organic", &O::stripe_coherence_organic,
           "any part, organic-looking ones included (short bands fool the look), is read creased throughout where "
           "the sharp fit's residual points one way across it with at least this coherence; 1 never", between(0, 1))
      .add("stripe_share", &O::stripe_share,
           "a CAD-looking part is also read creased throughout where one sinusoid along one axis (fitted in 3D) "
           "explains at least this share of the sharp fit's residual: bands whose direction differs face to face; "
           "so is a part of any look where its coherence is also above stripe_coherence_organic, or its share "
           "above 1.5 x this; 1 never", between(0, 1))
      .add("low_frequency_residual", &O::low_frequency_residual,
           "a part is read creased throughout where the sharp fit moves it by more than this many noise variances "
           "(median; the part's own noise) and the mild fit by nearly as much: low-frequency noise the noise estimate "
           "follows; 0 never",
           between(0, 1e6))
      .add("plane_misfit", &O::plane_misfit,
           "a flat region of the sharp fit is read creased throughout where the input lies on one plane to within "
           "this x the region's noise (root-mean-square distance) and no curvature stands above the noise, where the "
           "noise runs along one axis (depth_anisotropy); 0 never",
           between(0, 1e6))
      .add("strong_floor", &O::strong_floor,
           "where a region read smooth takes the sharp pass's stronger smoothing: its departure from the mild fit "
           "below this × the local noise energy, and smoother normals; 0 never", between(0, 1e6))
      .add("plain_departure", &O::plain_departure,
           "step 5c takes a part read smooth whole where its median departure of the sharp fit from the mild one is "
           "below this × the local noise energy (wholly below 0.6 × it: the mild fit's wobble, no relief) and the "
           "noise is well above its curvature; 0 never", between(0, 1e6))
      .add("region_spread", &O::region_spread,
           "each region keeps the share of the change of its own noise level where the noise map's spread (its "
           "90%/10% quantile ratio, averaged over three more rings) is above this and holds over twenty rings; 0 never",
           between(0, 1e6))
      .add("keep_below", &O::keep_below,
           "normal noise (mean edge lengths) at which half of the change is kept; much less noisy inputs stay as they are",
           positive())
      .add("coherence_weight", &O::coherence_weight,
           "how strongly a change that is spatially coherent beyond the noise (a coarse mesh's own facets) is "
           "given back in the smooth reading; 0 keeps every change", between(0, 1e6))
      .choice("reading", &O::reading, reading_rule_names(),
              "how each region's reading is decided: combined (the hand-made rule, and sharp where the learned model "
              "is sure), rule (the hand-made threshold alone) or learned (the model alone: trained on synthetic noise "
              "of generated shapes; bench/denoise.md)")
      .add("label_angle", &O::label_angle_deg,
           "label edges sharper than this after denoising, degrees; auto: 60 (creased regions), 75 (smooth ones)",
           {0, 180, true, false}, "Eq. (6.9)");
  return t;
}

namespace {

// The mild pass (organic surfaces, and the reading of every input): IRLS weights, thresholds from
// kMildFactor × the median neighbour angle down to kMildEnd. Measured on the smooth synthetic models
// (cow, spot, cheburashka, bunny, sphere; bench/denoise.md): factor 1 / 1.5 / 2.5 gave 8.73 / 8.50 / 8.33°.
constexpr double kMildFactor = 2.5, kMildEnd = 20;
// The sharp pass (creased surfaces): surfel_denoise()'s defaults.
constexpr double kSharpFactor = 0.85, kSharpEnd = 10;
// Label thresholds: fandisk and cube P/R 0.93/0.94 and 0.96/0.97 at 60° (50°: 0.89/0.94; 40°: 0.83/0.97).
constexpr double kLabelCreased = 60, kLabelSmooth = 75;
constexpr double kRelaxation = 0.25;  // the fit's tangential relaxation (surfel_fitted_mesh())
// Rounds of untangling: more rounds, with the region grown further, moved whole regions of the coarse cow
// (Ev 2.7e-3 at 10 rounds, 6.0e-3 at 50 on cow, spot and bunny at 0.2 and 0.9); 10 leave no fold in the tests.
constexpr int kUntangleRounds = 10;
// A face the input itself turns away from its target is left by untangle() where no noise could have turned it:
// where its least height is above kFlipSpread × the normal noise (4 standard deviations of the difference of
// two vertices' noise, √2 × it). Such a face is the target's error, the smooth reading of a coarse model's own
// facets, and untangling it dragged whole regions to their neighbours' means (cow at σ 0.02 given: 1.91° noisy,
// 3.04° with, 1.94° without; the beetle's thin faces mostly stay below the bound: bench/denoise.md, issue 24
// "low noise on coarse models"). A global noise bound instead (every such face left below normal noise 0.2)
// kept noise-made folds at σ 0.3 and cost the teapot's slivers 7-8 % at σ 0.2-0.3.
constexpr double kFlipSpread = 4 * 1.4142135623730951;
using detail::kGaussianOutliers;  // outliers above it: the noise is read impulsive
// Rings over which the energy of the light fit's departure is averaged (step 5b).
constexpr int kReliefRings = 3;


// The reading of the surface per region (issue 24): both readings are fitted, and each vertex takes the
// one the learned reading (reading_model.h) says is nearer the truth, or by the previous release's rule
// (AutoDenoiseOptions::reading); the 0/1 choice is averaged over kReadingRings rings: a soft map, 1 creased.
constexpr int kReadingRings = 3;
// A blend of two fits takes its per-vertex weight averaged over a few rings: two fits' positions mixed by a
// weight that changes from vertex to vertex wrinkle the surface between them. The strong step (5c) over 4
// rings: level-4 torus at σ 0.5 1.55° -> 1.40° (the sharp fit alone 1.15°), level-3 sphere 1.19° -> 1.04°. The
// light fit's relief (5b) over 2: the shared models' synthetic noise 0.5-2 % nearer the truth on 32 of 63 cases,
// one 1.6 % farther (the beetle at σ 0.05); over 4 a noisy bunny kept a face turned over (bench/denoise.md).
constexpr int kStrongBlendRings = 4, kReliefBlendRings = 2;
// Step 5c takes a region whole where at least this share of its vertices (averaged over kStrongBlendRings
// rings) pass the roughness gate. The gate passes 79 % of a level-4 torus at σ 0.5, 42 % of a level-3 capsule at
// σ 0.2 and 2 % of a level-3 sphere at σ 0.05 (where the sharp fit facets): with the share as it was (1) the torus
// took 0.73 of the sharp fit, 1.37° against its 1.15°. 0.7 / 0.5: torus 1.32 / 1.31°, capsule 0.55 / 0.53°
// (0.57°; sharp fit 0.49°), the 63-case grid -0.01 / +0.00 % on average (bench/denoise.md, twelfth session).
constexpr double kStrongGatePass = 0.7;
// Step 5c's plain parts (plain_part_share()): a part whose median departure share E / R' is at most
// kPlainPartSpan × plain_departure is plain throughout, above plain_departure not at all (log-linear between). On pure noise the share is about
// 0.01 at every level (its median 0.007-0.010 on generated spheres, tori and capsules at σ 0.1-0.7: the mild fit's
// low-frequency wobble), on organic relief 0.07-0.7 (igea, the bunny, cheburashka, spot at σ 0.3-0.7; the
// beetle and the teapot 0.15); and the sharp fit is taken there where the normal noise is at least
// kNoiseOverCurvature[0] (wholly from [1]) times the root of the sharp fit's own normal spread (its facets, of
// the order of the curvature per edge, are then below the mild fit's wobble): median over the vertices, level-4
// torus at σ 0.1 2.9, at σ 0.2 5.4, at σ 0.5 12, where the sharp fit is 1.25×, 0.95× and 0.51× the mild one; level-3
// sphere at σ 0.05 / 0.1 / 0.2 2.1 / 4.1 / 7.9 (4 / 6: sphere σ 0.1 +1.1 %; 4.5 / 6.5: -0.4 %; bench/denoise.md,
// thirteenth session).
constexpr double kPlainPartSpan = 0.6;
constexpr double kNoiseOverCurvature[2] = {4.5, 6.5};
// ReadingRule::Combined: the learned model overrides the rule where it is this sure the sharp fit is better
// (0.9 and 0.97 measured on 28 cases of synthetic noise on the shared clean models: mean ratio to the better
// forced reading 1.010 and 1.037, the rule alone 1.043; bench/denoise.md).
constexpr double kConfident = 0.9;
// A part looks organic above this look (the share of the neighbour-normal angles the sharp fit keeps: 0.2–0.5
// on CAD parts, 0.7–1.1 on organic ones at every noise level measured; bench/denoise.md); the creased reading
// is refused there where the sharp fit moves the input by more than the noise (refuse_creased_beyond_noise()).
constexpr double kOrganicLook = 0.6;

// A target normal that points away from the input's own normals around the face (the area-weighted mean
// over the faces sharing a vertex with it: a surfel turned over on a thin part, whose one-ring reaches the
// other side) is replaced by that mean; then one that points away from the mean of its edge neighbours'
// targets is replaced by that mean (no placement of the vertices could meet both). \return the faces changed.
int consistent_targets(const Mesh& mesh, const MatrixX3d& X, MatrixX3d& target) {
  int changed = 0;
  MatrixX3d area_normal(target.rows(), 3);  // |N_f| n_f of the input
  for (auto f : mesh.faces()) {
    Vec3 p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k++] = X.row(v.idx()).transpose();
    area_normal.row(f.idx()) = (p[1] - p[0]).cross(p[2] - p[0]).transpose();
  }
  std::vector<int> around;
  for (auto f : mesh.faces()) {
    around.clear();
    for (auto v : mesh.fv_range(f))
      for (auto g : mesh.vf_range(v)) around.push_back(g.idx());
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    Vec3 mean = Vec3::Zero();
    for (int g : around) mean += area_normal.row(g).transpose();
    if (mean.norm() > 0 && target.row(f.idx()).dot(mean) < 0) {
      target.row(f.idx()) = mean.normalized().transpose();
      ++changed;
    }
  }
  for (int pass = 0; pass < 3; ++pass) {
    int now = 0;
    for (auto f : mesh.faces()) {
      Vec3 mean = Vec3::Zero();
      for (auto g : mesh.ff_range(f)) mean += target.row(g.idx()).transpose();
      if (mean.norm() > 0 && target.row(f.idx()).dot(mean) < 0) {
        target.row(f.idx()) = mean.normalized().transpose();
        ++now;
      }
    }
    changed += now;
    if (now == 0) break;
  }
  return changed;
}

// Faces that face away from their target normal (n_f · t_f <= 0: turned over, or degenerate) are untangled:
// the vertices around them move to the mean of their neighbours (Jacobi rounds, which unfold a fold-over
// as a Tutte embedding does; the region grows by a ring every kGrow rounds where a fold persists), until
// none is left or \p rounds ran. With \p input (the noisy positions), a face the input itself turns away from
// its target and whose least height there is above \p height is left alone: no fold of the fit's, but the
// target's error (see kFlipSpread). \return the faces still turned over.
int untangle(const Mesh& mesh, const MatrixX3i& F, MatrixX3d& X, const MatrixX3d& target, int rounds,
             const MatrixX3d* input = nullptr, double height = 0) {
  constexpr int kGrow = 5;
  // The target and the mean of the edge neighbours' targets: a face must agree with both.
  MatrixX3d around = MatrixX3d::Zero(target.rows(), 3);
  for (auto f : mesh.faces())
    for (auto g : mesh.ff_range(f)) around.row(f.idx()) += target.row(g.idx());
  auto turned_in = [&](const MatrixX3d& P, Eigen::Index f) {
    const Vec3 a = P.row(F(f, 0)), b = P.row(F(f, 1)), c = P.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    return n.dot(target.row(f).transpose()) <= 0 || n.dot(around.row(f).transpose()) <= 0;
  };
  std::vector<char> inherited(F.rows(), 0);  // turned over in the input already, and too tall for noise to turn
  if (input)
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const Vec3 a = input->row(F(f, 0)), b = input->row(F(f, 1)), c = input->row(F(f, 2));
      const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
      inherited[f] = turned_in(*input, f) && (b - a).cross(c - a).norm() > height * longest;  // 2 A / e > h
    }
  auto turned = [&](Eigen::Index f) { return !inherited[f] && turned_in(X, f); };
  std::vector<char> move(X.rows()), grown;
  int bad = 0;
  for (int round = 0;; ++round) {
    check_interrupt();
    std::fill(move.begin(), move.end(), 0);
    bad = 0;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      if (turned(f)) {
        ++bad;
        for (int k = 0; k < 3; ++k) move[F(f, k)] = 1;
      }
    if (bad == 0 || round == rounds) break;
    for (int ring = 0; ring < round / kGrow; ++ring) {
      grown = move;
      for (auto v : mesh.vertices())
        if (move[v.idx()])
          for (auto u : mesh.vv_range(v)) grown[u.idx()] = 1;
      move.swap(grown);
    }
    const MatrixX3d Y = X;
    for (auto v : mesh.vertices()) {
      if (!move[v.idx()] || mesh.is_boundary(v)) continue;
      Vec3 mean = Vec3::Zero();
      int n = 0;
      for (auto u : mesh.vv_range(v)) {
        mean += Y.row(u.idx()).transpose();
        ++n;
      }
      if (n > 0) X.row(v.idx()) = (mean / n).transpose();
    }
  }
  return bad;
}

// Step 7: no face of r.positions left turned over against \p FN, but those the input \p X itself turns over
// where Gaussian noise of \p normal_noise (absolute) could not have (kFlipSpread). Impulses have no Gaussian
// tail: with outliers found, every turned face is untangled (teapot impulsive +1.2 % otherwise). The mesh's level,
// not the region's: a cylinder's side under depth noise along its axis reads noise-free, yet the noise slid its
// faces along the surface and turned some over, which this undoes (per region: 1.77° -> 9.40°; fifteenth session).
void untangle_result(const Mesh& mesh, const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& FN, double normal_noise,
                     AutoDenoiseResult& r) {
  const bool gaussian = !(r.noise.outliers > kGaussianOutliers);
  r.turned_over = untangle(mesh, F, r.positions, FN, kUntangleRounds, gaussian ? &X : nullptr, kFlipSpread * normal_noise);
}

// The mesh's connected components (connected_components()), read once per call: steps 5 and 5c decide per part.
struct Parts {
  explicit Parts(const Mesh& mesh) : id(connected_components(mesh, &count)) {}
  int count = 0;       // declared first: id's initializer sets it
  Eigen::VectorXi id;  // per vertex
};

// The wall time of each stage since the previous one, appended to \p seconds by stage("name").
struct StageClock {
  std::vector<std::pair<std::string, double>>& seconds;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  void operator()(const char* name) {
    const auto now = std::chrono::steady_clock::now();
    seconds.emplace_back(name, std::chrono::duration<double>(now - last).count());
    last = now;
  }
};

// Per face, the mean of a per-vertex quantity over its three corners.
Eigen::VectorXd face_means(const MatrixX3i& F, const Eigen::VectorXd& v) {
  Eigen::VectorXd m(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) m[f] = (v[F(f, 0)] + v[F(f, 1)] + v[F(f, 2)]) / 3;
  return m;
}

// Step 6: the share \p keep of the change from the input \p X kept, per vertex (low noise: nearly none), but all of
// it at the vertices of \p whole (1 there): the CAD-looking parts read as low-frequency noise, whose noise the
// estimate missed (read_low_frequency_parts_creased()), so the share it gives is too small there (the level-4 cube
// and woody under the field over 4 edges: σ̂ 0.057 for σ 0.5, 89 % kept; all of it 8 / 5 % nearer the truth). On
// organic-looking parts the creased reading's move is partly shape flattened, which the share rightly tempers (all
// of it: spot, the bunny, cheburashka 0.5-10 % farther; bench/denoise.md, fifteenth session).
void keep_share_of_change(const MatrixX3d& X, const Eigen::VectorXd& keep_at, const Eigen::VectorXd& whole,
                          AutoDenoiseResult& r) {
  const Eigen::VectorXd keep = whole.cwiseMax(keep_at);
  if (keep.minCoeff() >= 0.999) return;
  r.positions = X + keep.asDiagonal() * (r.positions - X);
  const std::string all = whole.maxCoeff() > 0 ? " (all of it on the parts read as low-frequency noise)" : "";
  if (keep_at.maxCoeff() - keep_at.minCoeff() < 1e-9)
    r.choices.push_back(fmt::format("low noise: {:.0f}% of the change kept{}", 100 * keep_at[0], all));
  else
    r.choices.push_back(fmt::format("low noise by region: {:.0f}% of the change kept on average ({:.0f}% to {:.0f}%){}",
                                    100 * keep_at.mean(), 100 * keep_at.minCoeff(), 100 * keep_at.maxCoeff(), all));
}

// Step 6b: where the estimate read part of the residual as a coarse model's own facets (misfit_growth.h), no vertex
// moves farther than kNoiseReach × σ̂ (\p sigma_abs, absolute): 3-D Gaussian noise of σ moves 99 % of the vertices
// less than 1.94 σ; a larger move changes the model's shape. Measured (bench/denoise.md, fourteenth session):
// cow at σ 0.05 7.75° -> 6.73°, beetle 21.9° -> 15.3°; everywhere (without the gate) it cost the teapot at σ 0.2
// 19 % and spot 4 %.
constexpr double kNoiseReach = 2;
void keep_within_noise_reach(const MatrixX3d& X, double sigma_abs, AutoDenoiseResult& r) {
  if (!(r.noise.noise_share < 1) || !(sigma_abs > 0)) return;
  int capped = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const Vec3 d = (r.positions.row(v) - X.row(v)).transpose();
    const double len = d.norm();
    if (len > kNoiseReach * sigma_abs) r.positions.row(v) = X.row(v) + (kNoiseReach * sigma_abs / len) * d.transpose(), ++capped;
  }
  if (capped > 0)
    r.choices.push_back(fmt::format("coarse model: {} vertices kept within {} x sigma of the input", capped, kNoiseReach));
}

// Face target normals of the smooth reading: the mean of the three corners' surfels (picking one corner
// makes creases; measured on the smooth synthetic models: 5.82° against 6.59°), turned consistent.
MatrixX3d mild_face_normals(const Mesh& mesh, const MatrixX3d& X, const MatrixX3i& F, const MatrixX3d& S) {
  MatrixX3d FN(F.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 m = S.row(F(f, 0)) + S.row(F(f, 1)) + S.row(F(f, 2));
    FN.row(f) = (m.norm() > 0 ? Vec3(m.normalized()) : Vec3(S.row(F(f, 0)).transpose())).transpose();
  }
  consistent_targets(mesh, X, FN);
  return FN;
}

// The energies of relief_weights() (below), per vertex: E, the mean of d^2 over kReliefRings rings for the
// departure d of \p Xl from \p Xm along the normals, and R', the local noise energy (at most \p max_noise_energy).
struct DepartureEnergy {
  Eigen::VectorXd departure, noise;  // E and R' per vertex
};
DepartureEnergy departure_energy(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Xm,
                                 const MatrixX3d& Xl, double max_noise_energy) {
  MatrixX3d VN = MatrixX3d::Zero(Xm.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = Xm.row(F(f, 0)), b = Xm.row(F(f, 1)), c = Xm.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);  // area-weighted
    for (int k = 0; k < 3; ++k) VN.row(F(f, k)) += n.transpose();
  }
  Eigen::VectorXd d2(Xm.rows()), r2(Xm.rows());
  for (Eigen::Index v = 0; v < Xm.rows(); ++v) {
    const double len = VN.row(v).norm();
    const double d = len > 0 ? (Xl.row(v) - Xm.row(v)).dot(VN.row(v)) / len : 0.0;
    const double r = len > 0 ? (X.row(v) - Xm.row(v)).dot(VN.row(v)) / len : 0.0;
    d2[v] = d * d, r2[v] = r * r;
  }
  DepartureEnergy e{ring_average(N, d2, kReliefRings), ring_average(N, r2, kReliefRings)};
  for (Eigen::Index v = 0; v < e.noise.size(); ++v)
    e.noise[v] = std::min(std::max(e.noise[v] - e.departure[v], 0.0), max_noise_energy);
  return e;
}

// The Wiener share w = max(0, E - floor R') / E of departure_energy()'s \p e, per vertex.
Eigen::VectorXd wiener_share(const DepartureEnergy& e, double floor) {
  const Eigen::VectorXd& E = e.departure;
  Eigen::VectorXd w(E.size());
  for (Eigen::Index v = 0; v < E.size(); ++v) {
    const double noise_floor = floor * e.noise[v];
    w[v] = E[v] > noise_floor ? (E[v] - noise_floor) / E[v] : 0.0;
  }
  return w;
}

// Step 5b, the smooth reading's relief per region. The light fit keeps fine relief and some noise, the mild
// fit neither; their difference along the normals, d, is noise where the surface is plain and relief plus
// noise where it has detail. Each vertex keeps the light fit in the Wiener proportion w = max(0, E - c R') / E,
// E the mean of d^2 over kReliefRings rings, R' the local noise energy: the mean of r^2 for the input's
// departure r from the mild fit, less E (what the mild fit removed of the relief). A local floor follows
// noise that differs by region (scanner depth noise, impulses), where one global level kept noise as relief
// on primitives (sphere, impulsive: 0.50° -> 0.74°, depth: 0.95° -> 1.77°; bench/denoise.md). On pure
// noise E / R' is 0.03-0.11 whatever its level.
Eigen::VectorXd relief_weights(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Xm,
                               const MatrixX3d& Xl, double floor,
                               double max_noise_energy = std::numeric_limits<double>::infinity()) {
  return wiener_share(departure_energy(N, F, X, Xm, Xl, max_noise_energy), floor);
}

// The relief kept without folds: where a face of the blend turns more than 60° away from the mild fit's
// (noise kept as relief on a thin part: a fold of the bunny's ear), its corners and their rings take the mild
// fit, for a few rounds.
Eigen::VectorXd keep_unfolded(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& Xm, const MatrixX3d& Xl,
                              Eigen::VectorXd w) {
  auto normal = [&](const MatrixX3d& P, Eigen::Index f) {
    const Vec3 n = (P.row(F(f, 1)) - P.row(F(f, 0))).cross(P.row(F(f, 2)) - P.row(F(f, 0)));
    return n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero();
  };
  for (int round = 0; round < 4; ++round) {
    const MatrixX3d B = Xm + w.asDiagonal() * (Xl - Xm);
    std::vector<char> back(w.size(), 0);
    bool any = false;
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      if (normal(B, f).dot(normal(Xm, f)) < 0.5)
        for (int k = 0; k < 3; ++k) back[F(f, k)] = 1, any = true;
    if (!any) break;
    for (Eigen::Index v = 0; v < w.size(); ++v) {
      if (!back[v]) continue;
      w[v] = 0;
      for (int j = N.offsets[v]; j < N.offsets[v + 1]; ++j) w[N.indices[j]] = 0;
    }
  }
  return w;
}

// Per vertex: 1 where the sharp fit's faces around it are nearer the truth's normals than the smooth fit's,
// weighted by the difference (degrees, at most 20: a choice that matters more is learned first).
ReadingSamples reading_samples_from(const Mesh& mesh, const Eigen::MatrixXd& features, const MatrixX3d& Xs,
                                    const MatrixX3d& Xm, const MatrixX3d& truth) {
  const MatrixX3i F = faces(mesh);
  Mesh fit = mesh;
  auto normals = [&](const MatrixX3d& P) {
    set_positions(fit, P);
    return face_normals(fit);
  };
  const MatrixX3d Nt = normals(truth), Ns = normals(Xs), Nm = normals(Xm);
  const Eigen::Index n = features.rows();
  Eigen::VectorXd es = Eigen::VectorXd::Zero(n), em = Eigen::VectorXd::Zero(n), count = Eigen::VectorXd::Zero(n);
  auto angle = [](const Vec3& p, const Vec3& q) { return std::atan2(p.cross(q).norm(), p.dot(q)) * 180 / M_PI; };
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 t = Nt.row(f);
    const double a = angle(Ns.row(f), t), b = angle(Nm.row(f), t);
    for (int k = 0; k < 3; ++k) es[F(f, k)] += a, em[F(f, k)] += b, count[F(f, k)] += 1;
  }
  ReadingSamples s;
  s.features = features;
  s.sharp_better.resize(n);
  s.weight.resize(n);
  for (Eigen::Index v = 0; v < n; ++v) {
    const double d = count[v] > 0 ? (em[v] - es[v]) / count[v] : 0;
    s.sharp_better[v] = d > 0 ? 1.0 : 0.0;
    s.weight[v] = std::min(std::abs(d), 20.0);
  }
  return s;
}

}  // namespace

namespace {

// Step 1: the noise level, given (r.resolved.sigma) or estimated (into r.noise and r.resolved.sigma; the samples'
// fits into \p reading, for the noise per region). \return the normal noise (impulses included).
double resolve_noise(const Mesh& mesh, AutoDenoiseResult& r, detail::NoiseReading& reading) {
  AutoDenoiseOptions& o = r.resolved;
  if (!o.sigma) {
    try {
      reading = detail::read_noise(mesh);
      r.noise = reading.estimate;
    } catch (const InvalidInput& e) {
      throw InvalidInput(fmt::format("{} (too small a mesh to read its noise level from: give the noise level, sigma)", e.what()));
    }
  }
  double normal_noise = r.noise.rms_normal_sigma;
  if (o.sigma) {
    normal_noise = *o.sigma / std::sqrt(3.0);
    r.choices.push_back(fmt::format("noise: sigma {:.3f} mean edge lengths (given)", *o.sigma));
  } else {
    o.sigma = r.noise.sigma;
    r.choices.push_back(fmt::format("noise: sigma {:.3f} mean edge lengths (estimated{})", r.noise.sigma,
                                    r.noise.outliers > kGaussianOutliers ? fmt::format(", {:.0f}% outliers", 100 * r.noise.outliers)
                                                            : std::string()));
    if (r.noise.noise_share < 1)
      r.choices.push_back(fmt::format("noise: the fit's residual grows {:.2f}x from two rings to three: {:.0f}% of it "
                                      "read as a coarse model's own facets, not noise", r.noise.misfit_growth,
                                      100 * (1 - r.noise.noise_share)));
  }
  return normal_noise;
}

// Step 1, the mesh's level (resolve_noise(), the mesh noise below) and the noise per region (region_noise.h, from the
// same samples' fits) into r.noise_map: the given level everywhere where it was given. Per vertex, the normal noise
// its region is measured against and the share of the change it keeps (step 6, s = σ⁴ / (σ⁴ + σ0⁴) of its level);
// the level the denoiser runs at (running_level()). The regions' own levels
// (region_levels()) only where the mesh reads (nearly) noise-free but some regions do not; elsewhere the mesh noise
// everywhere, as where the noise was given: on white noise a region read above twice the mesh's level is mostly
// shape the cubic misses (creases, a coarse model's detail), and measuring it against that level cost the issue's
// grid up to 2 % (fandisk σ 0.05 +1.99 %, spot with impulses +1.02 %; bench/denoise.md, fifteenth session).
struct RegionLevels {
  Eigen::VectorXd level, keep;
  double running = 0;
};
RegionLevels read_region_noise(const Mesh& mesh, const Neighborhoods& N, AutoDenoiseResult& r) {
  detail::NoiseReading reading;  // the estimate's samples and fits, read again per region
  const double mesh_noise = resolve_noise(mesh, r, reading);
  RegionLevels out;
  if (r.noise.samples == 0) {
    r.noise_map = Eigen::VectorXd::Constant(mesh.n_vertices(), r.resolved.sigma.value_or(0) / std::sqrt(3.0));
    out.level = Eigen::VectorXd::Constant(mesh.n_vertices(), mesh_noise);
  } else {
    const detail::RegionNoise map = detail::region_noise(N, reading);
    r.noise_map = map.level;
    r.choices.push_back(detail::describe_region_noise(r.noise_map, map.whole));
    out.level = detail::region_levels(map, r.noise, mesh_noise);
  }
  const double keep_below = r.resolved.keep_below;
  out.running = detail::running_level(out.level, mesh_noise, keep_below);
  if (out.running != mesh_noise)
    r.choices.push_back(fmt::format("noise: the mesh reads {:.3f} normal noise, but some regions more: run at their "
                                    "median {:.3f}, the change kept by each region's level", mesh_noise, out.running));
  else
    out.level.setConstant(mesh_noise);
  // Levels that differ region to region (mixed_levels.h): the share of the change each region keeps by its own.
  detail::MixedLevels mixed;
  if (r.noise.samples > 0 && out.running == mesh_noise)
    mixed = detail::mixed_levels(mesh, r.noise_map,
                                 r.noise.normal_sigma > 0 ? r.noise.rms_normal_sigma / r.noise.normal_sigma : 1.0,
                                 r.resolved.region_spread);
  const Eigen::VectorXd& keep_level = mixed.level.size() > 0 ? mixed.level : out.level;
  out.keep.resize(out.level.size());
  for (Eigen::Index v = 0; v < out.keep.size(); ++v) {
    const double s4 = std::pow(keep_level[v] / keep_below, 4);
    out.keep[v] = s4 / (1 + s4);
  }
  if (mixed.level.size() > 0) r.choices.push_back(detail::describe_mixed_levels(mixed, out.keep, r.resolved.region_spread));
  return out;
}

// No noise found: the mesh returned as it is, its edges labelled (into \p r, returned).
AutoDenoiseResult keep_noise_free(const Mesh& mesh, const MatrixX3d& X, const MatrixX3i& F, AutoDenoiseResult r) {
  AutoDenoiseOptions& o = r.resolved;
  r.positions = X;
  r.choices.push_back("no noise found: the mesh is returned as it is");
  if (!o.creased) o.creased = false;
  if (!o.label_angle_deg) o.label_angle_deg = *o.creased ? kLabelCreased : kLabelSmooth;
  EdgeProcessOptions e;
  e.phi0_deg = *o.label_angle_deg;
  r.edge_labels = label_sharp_edges(mesh, r.positions, e);
  r.creased = Eigen::VectorXd::Constant(F.rows(), *o.creased ? 1.0 : 0.0);
  r.creased_share = *o.creased ? 1.0 : 0.0;
  r.relief = Eigen::VectorXd::Ones(F.rows());  // every detail kept as it is
  r.strong = Eigen::VectorXd::Zero(F.rows());
  r.refused = Eigen::VectorXd::Zero(F.rows());
  r.change_kept = Eigen::VectorXd::Ones(F.rows());
  r.relief_share = 1;
  return r;
}

// Each face's target normal: the sharp (\p FNs) and mild (\p FNm) readings' blended by how creased the
// face is (a reading not computed is null).
MatrixX3d blended_face_normals(const Eigen::VectorXd& creased, const MatrixX3d* FNs, const MatrixX3d* FNm) {
  MatrixX3d FN(creased.size(), 3);
  for (Eigen::Index f = 0; f < creased.size(); ++f) {
    const double c = creased[f];
    const Vec3 s_n = FNs ? Vec3(FNs->row(f).transpose()) : Vec3::Zero();
    const Vec3 m_n = FNm ? Vec3(FNm->row(f).transpose()) : Vec3::Zero();
    const Vec3 t = c * s_n + (1 - c) * m_n;
    FN.row(f) = (t.norm() > 0 ? Vec3(t.normalized()) : (c >= 0.5 ? s_n : m_n)).transpose();
  }
  return FN;
}

// The shares of creased and relief area (r.creased_share, r.relief_share) and the choices that say them;
// \p look: the range of the look feature over the parts.
void describe_reading(const Mesh& mesh, const MatrixX3i& F, std::pair<double, double> look, AutoDenoiseResult& r) {
  const AutoDenoiseOptions& o = r.resolved;
  const Eigen::VectorXd A = face_areas(mesh);
  double creased_area = 0, blend_area = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    if (r.creased[f] >= 0.5) creased_area += A[f];
    if (r.creased[f] > 0.1 && r.creased[f] < 0.9) blend_area += A[f];
  }
  const double total = A.sum() > 0 ? A.sum() : 1.0;
  r.creased_share = std::min(creased_area / total, 1.0);  // not above 1 by rounding ("-0% smooth")
  double refused_area = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (r.refused[f] >= 0.5) refused_area += A[f];
  r.refused_share = refused_area / total;
  double smooth_area = 0, relief_area = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (r.creased[f] < 0.5) smooth_area += A[f], relief_area += A[f] * r.relief[f];
  r.relief_share = smooth_area > 0 ? relief_area / smooth_area : 0.0;
  double strong_area = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (r.creased[f] < 0.5) strong_area += A[f] * r.strong[f];
  r.strong_share = smooth_area > 0 ? strong_area / smooth_area : 0.0;
  if (o.creased)
    r.choices.push_back(fmt::format("surface: {} everywhere (given)", *o.creased ? "creased" : "smooth"));
  else
    r.choices.push_back(fmt::format("surface, read per region: {:.0f}% creased (CAD-like), {:.0f}% smooth (organic), "
                                    "{:.0f}% in transitions",
                                    100 * r.creased_share, 100 * (1 - r.creased_share), 100 * blend_area / total));
  if (r.refused_share > 0)
    r.choices.push_back(fmt::format("creased reading refused on {:.1f}% (organic-looking, the sharp fit moved it "
                                    "beyond the noise; --creased-budget)", 100 * r.refused_share));
  if (!o.creased)
    r.choices.push_back(fmt::format("reading: {}; look (the share of the neighbour-normal angles the sharp fit "
                                    "keeps; CAD-like near 0.2-0.5, organic near 0.7-1.1): {:.3f}{}",
                                    o.reading == ReadingRule::Rule      ? "the hand-made rule"
                                    : o.reading == ReadingRule::Learned ? "learned"
                                                                        : "the hand-made rule, sharp where the learned model is sure",
                                    look.first,
                                    look.second > look.first ? fmt::format(" to {:.3f} over the parts", look.second) : ""));
}

// Step 8: the edge process (Eq. 6.12) on the result, with the threshold of each edge's reading (the
// mean of its faces'), unless one is given.
void label_edges_by_reading(const Mesh& mesh, AutoDenoiseResult& r) {
  const AutoDenoiseOptions& o = r.resolved;
  EdgeProcessOptions e;
  e.phi0_deg = o.label_angle_deg.value_or(kLabelCreased);
  r.edge_labels = label_sharp_edges(mesh, r.positions, e);
  if (!o.label_angle_deg && r.creased_share < 1) {
    e.phi0_deg = kLabelSmooth;
    const Eigen::VectorXd smooth_labels = label_sharp_edges(mesh, r.positions, e);
    for (auto edge : mesh.edges()) {
      double c = 0;
      int k = 0;
      for (int side = 0; side < 2; ++side)
        if (const auto face = edge.h(side).face(); face.is_valid()) c += r.creased[face.idx()], ++k;
      if (k == 0 || c / k < 0.5) r.edge_labels[edge.idx()] = smooth_labels[edge.idx()];
    }
  }
  int labelled = 0;
  for (Eigen::Index k = 0; k < r.edge_labels.size(); ++k) labelled += r.edge_labels[k] > 0.5;
  const std::string label_rule = o.label_angle_deg ? fmt::format("{:.0f} deg", *o.label_angle_deg)
                                                   : fmt::format("{:.0f} deg (creased regions), {:.0f} deg (smooth)",
                                                                 kLabelCreased, kLabelSmooth);
  r.choices.push_back(fmt::format("labels: {} edges sharper than {}", labelled, label_rule));
}

// 1 at the vertices read creased, 0 elsewhere: the rule's reading, the learned model's (p > 1/2), or the
// rule's where the model is not confident (p <= kConfident) and sharp where it is.
Eigen::VectorXd sharp_vertices(const Eigen::MatrixXd& features, ReadingRule reading) {
  const Eigen::VectorXd rule = rule_reading(features);
  Eigen::VectorXd sharp_here = rule;
  if (reading != ReadingRule::Rule) {
    const Eigen::VectorXd p = default_reading_model().probability(features);
    for (Eigen::Index v = 0; v < p.size(); ++v)
      sharp_here[v] = reading == ReadingRule::Learned ? (p[v] > 0.5 ? 1.0 : 0.0)
                                                      : (p[v] > kConfident ? 1.0 : rule[v]);
  }
  return sharp_here;
}

// Per vertex, the median of \p x over its closed 1-ring (the vertex and its neighbours): a few vertices far out
// (impulses) do not move it.
Eigen::VectorXd closed_ring_median(const Neighborhoods& N, const Eigen::VectorXd& x) {
  Eigen::VectorXd median(x.size());
#pragma omp parallel
  {
    std::vector<double> ring;  // one buffer per thread, not one allocation per vertex
#pragma omp for schedule(static)
    for (Eigen::Index v = 0; v < x.size(); ++v) {
      ring.assign(1, x[v]);
      for (int k = N.offsets[v]; k < N.offsets[v + 1]; ++k) ring.push_back(x[N.indices[k]]);
      const auto mid = ring.begin() + static_cast<std::ptrdiff_t>(ring.size() / 2);
      std::nth_element(ring.begin(), mid, ring.end());
      median[v] = *mid;
    }
  }
  return median;
}

// Per vertex, how far the fit \p P moves the input \p X along the normals \p Nn: the median of the squared move
// over the closed 1-ring (impulses, a tenth of the vertices, do not move it), averaged over 2 rings.
Eigen::VectorXd typical_move(const Neighborhoods& N, const MatrixX3d& Nn, const MatrixX3d& X, const MatrixX3d& P) {
  Eigen::VectorXd move(X.rows());
  for (Eigen::Index v = 0; v < X.rows(); ++v) move[v] = std::pow(Nn.row(v).dot(P.row(v) - X.row(v)), 2);
  return ring_average(N, closed_ring_median(N, move), 2);
}

// Depth noise (depth_noise_scale()): on white noise the mild fit's typical move (typical_move()) is 0.27-0.44 of
// the normal noise variance (level-3 sphere, level-2 cylinder at σ 0.2, level-3 torus at σ 0.5); the noise along a
// normal is read from it in proportion 1 / kMildMove (0.3 / 0.45 / 0.6: the scanner grid's cylinder under depth
// noise σ 0.2 1.326 / 1.341 / 1.380°, the bunny σ 0.5 6.080 / 6.074 / 6.065°; bench/denoise.md, fourteenth session).
constexpr double kMildMove = 0.3;
// The normals determine Σ (depth_noise_scale()) where the least-squares system's reciprocal condition is above
// this: a box's faces (woody) face along three axes only, and leave Σ's off-diagonal terms free.
constexpr double kDepthDetermined = 1e-4;

// Step 5, depth noise: a range scanner displaces each vertex along its viewing axis a, so the noise along the
// normal has the variance σ² (n·a)²: largest where the surface faces the scanner, where the mesh's estimate (its
// best-fitting half of the rings, the least noisy) reads much less (a level-2 cylinder at σ 0.2 along an oblique
// axis: normal noise 0.061 estimated, 0.105 over the surface, 0.17 on the caps). The mild fit \p Xm's move from
// \p X (typical_move() along its normals \p Nn) is fitted as nᵀ Σ n, Σ symmetric, by least squares over the
// vertices. Where Σ is far from isotropic (its smallest eigenvalue below \p anisotropy × its largest; white noise
// on the shared models 0.16-0.91, depth noise on the cylinder below 0.01, on fandisk and the bunny at σ 0.5
// 0.09 / 0.04, where the shape's misfit in the mild fit's move hides it at σ 0.2: 0.17-0.45) and the normals
// present determine it, \return per vertex the noise variance along the normal over \p noise_var
// (nᵀ Σ n / kMildMove), at least 1; else ones.
Eigen::VectorXd depth_noise_scale(const Neighborhoods& N, const MatrixX3d& Nn, const MatrixX3d& X,
                                  const MatrixX3d& Xm, double noise_var, double anisotropy) {
  const Eigen::Index n = Nn.rows();
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(n);
  if (!(anisotropy > 0) || !(noise_var > 0)) return scale;
  const Eigen::VectorXd move = typical_move(N, Nn, X, Xm);
  auto row = [&](Eigen::Index v) {
    const Vec3 m = Nn.row(v);
    Eigen::Matrix<double, 6, 1> q;
    q << m.x() * m.x(), m.y() * m.y(), m.z() * m.z(), 2 * m.x() * m.y(), 2 * m.x() * m.z(), 2 * m.y() * m.z();
    return q;
  };
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (Eigen::Index v = 0; v < n; ++v) {
    const auto q = row(v);
    A += q * q.transpose(), b += move[v] * q;
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(A);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > kDepthDetermined)) return scale;  // normals along few axes
  const Eigen::Matrix<double, 6, 1> s = ldlt.solve(b);
  Eigen::Matrix3d S;
  S << s[0], s[3], s[4], s[3], s[1], s[5], s[4], s[5], s[2];
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(S, Eigen::EigenvaluesOnly);
  if (!(es.eigenvalues()[2] > 0) || es.eigenvalues()[0] >= anisotropy * es.eigenvalues()[2]) return scale;
  for (Eigen::Index v = 0; v < n; ++v) scale[v] = std::max(row(v).dot(s) / (kMildMove * noise_var), 1.0);
  return scale;
}

// Step 5, the creased reading held to the noise: a fit that removes only noise moves each vertex along the normal
// by about the noise (median of its squared move over a 1-ring about 0.45 σ², a χ² of one degree). Where the
// sharp fit moves a vertex of an organic-looking part by more than \p budget σ² (the median over its closed
// 1-ring, averaged over 2 rings: impulses, a tenth of the vertices, do not move the median; not on the parts read
// striped, \p striped, whose bands the sharp fit rightly removes), it flattens shape,
// not noise: a coarse organic mesh's curvature at low noise (cow σ 0.05: the creased reading 18.5° against 9.6°,
// and the rule read 8 % of it creased). Such vertices are read smooth (\p sharp set to 0). On CAD-looking parts
// the sharp fit's larger moves are creases restored or scanner stripes flattened, rightly (the striped cube:
// 3.1° as it is, 6.9° if they were refused). The default budget, 1 σ², is about twice a noise-only fit's median
// (budgets 2 / 1.5 / 1 on the shared models' synthetic noise: spot σ 0.2 4.56 / 4.52 / 4.46°, forced smooth
// 4.43°; the beetle σ 0.05 23.5 / — / 22.9°; nothing worse by more than 0.3 %). Under depth noise σ² is the
// noise along each normal (depth_noise_scale(), \p anisotropy), or where larger the region's own (\p regional: its
// level's variance over the mesh's, at least 1; region_levels()). \return 1 at the vertices refused.
Eigen::VectorXd refuse_creased_beyond_noise(const Mesh& mesh, const Neighborhoods& N, const MatrixX3d& X,
                                            const MatrixX3d& Xs, const MatrixX3d& Xm, const Eigen::MatrixXd& features,
                                            const Eigen::VectorXd& striped, double budget, double noise_var,
                                            double anisotropy, const Eigen::VectorXd& regional, Eigen::VectorXd& sharp) {
  const Eigen::Index n = X.rows();
  Eigen::VectorXd refused = Eigen::VectorXd::Zero(n);
  if (!(budget > 0)) return refused;
  Mesh fit = mesh;
  set_positions(fit, Xm);
  const MatrixX3d Nm = vertex_normals(fit);
  const Eigen::VectorXd typical = typical_move(N, Nm, X, Xs);
  std::vector<Eigen::Index> beyond;  // column 4: the log of the part's look (reading_feature_names())
  for (Eigen::Index v = 0; v < n; ++v)
    if (sharp[v] > 0 && striped[v] == 0 && typical[v] > budget * noise_var && features(v, 4) > std::log(kOrganicLook))
      beyond.push_back(v);
  if (beyond.empty()) return refused;  // the depth noise's scale only raises the budget
  const Eigen::VectorXd along = depth_noise_scale(N, Nm, X, Xm, noise_var, anisotropy);
  for (Eigen::Index v : beyond)
    if (typical[v] > budget * noise_var * std::max(along[v], regional[v])) sharp[v] = 0, refused[v] = 1;
  return refused;
}

// A part of fewer vertices has too few faces for a direction of its residual to mean anything: the teapot's
// patches of 111-450 vertices reach 0.45-0.99 under white noise (0.07-0.75 at σ 0.05-0.7, seed 7, where their
// residual's energy, 0.1-34 noise variances, does not tell them from bands either). Woody's 694 vertices read
// 0.06-0.09 under white noise (σ 0.05-0.7) and 0.48-0.51 under stripes 4-6 edges apart (bench/denoise.md,
// fourteenth session).
constexpr int kMinStripedPart = 600;
// An organic-looking part is read striped only where the bands stand above the noise: the part's mean squared
// residual, after the 1-ring median, at least this × the normal noise variance. A white residual's median keeps
// little of it (the cylinder under white noise, σ 0.05-0.7 at two seeds: 0.06-0.23, with a coherence of 0.34-0.44
// from its shape alone, the sharp fit's facets along its axis); bands keep most (fandisk, the cube and igea under
// stripes 3-4 edges apart: 1.18-2.96; bench/denoise.md, thirteenth session).
constexpr double kStripeEnergy = 0.5;

// Step 5, scanner stripes whose direction differs face to face (issue 24, fifteenth session): the part-wide
// tensor of read_striped_parts_creased() mixes the projections of the bands' axis onto a cube's faces (stripes 16
// edges apart: 0.16; woody under oblique stripes: 0.27), but the bands are one function of a·x for one world axis a,
// which fit_stripes() fits in 3D (stripes.h). One sinusoid along it explains 0.19-0.83 of the residual under
// stripes and at most 0.12 under white noise (woody with 10 % impulses 0.37, a part read creased throughout
// anyway; bench/denoise.md). Where the coherence rule has not already read it: a CAD-looking part above
// \p stripe_share is banded; an organic-looking part where its coherence is also above \p organic_threshold (the
// share then stands in for kStripeEnergy: the cylinder under stripes 8 edges apart at σ 0.5, 0.37) or where the
// share is above kOrganicBands × \p stripe_share: a smooth primitive under oblique stripes, whose faces see the
// bands run different ways (the cylinder: coherence 0.23-0.39, share 0.56-0.74), while organic models under
// stripes reach 0.33 (the bunny; spot and cheburashka 0.13-0.24), their residual being shape the sharp fit
// flattens as much as bands, and the smooth reading the better one. \p best_share: the largest share measured
// (-1: none). \return per part, 1 where banded.
constexpr double kOrganicBands = 1.5;
std::vector<char> banded_parts(const Mesh& mesh, const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& Xs,
                               const Eigen::VectorXd& r, const Eigen::MatrixXd& features, const Eigen::VectorXi& part,
                               const std::vector<int>& size, const std::vector<double>& coherence,
                               const std::vector<double>& energy, double organic_threshold, double stripe_share,
                               double* best_share) {
  const int n_parts = static_cast<int>(size.size());
  std::vector<char> banded(n_parts, 0), cad(n_parts, 0), measure(n_parts, 0);
  if (!(stripe_share < 1)) return banded;
  for (Eigen::Index v = 0; v < X.rows(); ++v) cad[part[v]] = features(v, 4) < std::log(kOrganicLook);
  std::vector<std::vector<int>> verts(n_parts), tris(n_parts);
  for (int p = 0; p < n_parts; ++p)  // only where the answer could change the reading
    measure[p] = coherence[p] >= 0 && (cad[p] || !(coherence[p] > organic_threshold && energy[p] >= kStripeEnergy));
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    if (measure[part[v]]) verts[part[v]].push_back(static_cast<int>(v));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (measure[part[F(f, 0)]]) tris[part[F(f, 0)]].push_back(static_cast<int>(f));
  const double h = mean_edge_length(mesh);
  for (int p = 0; p < n_parts; ++p) {
    if (!measure[p]) continue;
    const double share = detail::fit_stripes(X, Xs, F, tris[p], verts[p], r, h).share;
    *best_share = std::max(*best_share, share);
    banded[p] = share > stripe_share &&
                (cad[p] || coherence[p] > organic_threshold || share > kOrganicBands * stripe_share);
  }
  return banded;
}

// Step 5, scanner stripes: a range scanner's bands displace a part along its normals by a wave that runs one way
// across it. The sharp fit removes them (its residual is the wave) where the mild fit keeps them as relief, and the
// rule reads the creases' neighbourhoods (bent by the bands) and scattered vertices smooth: the default was 1.19-1.63x
// the forced creased reading on striped fandisk and cube (bench/denoise.md, twelfth session). Per part, the
// area-weighted structure tensor of the gradient of the residual r = n·(X − Xs) (its median over the closed 1-ring;
// on the sharp fit's faces, n its vertex normals): white noise has no direction (coherence (λ1 − λ2) / (λ1 + λ2)
// 0.00-0.22 on fandisk, the cube and woody at σ 0.05-0.7 and with impulses), bands one (0.44-0.80 at wavelengths
// 4-8, across z or an oblique axis, σ 0.2-0.3). A CAD-looking part (look below kOrganicLook) above \p threshold
// is read creased throughout, and any part above \p organic_threshold: bands 4 edges apart fool the look (fandisk
// 0.72, the cube 1.38; coherence 0.56, 0.73), while an organic part's residual is mostly shape flattened, which
// runs no one way (0.03-0.32 under white and striped noise; bench/denoise.md, thirteenth session), where the bands
// stand above the noise (kStripeEnergy; \p noise_var the normal noise's variance, absolute). \p striped_at:
// 1 at the vertices of the parts so read. \p largest: the largest coherence over the parts measured (-1: none).
// \return the vertices set.
int read_striped_parts_creased(const Mesh& mesh, const Parts& parts, const Neighborhoods& N, const MatrixX3i& F,
                               const MatrixX3d& X, const MatrixX3d& Xs, const Eigen::MatrixXd& features, double threshold,
                               double organic_threshold, double stripe_share, double noise_var, Eigen::VectorXd& sharp,
                               Eigen::VectorXd& striped_at, double* largest, double* best_share) {
  *largest = -1, *best_share = -1;  // no part measured
  striped_at = Eigen::VectorXd::Zero(X.rows());
  if (!(std::min({threshold, organic_threshold, stripe_share}) < 1)) return 0;
  Mesh fit = mesh;
  set_positions(fit, Xs);
  const MatrixX3d Ns = vertex_normals(fit);
  Eigen::VectorXd r0(X.rows());
  for (Eigen::Index v = 0; v < X.rows(); ++v) r0[v] = Ns.row(v).dot(X.row(v) - Xs.row(v));
  // The median over the closed 1-ring: impulses (a few vertices far out, each with a gradient of its own
  // direction) would otherwise make a part look banded by chance (fandisk with 10 % impulses: 0.19).
  const Eigen::VectorXd r = closed_ring_median(N, r0);
  const int n_parts = parts.count;
  const Eigen::VectorXi& part = parts.id;
  std::vector<Eigen::Matrix3d> T(n_parts, Eigen::Matrix3d::Zero());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = Xs.row(F(f, 0)), b = Xs.row(F(f, 1)), c = Xs.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    const double n2 = n.squaredNorm();
    if (!(n2 > 0)) continue;
    // The gradient of the linear interpolant of r over the face, weighted by its area.
    const Vec3 g = (n.cross(c - b) * r[F(f, 0)] + n.cross(a - c) * r[F(f, 1)] + n.cross(b - a) * r[F(f, 2)]) / n2;
    T[part[F(f, 0)]] += 0.5 * std::sqrt(n2) * g * g.transpose();
  }
  std::vector<int> size(n_parts, 0);
  std::vector<double> energy(n_parts, 0);  // the mean of r^2 over the part, in noise variances
  for (Eigen::Index v = 0; v < X.rows(); ++v) ++size[part[v]], energy[part[v]] += r[v] * r[v];
  for (int p = 0; p < n_parts; ++p) energy[p] /= std::max(size[p], 1) * noise_var;
  std::vector<double> coherence(n_parts, -1);
  for (int p = 0; p < n_parts; ++p) {
    if (size[p] < kMinStripedPart) continue;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
    es.computeDirect(T[p], Eigen::EigenvaluesOnly);
    const double l1 = es.eigenvalues()[2], l2 = es.eigenvalues()[1];
    if (l1 + l2 > 0) coherence[p] = (l1 - l2) / (l1 + l2), *largest = std::max(*largest, coherence[p]);
  }
  const std::vector<char> banded = banded_parts(mesh, F, X, Xs, r, features, part, size, coherence, energy,
                                                 organic_threshold, stripe_share, best_share);
  int set = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const bool cad = features(v, 4) < std::log(kOrganicLook);
    const bool coherent = coherence[part[v]] > (cad ? threshold : organic_threshold) &&
                          (cad || energy[part[v]] >= kStripeEnergy);
    if (!coherent && !banded[part[v]]) continue;
    striped_at[v] = 1;
    if (sharp[v] == 0) sharp[v] = 1, ++set;
  }
  return set;
}

// Step 5's scanner stripes (read_striped_parts_creased() with the resolved threshold), said in the choices.
Eigen::VectorXd read_stripes(const Mesh& mesh, const Parts& parts, const Neighborhoods& N, const MatrixX3i& F,
                             const MatrixX3d& X, const MatrixX3d& Xs, const Eigen::MatrixXd& features, double noise_var,
                             Eigen::VectorXd& sharp, AutoDenoiseResult& r) {
  const double threshold = r.resolved.stripe_coherence;
  double coherence = -1, share = -1;
  Eigen::VectorXd striped_at;
  const int striped = read_striped_parts_creased(mesh, parts, N, F, X, Xs, features, threshold,
                                                 r.resolved.stripe_coherence_organic, r.resolved.stripe_share,
                                                 noise_var, sharp, striped_at, &coherence, &share);
  if (coherence >= 0)
    r.choices.push_back(fmt::format("stripes: the sharp fit's residual runs one way with coherence {:.3f} (largest "
                                    "over the parts of {}+ vertices; striped above {} on CAD-looking parts, above {} "
                                    "on others where the bands stand above the noise){}{}", coherence, kMinStripedPart,
                                    threshold, r.resolved.stripe_coherence_organic,
                                    share >= 0 ? fmt::format("; one sinusoid along a fitted axis explains {:.3f} of it "
                                                             "(banded above {})", share, r.resolved.stripe_share)
                                               : std::string(),
                                    striped > 0 ? fmt::format(": {} vertices of a striped part read creased", striped)
                                                : std::string()));
  return striped_at;
}

// Step 5, low-frequency scanner noise (issue 24, fourteenth session): a scanner's low-frequency error displaces a
// part along its normals by a smooth field a few edges across. The noise estimate's cubic over the 2-ring follows
// most of it (σ 0.5 over 4 edges reads σ̂ 0.03-0.06), the mild fit keeps the rest as relief, and the rule (the
// sharp fit's residual against the mild one's) reads the part smooth where the creased reading removes the field
// (fandisk 18.2° against 12.4°, the bunny 14.0° against 11.0°; bench/denoise.md). It has no direction, so the
// stripe rules cannot see it. Per part, the medians of two reading features (reading_feature_names(), 5 rings):
// the sharp fit moves the part far beyond the noise estimated (sharp_residual above \p residual noise variances)
// and the mild fit nearly as far (z5 = log(r_sharp / r_smooth) less than kLowFrequencyReach above the hand-made
// rule's threshold for the part's look, rule_threshold(): below 0.5 on organic-looking parts). Under the field over 4-6
// edges: 30-87 noise variances, z5 0.11-0.45. Where the sharp fit flattens shape that the mild fit keeps, z5 is
// 0.65-1.1 (organic models under white noise at σ 0.05, up to 28 noise variances; under a field 8 edges across,
// which is shape to both fits and the smooth reading's to keep). With z5 below 0.5 and no gain from the creased
// reading, at most 12.5 (the coarse cow, spot under a field over 3 edges); white noise at most 7. \p residual's
// default, 20, sits between (a factor 1.5-1.6 from each). Such a part is read creased throughout, and the creased
// budget is not applied to it (\p low_at: 1 there). \p largest: the medians of the part the sharp fit moves most
// (size -1: none measured). \return the vertices set.
// The medians of a smaller part are a few vertices' (the teapot's patches, 348-450 vertices, read alike).
constexpr int kMinLowFrequencyPart = 300;
// How far z5 may stand above the rule's threshold for the part's look. On a CAD-looking part the sharp fit's
// residual exceeds the mild one's on the flat faces it restores (the rule reads such a part creased up to z5 0.3,
// an organic one up to -0.5), so the field leaves z5 higher there: the cube and woody under the field over 4
// edges 0.69 / 0.71 at looks 0.49 / 0.43, where the creased reading is 1.63 / 1.31x better (a bound of 0.5 on
// every look left them smooth; fifteenth session, bench/denoise.md). A CAD-looking part under white noise never
// comes near (sharp_residual at most 2 on fandisk and woody, σ 0.05-0.7). Over 8+ edges z5 stands 1.2-1.5 above
// the threshold (the cube 1.44-1.54, where the readings tie; the bunny 1.36, spot 1.2, the smooth reading better).
constexpr double kLowFrequencyReach = 1.0;

struct PartMedians {
  double size = -1, sharp_residual = 0, z5 = 0, threshold = 0;  // threshold: the rule's for the part's look
  bool readable() const { return size >= kMinLowFrequencyPart && z5 < threshold + kLowFrequencyReach; }
};

std::vector<PartMedians> part_medians(const Eigen::MatrixXd& features, const Eigen::VectorXi& part, int n_parts) {
  std::vector<std::vector<double>> sr(n_parts), z5(n_parts), t(n_parts);
  for (Eigen::Index v = 0; v < features.rows(); ++v)  // columns 0, 2, 11: z5, sharp_residual, rule_margin (t - z5)
    sr[part[v]].push_back(features(v, 2)), z5[part[v]].push_back(features(v, 0)),
        t[part[v]].push_back(features(v, 11) + features(v, 0));
  const auto median = [](std::vector<double>& x) {
    const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
    std::nth_element(x.begin(), mid, x.end());
    return *mid;
  };
  std::vector<PartMedians> m(n_parts);
  for (int p = 0; p < n_parts; ++p)
    if (!sr[p].empty()) m[p] = {double(sr[p].size()), std::exp(median(sr[p])), median(z5[p]), median(t[p])};
  return m;
}

// The variance of a part's normal noise alone (estimate_noise() on the part: its vertices \p verts, its faces \p
// tris, both of the mesh \p X, \p F) over the mesh's \p noise: one noise level per mesh measures a part under a
// low-frequency field against another part's white noise (fandisk under a field beside spot under white σ 0.2: 17.6
// noise variances, 42 alone). 1 where the part is too small to estimate from.
double part_noise_share(const MatrixX3d& X, const MatrixX3i& F, const std::vector<int>& verts,
                        const std::vector<int>& tris, double all_var) {
  std::unordered_map<int, int> index;
  MatrixX3d Xp(verts.size(), 3);
  for (size_t k = 0; k < verts.size(); ++k) index[verts[k]] = static_cast<int>(k), Xp.row(k) = X.row(verts[k]);
  MatrixX3i Fp(tris.size(), 3);
  for (size_t k = 0; k < tris.size(); ++k)
    Fp.row(k) << index[F(tris[k], 0)], index[F(tris[k], 1)], index[F(tris[k], 2)];
  try {
    const Mesh sub = make_mesh(Xp, Fp);
    const double own = estimate_noise(sub).rms_normal_sigma * mean_edge_length(sub);
    return own > 0 && all_var > 0 ? own * own / all_var : 1;
  } catch (const InvalidInput&) {
    return 1;
  }
}

// Each part's own noise variance over the mesh's (part_noise_share()) where \p m says it could be read
// (PartMedians::readable()); 1 where the noise was given (\p noise not estimated) or the mesh has one part.
std::vector<double> part_noise_shares(const Mesh& mesh, const Eigen::VectorXi& part, const std::vector<PartMedians>& m,
                                      const NoiseEstimate& noise) {
  const int n_parts = static_cast<int>(m.size());
  std::vector<double> share(n_parts, 1);
  if (n_parts < 2 || noise.samples == 0) return share;
  const MatrixX3d X = positions(mesh);
  const MatrixX3i F = faces(mesh);
  std::vector<std::vector<int>> verts(n_parts), tris(n_parts);
  for (Eigen::Index v = 0; v < X.rows(); ++v) verts[part[v]].push_back(static_cast<int>(v));
  for (Eigen::Index f = 0; f < F.rows(); ++f) tris[part[F(f, 0)]].push_back(static_cast<int>(f));
  const double all_var = std::pow(noise.rms_normal_sigma * mean_edge_length(mesh), 2);
  for (int p = 0; p < n_parts; ++p)
    if (m[p].readable())
      share[p] = part_noise_share(X, F, verts[p], tris[p], all_var);
  return share;
}

int read_low_frequency_parts_creased(const Mesh& mesh, const Parts& parts, const Eigen::MatrixXd& features,
                                     double residual, const NoiseEstimate& noise, Eigen::VectorXd& sharp,
                                     Eigen::VectorXd& low_at, PartMedians* largest) {
  low_at = Eigen::VectorXd::Zero(features.rows());
  // The rule finds noise the estimate missed: none where the noise was given (the coarse cow at a given σ 0.02: its
  // facets stand at 40+ noise variances), nor where the estimate read part of the residual as a coarse model's own
  // facets (misfit_growth.h; the cow at σ 0.02 estimated: 40 noise variances, z5 0.25, read creased 6.36° against
  // 4.75°): the sharp fit's large move is those facets flattened.
  if (!(residual > 0) || noise.samples == 0 || noise.noise_share < 1) return 0;
  const int n_parts = parts.count;
  const Eigen::VectorXi& part = parts.id;
  std::vector<PartMedians> m = part_medians(features, part, n_parts);
  const std::vector<double> share = part_noise_shares(mesh, part, m, noise);
  std::vector<char> low(n_parts, 0);
  for (int p = 0; p < n_parts; ++p) {
    if (m[p].size < kMinLowFrequencyPart) continue;
    m[p].sharp_residual /= share[p];
    if (m[p].sharp_residual > largest->sharp_residual || largest->size < 0) *largest = m[p];
    low[p] = m[p].sharp_residual > residual && m[p].readable();
  }
  int set = 0;
  for (Eigen::Index v = 0; v < features.rows(); ++v) {
    if (!low[part[v]]) continue;
    low_at[v] = 1;
    if (sharp[v] == 0) sharp[v] = 1, ++set;
  }
  return set;
}

// Step 5's low-frequency noise (read_low_frequency_parts_creased()), said in the choices; \p full_change: 1 at the
// vertices so read on CAD-looking parts (keep_share_of_change()).
Eigen::VectorXd read_low_frequency(const Mesh& mesh, const Parts& parts, const Eigen::MatrixXd& features,
                                   Eigen::VectorXd& sharp, Eigen::VectorXd& full_change, AutoDenoiseResult& r) {
  PartMedians largest;
  Eigen::VectorXd low_at;
  const int set = read_low_frequency_parts_creased(mesh, parts, features, r.resolved.low_frequency_residual, r.noise,
                                                   sharp, low_at, &largest);
  if (largest.size >= 0)
    r.choices.push_back(fmt::format("low-frequency noise: the sharp fit moves a part by {:.3g} noise variances, "
                                    "z5 {:.3f} (medians over the part of {:.0f} vertices moved most; a part is read "
                                    "creased throughout above {} and below {:.2f}: {} above the rule's threshold for "
                                    "its look){}", largest.sharp_residual, largest.z5, largest.size,
                                    r.resolved.low_frequency_residual, largest.threshold + kLowFrequencyReach,
                                    kLowFrequencyReach,
                                    low_at.sum() > 0 ? fmt::format(": {:.0f} vertices read so, {} of them set", low_at.sum(), set)
                                                     : std::string()));
  full_change = low_at;  // column 4: the log of the part's look
  for (Eigen::Index v = 0; v < low_at.size(); ++v)
    if (features(v, 4) > std::log(kOrganicLook)) full_change[v] = 0;
  return low_at;
}

// Step 5, flat regions (plane_regions.h): a region the sharp fit makes one plane and whose input lies on it to
// within its noise (noise_map) is read creased throughout, whatever its vertices' features say one by one: the
// flat caps of a cylinder under depth noise, 2.6x noisier than its side, read creased in spots (the learned model
// sure at 54-62 % of their vertices, the rule nowhere), 2.16° against 1.19° forced creased (bench/denoise.md,
// sixteenth session). \return 1 at their vertices.
// Only where the noise runs along one axis (depth_noise_scale() reads Σ anisotropic): under white noise a region of
// an organic model at high noise passes the test on a curvature below the noise (cheburashka at σ 0.7 +3.6 %), and
// woody's one part at σ 0.5 +6.7 % (the grid).
Eigen::VectorXd read_planes(const Mesh& mesh, const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X,
                            const MatrixX3d& Xs, const MatrixX3d& Xm, double noise_var, Eigen::VectorXd& sharp,
                            AutoDenoiseResult& r) {
  Mesh fit = mesh;
  set_positions(fit, Xm);
  if (!(depth_noise_scale(N, vertex_normals(fit), X, Xm, noise_var, r.resolved.depth_anisotropy).maxCoeff() > 1))
    return Eigen::VectorXd::Zero(X.rows());
  const Eigen::VectorXd plane =
      detail::plane_regions(F, X, Xs, r.noise_map, mean_edge_length(mesh), r.resolved.plane_misfit);
  int set = 0;
  for (Eigen::Index v = 0; v < plane.size(); ++v)
    if (plane[v] > 0 && sharp[v] == 0) sharp[v] = 1, ++set;
  if (plane.sum() > 0)
    r.choices.push_back(fmt::format("flat regions: {:.0f} vertices lie on planes of the sharp fit to within {} x their "
                                    "noise, read creased throughout ({} of them set)",
                                    plane.sum(), r.resolved.plane_misfit, set));
  return plane;
}

// Step 5's parts read creased throughout: scanner stripes (read_stripes()), low-frequency noise
// (read_low_frequency(); \p low: 1 at those of CAD-looking parts) and flat regions (read_planes()); \return 1 at
// their vertices, which the creased budget leaves alone.
Eigen::VectorXd read_whole_parts(const Mesh& mesh, const Parts& parts, const Neighborhoods& N, const MatrixX3i& F,
                                 const MatrixX3d& X, const MatrixX3d& Xs, const MatrixX3d& Xm,
                                 const Eigen::MatrixXd& features,
                                 double noise_var, Eigen::VectorXd& sharp, Eigen::VectorXd& low, AutoDenoiseResult& r) {
  const Eigen::VectorXd striped = read_stripes(mesh, parts, N, F, X, Xs, features, noise_var, sharp, r);
  const Eigen::VectorXd low_frequency = read_low_frequency(mesh, parts, features, sharp, low, r);
  return striped.cwiseMax(low_frequency).cwiseMax(read_planes(mesh, N, F, X, Xs, Xm, noise_var, sharp, r));
}

// Step 5b: the light pass's relief blended into the mild fit \p Xm and its normals \p FNm where it stands
// above the noise; \p relief: per face, how much of it was kept.
void add_light_relief(const Mesh& mesh, const MatrixX3d& X, const MatrixX3i& F, const Neighborhoods& N,
                      const Surfels& S0, const SurfelOptions& mild, const AutoDenoiseOptions& o, MatrixX3d& Xm,
                      MatrixX3d& FNm, Eigen::VectorXd& relief) {
  SurfelOptions l = mild;
  l.iterations = o.light_iterations;
  l.progress = nullptr;
  const SurfelResult light = optimize_surfels(X, N, S0, l);
  const MatrixX3d FNl = mild_face_normals(mesh, X, F, light.surfels.normals);
  const MatrixX3d Xl = fit_vertices_to_normals(F, X, FNl, o.light_fit_iterations, kRelaxation);
  const Eigen::VectorXd w =
      keep_unfolded(N, F, Xm, Xl, ring_average(N, relief_weights(N, F, X, Xm, Xl, o.relief_floor), kReliefBlendRings));
  Xm += w.asDiagonal() * (Xl - Xm);
  relief = face_means(F, w);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 t = relief[f] * FNl.row(f) + (1 - relief[f]) * FNm.row(f);
    if (t.norm() > 0) FNm.row(f) = t.normalized().transpose();
  }
}

// Per vertex, how much the unit face normals of \p P vary around it: 1 - |their mean|^2 (the mean of
// |n_f - mean|^2 over its faces).
Eigen::VectorXd normal_spread(const MatrixX3i& F, const MatrixX3d& P) {
  MatrixX3d sum = MatrixX3d::Zero(P.rows(), 3);
  Eigen::VectorXd count = Eigen::VectorXd::Zero(P.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 n = (P.row(F(f, 1)) - P.row(F(f, 0))).cross(P.row(F(f, 2)) - P.row(F(f, 0)));
    if (n.norm() == 0) continue;
    for (int k = 0; k < 3; ++k) sum.row(F(f, k)) += n.normalized().transpose(), count[F(f, k)] += 1;
  }
  Eigen::VectorXd spread(P.rows());
  for (Eigen::Index v = 0; v < P.rows(); ++v)
    spread[v] = count[v] > 0 ? 1 - sum.row(v).squaredNorm() / (count[v] * count[v]) : 0.0;
  return spread;
}

// Step 5c on a plain part (issue 24, thirteenth session): the Wiener share (per vertex) counts the mild fit's
// low-frequency wobble as relief where it stands above strong_floor at scattered vertices, and the roughness
// gate fails at scattered vertices where the sharp fit's normals spread as much as the mild fit's, so a dense
// primitive at high noise took 0.7-0.9 of the sharp fit (level-4 torus at σ 0.5 1.32° against 1.15°). Over a whole
// part the wobble is told from relief by its size: a part whose median departure share E / R'
// (departure_energy() of the sharp fit from the mild one) is below \p plain_departure, the wobble's own size
// on pure noise, has no relief the mild fit could keep, and its vertices take the sharp fit where the normal noise
// is well above the sharp fit's own normal spread \p rough_s (kNoiseOverCurvature: at low noise the sharp fit's
// facets cost more than the wobble; the mild fit's spread would count its wobble as curvature). \p normal_noise
// in mean edge lengths. \return per vertex, the share so taken.
Eigen::VectorXd plain_part_share(const Parts& parts, const Neighborhoods& N, const DepartureEnergy& e,
                                 const Eigen::VectorXd& rough_s, double normal_noise, double plain_departure) {
  if (!(plain_departure > 0)) return Eigen::VectorXd::Zero(rough_s.size());
  const int n_parts = parts.count;
  const Eigen::VectorXi& part = parts.id;
  std::vector<std::vector<double>> shares(n_parts);
  for (Eigen::Index v = 0; v < part.size(); ++v)
    shares[part[v]].push_back(e.noise[v] > 0 ? e.departure[v] / e.noise[v] : std::numeric_limits<double>::infinity());
  std::vector<double> plain(n_parts, 0.0);
  const double lo = kPlainPartSpan * plain_departure, hi = plain_departure;
  for (int p = 0; p < n_parts; ++p) {
    auto& x = shares[p];
    if (x.size() < 2) continue;  // an isolated vertex
    const auto mid = x.begin() + static_cast<std::ptrdiff_t>(x.size() / 2);
    std::nth_element(x.begin(), mid, x.end());
    plain[p] = *mid <= lo ? 1.0 : *mid >= hi ? 0.0 : std::log(hi / *mid) / std::log(hi / lo);
  }
  Eigen::VectorXd above(part.size());
  for (Eigen::Index v = 0; v < above.size(); ++v) {
    const double ratio = rough_s[v] > 0 ? normal_noise / std::sqrt(rough_s[v]) : std::numeric_limits<double>::infinity();
    above[v] = std::clamp((ratio - kNoiseOverCurvature[0]) / (kNoiseOverCurvature[1] - kNoiseOverCurvature[0]), 0.0, 1.0);
  }
  above = ring_average(N, above, kStrongBlendRings);
  for (Eigen::Index v = 0; v < above.size(); ++v) above[v] *= plain[part[v]];
  return above;
}

// Step 5c, the smooth reading smoothed as strongly as the sharp pass where that is safe. On a dense, plainly
// curved surface at moderate to high noise the sharp pass (more steps, cluster moves) removes noise the mild
// pass leaves (level-4 sphere at σ 0.2: 0.39° against 0.73°; torus at σ 0.5: 1.15° against 2.30°), where on
// relief it flattens eyes and nostrils into facets, and at low noise it facets a sphere (σ 0.05: 0.73° against
// 0.63°). So a vertex takes the sharp fit in proportion 1 - w, w the Wiener share of the sharp fit's departure
// standing above strong_floor × the local noise energy (relief_weights(): on pure noise the departure's
// energy is 0.3-1.5 % of it, on the relief of spot, the bunny or igea at σ 0.5 6-16 %; the local energy capped
// at the mesh's noise variance, since where the mild pass itself rounds relief away, as on the spiky sphere's
// spikes, the input's departure from it is relief, not noise), and only where the
// sharp fit's normals vary less around the vertices than the mild fit's over kReliefRings rings (smoother,
// not faceted). Chosen on generated spheres, tori and capsules at levels 3-5, spot and cheburashka.
// \p noise_var: the normal noise's variance (absolute). \return the share taken, per vertex.
Eigen::VectorXd add_strong_smoothing(const Parts& parts, const Neighborhoods& N, const MatrixX3d& X, const MatrixX3i& F,
                                     const MatrixX3d& Xs, const MatrixX3d& FNs, const Eigen::VectorXd& cv,
                                     const AutoDenoiseOptions& o, double normal_noise, double noise_var, MatrixX3d& Xm,
                                     MatrixX3d& FNm) {
  const double floor = o.strong_floor;
  if (floor <= 0) return Eigen::VectorXd::Zero(X.rows());
  const DepartureEnergy energy = departure_energy(N, F, X, Xm, Xs, noise_var);
  const Eigen::VectorXd w = wiener_share(energy, floor);
  const Eigen::VectorXd rough_m = ring_average(N, normal_spread(F, Xm), kReliefRings);
  const Eigen::VectorXd rough_s = ring_average(N, normal_spread(F, Xs), kReliefRings);
  // The gate and the Wiener complement averaged over the rings apart: the gate's share taken whole from
  // kStrongGatePass up (a plain region whose gate fails at scattered vertices, the sharp fit's few facets, is
  // plain all the same), the complement as it is (relief keeps the mild fit).
  Eigen::VectorXd gate(w.size()), plain(w.size());
  for (Eigen::Index v = 0; v < w.size(); ++v) {
    gate[v] = cv[v] < 1 && rough_s[v] < rough_m[v] ? 1.0 : 0.0;
    plain[v] = cv[v] < 1 ? 1 - w[v] : 0.0;
  }
  gate = ring_average(N, gate, kStrongBlendRings), plain = ring_average(N, plain, kStrongBlendRings);
  Eigen::VectorXd t(w.size());
  // A plain part (plain_part_share()) takes the sharp fit whatever the gate and the Wiener share say.
  const Eigen::VectorXd whole = plain_part_share(parts, N, energy, rough_s, normal_noise, o.plain_departure);
  for (Eigen::Index v = 0; v < t.size(); ++v)
    t[v] = std::max(std::min(1.0, gate[v] / kStrongGatePass) * plain[v], cv[v] < 1 ? whole[v] : 0.0);
  t = keep_unfolded(N, F, Xm, Xs, t);
  Xm += t.asDiagonal() * (Xs - Xm);
  const Eigen::VectorXd tf = face_means(F, t);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 b = tf[f] * FNs.row(f) + (1 - tf[f]) * FNm.row(f);
    if (b.norm() > 0) FNm.row(f) = b.normalized().transpose();
  }
  return t;
}

// Step 5d: the reading's transitions kept unfolded. Where a CAD-looking part (\p cad: 1 at its vertices) is
// read partly smooth, the mild fit can fold at high noise beside a flat panel, and the reading's blend with it
// (keep_unfolded()'s test: a face turned more than 60° from the sharp fit's) takes the sharp fit around that
// face instead (woody at σ 0.7: three faces 35-76° from the truth, against 4-6° in the sharp fit). Organic parts
// are left to the reading: there a fold of the sharp fit is the likelier one. \p creased, the per-face map, is
// updated where \p cv changed. \return the vertices changed.
int keep_transitions_unfolded(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& Xs, const MatrixX3d& Xm,
                              const Eigen::VectorXd& cad, Eigen::VectorXd& cv, Eigen::VectorXd& creased) {
  Eigen::VectorXd mild_share = (1 - cv.array()).matrix();
  if (!((cad.array() > 0) && (cv.array() > 0) && (cv.array() < 1)).any()) return 0;  // no such transition
  const Eigen::VectorXd kept = keep_unfolded(N, F, Xs, Xm, mild_share);
  int changed = 0;
  for (Eigen::Index v = 0; v < cv.size(); ++v)
    if (cad[v] > 0 && cv[v] > 0 && kept[v] < mild_share[v]) cv[v] = 1 - kept[v], ++changed;
  if (changed > 0) creased = face_means(F, cv);
  return changed;
}

// Step 6a: the change of the regions read smooth (1 - \p cv) given back where it is coherent beyond the
// noise (coherent_change.h), \p noise_var the normal noise's variance (absolute); the sharp fit's share
// \p strong (step 5c) is exempt like the creased reading (its low-frequency wobble removed is coherent, and
// rightly: a level-4 torus at σ 0.5 1.45° with the exemption, 1.58° without). Fills r.change_kept(_share). Chosen on
// synthetic noise of cow, beetle, spot, bunny and cheburashka (bench/denoise.md "Coarse models"): the
// creased reading is left alone (its crease fits move whole regions coherently, and rightly).
void give_back_coherent(const Mesh& mesh, const MatrixX3d& X, const MatrixX3i& F, const Neighborhoods& N,
                        const Eigen::VectorXd& cv, const Eigen::VectorXd& strong, double noise_var,
                        AutoDenoiseResult& r) {
  r.change_kept = Eigen::VectorXd::Ones(F.rows());
  CoherentChangeOptions c;
  c.weight = r.resolved.coherence_weight;
  if (c.weight <= 0 || cv.minCoeff() >= 1) return;  // off, or every region read creased
  const MatrixX3d change = r.positions - X;
  Eigen::VectorXd g = coherent_change_gain(N, vertex_normals(mesh), change, noise_var, c);
  for (Eigen::Index v = 0; v < g.size(); ++v)
    g[v] = 1 - (1 - g[v]) * (1 - std::clamp(cv[v], 0.0, 1.0)) * (1 - strong[v]);
  r.positions = X + g.asDiagonal() * change;
  const Eigen::VectorXd area = face_areas(mesh);
  double kept = 0;
  r.change_kept = face_means(F, g);
  for (Eigen::Index f = 0; f < F.rows(); ++f) kept += area[f] * r.change_kept[f];
  r.change_kept_share = area.sum() > 0 ? kept / area.sum() : 1.0;
  if (r.change_kept_share < 0.995)
    r.choices.push_back(fmt::format("coherent change given back: {:.0f}% of the change kept (area-weighted; "
                                    "coherence weight {})", 100 * r.change_kept_share, c.weight));
}

// The choices that say how the surfel passes ran (a pass not run is null) and how much relief was kept.
void describe_passes(const SurfelOptions* sharp, const SurfelOptions* mild, bool want_light, int unfolded,
                     AutoDenoiseResult& r) {
  const AutoDenoiseOptions& o = r.resolved;
  if (sharp && r.creased_share > 0)
    r.choices.push_back(fmt::format("sharp surfel pass: thresholds {:.1f} -> {:.0f} deg over {} steps", sharp->t_start_deg,
                                    sharp->t_end_deg, sharp->iterations));
  if (mild && r.creased_share < 1)
    r.choices.push_back(fmt::format("mild surfel pass: threshold {:.1f} -> {:.0f} deg over {} sweeps",
                                    mild->t_start_deg, mild->t_end_deg, mild->iterations));
  if (want_light && r.creased_share < 1)
    r.choices.push_back(fmt::format("relief (smooth regions): {:.0f}% of the light fit ({} sweep(s), {} updates) "
                                    "kept where it stands above {} x the local noise energy",
                                    100 * r.relief_share, o.light_iterations, o.light_fit_iterations, o.relief_floor));
  if (r.strong_share > 0.005)
    r.choices.push_back(fmt::format("strong smoothing (smooth regions): {:.0f}% take the sharp fit (departure below {} x "
                                    "the local noise energy, smoother normals; a part whole where its median departure "
                                    "is below {} x it)", 100 * r.strong_share, o.strong_floor, o.plain_departure));
  if (unfolded > 0)
    r.choices.push_back(fmt::format("transitions kept unfolded: {} vertices of CAD-looking parts take the sharp fit "
                                    "where the mild one folds", unfolded));
}

// A surfel pass's options: \p iterations threshold steps from \p factor × the median neighbour angle \p m0
// (at most 60°, at least \p end_deg) down to \p end_deg.
SurfelOptions pass_options(SurfelOptions p, int iterations, double factor, double end_deg, double m0) {
  p.iterations = iterations;
  p.t_end_deg = end_deg;
  p.t_start_deg = std::clamp(factor * m0, end_deg, 60.0);
  return p;
}

// The options both passes share: lengths in mean edge lengths, IRLS weights, no energy record.
SurfelOptions base_pass_options(const Mesh& mesh) {
  SurfelOptions base;
  base.unit_length = mean_edge_length(mesh);
  base.irls_weights = true;
  base.local_sweeps = 3;  // ICM visits every surfel again: a few block minimisations per visit suffice
  base.record_energy = false;
  return base;
}

// auto_denoise(); with \p truth (the clean positions), stops after the two fits and fills \p samples instead.
AutoDenoiseResult denoise_or_sample(const Mesh& mesh, const AutoDenoiseOptions& options, const MatrixX3d* truth,
                                    ReadingSamples* samples) {
  AutoDenoiseOptions::table().check(options);
  require_valid(mesh, "denoise input");
  AutoDenoiseResult r;
  AutoDenoiseOptions& o = r.resolved;
  o = options;
  const MatrixX3d X = positions(mesh);
  const MatrixX3i F = faces(mesh);
  StageClock stage{r.seconds};

  // 1. How noisy, per region (region_noise.h; impulses included): each vertex keeps the change in proportion to its
  // region's level. A given sigma needs no estimate (and a mesh too small to estimate from can still be denoised).
  const Neighborhoods N = one_ring_neighborhoods(mesh);
  const RegionLevels region = read_region_noise(mesh, N, r);
  const double normal_noise = region.running;
  stage("noise estimate");
  if (std::pow(normal_noise / o.keep_below, 4) < 1e-6 || region.keep.maxCoeff() < 1e-6)  // as keep's formula
    return keep_noise_free(mesh, X, F, std::move(r));

  // A reading that is forced away is not computed (--creased skips the mild pass, --no-creased the sharp).
  const bool want_sharp = o.creased.value_or(true), want_mild = !o.creased.value_or(false);
  // 2. The mild pass: the smooth reading.
  const Parts parts(mesh);
  const Surfels S0 = initial_surfels(mesh);
  const double m0 = median_neighbor_angle_deg(S0, N);
  const SurfelOptions base = base_pass_options(mesh);
  SurfelOptions mild = pass_options(base, o.mild_iterations, kMildFactor, kMildEnd, m0);
  mild.progress = [&](double f, std::string_view) { report(o.progress, 0.1 * f, "auto: mild pass"); };
  SurfelResult sr;
  if (want_mild) sr = optimize_surfels(X, N, S0, mild);
  stage("mild surfel pass");
  // 3. The sharp pass: the creased reading. It flattens the faces of a creased surface until neighbouring
  // surfels are parallel, where on a smooth one they keep the angle of its curvature.
  SurfelOptions sharp = pass_options(base, o.sharp_iterations, kSharpFactor, kSharpEnd, m0);
  sharp.cluster_moves = true;
  sharp.progress = [&](double f, std::string_view) { report(o.progress, 0.1 + 0.8 * f, "auto: sharp pass"); };
  SurfelResult sharp_result;
  if (want_sharp) sharp_result = optimize_surfels(X, N, S0, sharp);
  stage("sharp surfel pass");

  // 4. Target face normals of each reading: the sharp pass's (each face the plane of its own side of a
  // crease) and the mean of the three corners' mild surfels (picking one corner makes creases; measured
  // on the smooth synthetic models: 5.82° against 6.59°); positions fitted to each.
  MatrixX3d FNs, FNm, Xs, Xm;
  if (want_sharp) {
    FNs = surfel_face_normals(mesh, X, sharp_result.surfels);
    consistent_targets(mesh, X, FNs);
    Xs = fit_vertices_to_normals(F, X, FNs, o.fit_iterations, kRelaxation);
  }
  if (want_mild) {
    FNm = mild_face_normals(mesh, X, F, sr.surfels.normals);
    Xm = fit_vertices_to_normals(F, X, FNm, o.fit_iterations, kRelaxation);
  }
  stage("vertex fit");

  // 5. The reading, per region (reading_model.h); --creased / --no-creased force one everywhere.
  std::pair<double, double> look{0, 0};
  const double noise_var = std::pow(normal_noise * base.unit_length, 2);
  Eigen::VectorXd cv, cad = Eigen::VectorXd::Zero(X.rows()), refused = cad, low = cad;
  if (o.creased) {
    cv = Eigen::VectorXd::Constant(N.size(), *o.creased ? 1.0 : 0.0);
  } else {
    const Eigen::MatrixXd features = reading_features(mesh, N, X, Xs, Xm, normal_noise, &parts.id);
    if (truth) {
      *samples = reading_samples_from(mesh, features, Xs, Xm, *truth);
      return r;
    }
    look = {std::exp(features.col(4).minCoeff()), std::exp(features.col(4).maxCoeff())};
    Eigen::VectorXd sharp_here = sharp_vertices(features, o.reading);
    const Eigen::VectorXd whole =
        read_whole_parts(mesh, parts, N, F, X, Xs, Xm, features, noise_var, sharp_here, low, r);
    refused = refuse_creased_beyond_noise(mesh, N, X, Xs, Xm, features, whole, o.creased_budget, noise_var,
                                          o.depth_anisotropy,
                                          (region.level / normal_noise).array().square().max(1.0).matrix(), sharp_here);
    cv = ring_average(N, sharp_here, kReadingRings);
    cad = (features.col(4).array() <= std::log(kOrganicLook)).cast<double>().matrix();
  }
  r.creased = face_means(F, cv);
  r.refused = face_means(F, refused);
  // 5b. The smooth reading keeps the light fit's relief where it stands above the noise (the reading above
  // compared the mild fit, as it was tuned and trained to).
  stage("reading");
  r.relief = Eigen::VectorXd::Zero(F.rows());
  // The light pass: not needed where no vertex is read smooth, or where it would be the mild pass itself.
  const bool want_light = want_mild && o.light_iterations != o.mild_iterations && cv.minCoeff() < 0.5;
  if (want_light) {
    add_light_relief(mesh, X, F, N, S0, mild, o, Xm, FNm, r.relief);
    stage("relief");
  }
  // 5c. Plain, smoothly curved regions read smooth take the sharp fit's stronger smoothing; 5d. no fold of the
  // mild fit left in the transitions of a CAD-looking part.
  Eigen::VectorXd strong = Eigen::VectorXd::Zero(X.rows());
  int unfolded = 0;
  if (want_mild && want_sharp && cv.minCoeff() < 1) {
    strong = add_strong_smoothing(parts, N, X, F, Xs, FNs, cv, o, normal_noise, noise_var, Xm, FNm);
    unfolded = keep_transitions_unfolded(N, F, Xs, Xm, cad, cv, r.creased);
    stage("strong smoothing");
  }
  r.strong = face_means(F, strong);
  r.positions = !want_mild ? Xs : !want_sharp ? Xm : MatrixX3d(cv.asDiagonal() * Xs + (1 - cv.array()).matrix().asDiagonal() * Xm);
  const MatrixX3d FN = blended_face_normals(r.creased, want_sharp ? &FNs : nullptr, want_mild ? &FNm : nullptr);
  describe_reading(mesh, F, look, r);
  describe_passes(want_sharp ? &sharp : nullptr, want_mild ? &mild : nullptr, want_light, unfolded, r);
  // 6a. The smooth reading's change given back where it is coherent beyond the noise.
  give_back_coherent(mesh, X, F, N, cv, strong, noise_var, r);
  // 6.–7. The change kept in proportion to the noise, then no face left turned over.
  keep_share_of_change(X, region.keep, low, r);
  keep_within_noise_reach(X, r.noise.sigma * base.unit_length, r);
  untangle_result(mesh, F, X, FN, normal_noise * base.unit_length, r);
  // 6c. On a model read coarse, each region's change shrunk to what the noise explains (region_guard.h).
  detail::hold_change_to_noise(N, F, X, r.noise.sigma * base.unit_length, r);
  stage("untangle");
  report(o.progress, 0.95, "auto: fit");

  // 8. Labels (see label_edges_by_reading).
  label_edges_by_reading(mesh, r);
  stage("labels");
  report(o.progress, 1.0, "auto");
  return r;
}

}  // namespace

AutoDenoiseResult auto_denoise(const Mesh& mesh, const AutoDenoiseOptions& options) {
  return denoise_or_sample(mesh, options, nullptr, nullptr);
}

ReadingSamples reading_samples(const Mesh& noisy, const MatrixX3d& clean, const AutoDenoiseOptions& options) {
  if (clean.rows() != static_cast<Eigen::Index>(noisy.n_vertices()))
    throw InvalidInput(fmt::format("reading samples: {} clean positions for {} vertices", clean.rows(), noisy.n_vertices()));
  AutoDenoiseOptions o = options;
  o.creased.reset();
  ReadingSamples s;
  denoise_or_sample(noisy, o, &clean, &s);
  if (s.features.rows() == 0) throw InvalidInput("reading samples: no noise found (the readings are not fitted)");
  return s;
}

}  // namespace geotex
