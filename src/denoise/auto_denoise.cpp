// The default denoiser (auto_denoise.h): the noise level and the kind of surface read from the input,
// the surfel passes of ch. 7 chosen by them, the vertex fit, the change kept in proportion to the noise,
// and the edge process of ch. 6 for the labels. The constants were chosen on synthetic noise over the
// shared clean models (bench/denoise.md), never on the shared noisy pairs.

#include "geotex/denoise/auto_denoise.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/normal_fit.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

const OptionTable<AutoDenoiseOptions>& AutoDenoiseOptions::table() {
  using O = AutoDenoiseOptions;
  static const auto t = OptionTable<O>()
      .add("sigma", &O::sigma, "noise level in mean edge lengths, as geotex noise --sigma; auto: estimated",
           non_negative())
      .add("creased", &O::creased, "the surface has sharp creases (CAD-like) or not (organic); auto: read from the input")
      .add("mild_iterations", &O::mild_iterations, "sweeps of the mild surfel pass (every input)", between(0, 1000),
           "Sec. 7.4.3.5")
      .add("sharp_iterations", &O::sharp_iterations, "threshold steps of the sharp surfel pass (creased inputs)",
           between(0, 1000), "Sec. 7.4.3.4")
      .add("fit_iterations", &O::fit_iterations, "vertex updates fitting the positions to the normals",
           between(0, 100000))
      .add("keep_below", &O::keep_below,
           "normal noise (mean edge lengths) at which half of the change is kept; much less noisy inputs stay as they are",
           positive())
      .add("label_angle", &O::label_angle_deg,
           "label edges sharper than this after denoising, degrees; auto: 60 (creased), 75 (smooth)",
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
// Creased when the lower quartile of the neighbour angles after the sharp pass is below kFlatRatio × their
// median after the mild pass, or that median is below kFlatDeg. Measured (bench/denoise.md, σ 0.2–1.2):
// fandisk, cube, woody 0.066–0.099; cheburashka ≥ 0.17, bunny ≥ 0.24, torus ≥ 0.24, sphere 0.97, spot
// 0.099–0.157, and the coarse cow 0.055–0.098 (read as creased: its flat-shaded look survives the sharp pass).
constexpr double kFlatRatio = 0.12, kFlatDeg = 1.0;
// Label thresholds: fandisk and cube P/R 0.93/0.94 and 0.96/0.97 at 60° (50°: 0.89/0.94; 40°: 0.83/0.97).
constexpr double kLabelCreased = 60, kLabelSmooth = 75;
constexpr double kRelaxation = 0.25;  // the fit's tangential relaxation (surfel_fitted_mesh())
// Rounds of untangling: more rounds, with the region grown further, moved whole regions of the coarse cow
// (Ev 2.7e-3 at 10 rounds, 6.0e-3 at 50 on cow, spot and bunny at 0.2 and 0.9); 10 leave no fold in the tests.
constexpr int kUntangleRounds = 10;

// Angles (degrees) between the surfels of neighbouring vertices, each pair once, sorted.
std::vector<double> neighbor_angles(const Surfels& S, const Neighborhoods& N) {
  std::vector<double> a;
  a.reserve(N.indices.size() / 2);
  for (Eigen::Index i = 0; i < N.size(); ++i)
    for (int k = N.offsets[i]; k < N.offsets[i + 1]; ++k)
      if (N.indices[k] > i) {
        const Vec3 p = S.normals.row(i), q = S.normals.row(N.indices[k]);
        a.push_back(std::atan2(p.cross(q).norm(), p.dot(q)) * 180 / M_PI);
      }
  std::sort(a.begin(), a.end());
  return a;
}

double quantile(const std::vector<double>& sorted, double p) {
  return sorted.empty() ? 0.0 : sorted[static_cast<size_t>(p * double(sorted.size() - 1))];
}

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
// none is left or \p rounds ran. \return the faces still turned over.
int untangle(const Mesh& mesh, const MatrixX3i& F, MatrixX3d& X, const MatrixX3d& target, int rounds) {
  constexpr int kGrow = 5;
  // The target and the mean of the edge neighbours' targets: a face must agree with both.
  MatrixX3d around = MatrixX3d::Zero(target.rows(), 3);
  for (auto f : mesh.faces())
    for (auto g : mesh.ff_range(f)) around.row(f.idx()) += target.row(g.idx());
  auto turned = [&](Eigen::Index f) {
    const Vec3 a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    return n.dot(target.row(f).transpose()) <= 0 || n.dot(around.row(f).transpose()) <= 0;
  };
  std::vector<char> move(X.rows()), grown;
  int bad = 0;
  for (int round = 0;; ++round) {
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

}  // namespace

AutoDenoiseResult auto_denoise(const Mesh& mesh, const AutoDenoiseOptions& options) {
  AutoDenoiseOptions::table().check(options);
  require_valid(mesh, "denoise input");
  AutoDenoiseResult r;
  AutoDenoiseOptions& o = r.resolved;
  o = options;
  const MatrixX3d X = positions(mesh);
  const MatrixX3i F = faces(mesh);
  auto clock = std::chrono::steady_clock::now();
  auto stage = [&](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    r.seconds.emplace_back(name, std::chrono::duration<double>(now - clock).count());
    clock = now;
  };

  // 1. How noisy: the normal noise (impulses included) decides how much of the change is kept.
  // A given sigma needs no estimate (and a mesh too small to estimate from can still be denoised).
  if (!o.sigma) {
    try {
      r.noise = estimate_noise(mesh);
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
                                    r.noise.outliers > 0.02 ? fmt::format(", {:.0f}% outliers", 100 * r.noise.outliers)
                                                            : std::string()));
  }
  stage("noise estimate");
  const double s4 = std::pow(normal_noise / o.keep_below, 4), keep = s4 / (1 + s4);
  if (keep < 1e-6) {
    r.positions = X;
    r.choices.push_back("no noise found: the mesh is returned as it is");
    if (!o.creased) o.creased = false;
    if (!o.label_angle_deg) o.label_angle_deg = *o.creased ? kLabelCreased : kLabelSmooth;
    EdgeProcessOptions e;
    e.phi0_deg = *o.label_angle_deg;
    r.edge_labels = label_sharp_edges(mesh, r.positions, e);
    return r;
  }

  // 2. The mild pass, and the reading of the surface.
  const Neighborhoods N = one_ring_neighborhoods(mesh);
  const Surfels S0 = initial_surfels(mesh);
  const double m0 = median_neighbor_angle_deg(S0, N);
  SurfelOptions base;
  base.unit_length = mean_edge_length(mesh);
  base.irls_weights = true;
  base.local_sweeps = 3;        // ICM visits every surfel again: a few block minimisations per visit suffice
  base.record_energy = false;
  SurfelOptions mild = base;
  mild.iterations = o.mild_iterations;
  mild.t_end_deg = kMildEnd;
  mild.t_start_deg = std::clamp(kMildFactor * m0, kMildEnd, 60.0);
  mild.progress = [&](double f, std::string_view) { report(o.progress, 0.1 * f, "auto: mild pass"); };
  SurfelResult sr = optimize_surfels(X, N, S0, mild);
  stage("mild surfel pass");
  const std::vector<double> angles = neighbor_angles(sr.surfels, N);
  const double q50 = quantile(angles, 0.5);
  // 3. The sharp pass, which also reads the surface: it flattens the faces of a creased surface until
  // neighbouring surfels are parallel, where on a smooth one they keep the angle of its curvature.
  SurfelOptions sharp = base;
  sharp.iterations = o.sharp_iterations;
  sharp.t_end_deg = kSharpEnd;
  sharp.t_start_deg = std::clamp(kSharpFactor * m0, kSharpEnd, 60.0);
  sharp.cluster_moves = true;
  sharp.progress = [&](double f, std::string_view) { report(o.progress, 0.1 + 0.8 * f, "auto: sharp pass"); };
  SurfelResult sharp_result = optimize_surfels(X, N, S0, sharp);
  const double q25 = quantile(neighbor_angles(sharp_result.surfels, N), 0.25);
  stage("sharp surfel pass");
  if (o.creased) {
    r.choices.push_back(fmt::format("surface: {} (given)", *o.creased ? "creased" : "smooth"));
  } else {
    o.creased = q50 < kFlatDeg || q25 < kFlatRatio * q50;
    r.choices.push_back(fmt::format("surface: {} (neighbouring normals: {:.2f} deg (lower quartile) after sharpening, "
                                    "{:.1f} deg (median) after smoothing)",
                                    *o.creased ? "creased, CAD-like" : "smooth, organic", q25, q50));
  }
  if (*o.creased) {
    sr = std::move(sharp_result);
    r.choices.push_back(fmt::format("sharp surfel pass: thresholds {:.1f} -> {:.0f} deg over {} steps", sharp.t_start_deg,
                                    sharp.t_end_deg, sharp.iterations));
  } else {
    r.choices.push_back(fmt::format("mild surfel pass: threshold {:.1f} -> {:.0f} deg over {} sweeps",
                                    mild.t_start_deg, mild.t_end_deg, mild.iterations));
  }

  // 4.–6. Positions fitted to the surfels' face normals, the change kept in proportion to the noise, then
  // no face left turned over.
  MatrixX3d FN;
  if (*o.creased) {
    FN = surfel_face_normals(mesh, X, sr.surfels);  // each face the plane of its own side of a crease
  } else {
    // Smooth: the mean of the three corners' surfels (picking one corner makes creases; measured on the
    // smooth synthetic models: 5.82° against 6.59°, and fewer folds).
    FN.resize(F.rows(), 3);
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      const Vec3 m = sr.surfels.normals.row(F(f, 0)) + sr.surfels.normals.row(F(f, 1)) + sr.surfels.normals.row(F(f, 2));
      FN.row(f) = (m.norm() > 0 ? Vec3(m.normalized()) : Vec3(sr.surfels.normals.row(F(f, 0)).transpose())).transpose();
    }
  }
  consistent_targets(mesh, X, FN);
  r.positions = fit_vertices_to_normals(F, X, FN, o.fit_iterations, kRelaxation);
  if (keep < 0.999) {
    r.positions = X + keep * (r.positions - X);
    r.choices.push_back(fmt::format("low noise: {:.0f}% of the change kept", 100 * keep));
  }
  stage("vertex fit");
  r.turned_over = untangle(mesh, F, r.positions, FN, kUntangleRounds);
  stage("untangle");
  report(o.progress, 0.95, "auto: fit");

  // 7. Labels: the edge process (Eq. 6.12) on the result.
  if (!o.label_angle_deg) o.label_angle_deg = *o.creased ? kLabelCreased : kLabelSmooth;
  EdgeProcessOptions e;
  e.phi0_deg = *o.label_angle_deg;
  r.edge_labels = label_sharp_edges(mesh, r.positions, e);
  int labelled = 0;
  for (Eigen::Index k = 0; k < r.edge_labels.size(); ++k) labelled += r.edge_labels[k] > 0.5;
  r.choices.push_back(fmt::format("labels: {} edges sharper than {:.0f} deg", labelled, *o.label_angle_deg));
  stage("labels");
  report(o.progress, 1.0, "auto");
  return r;
}

}  // namespace geotex
