// Training of the default denoiser's learned reading (reading_model.h, issue 24).
//
//   reading_bench train [--seed N] [--out FILE] [--quick]
//
// The training set is synthetic noise of models the project ships or generates, never the shared models:
// data/spot.obj (shipped, CC0) and procedural shapes — CAD-like (subdivided cubes, spheres cut flat, cylinders
// with sharp rims), smooth (spheres, tori, capsules, blobs with low-frequency and with fine relief), mixed
// (plates with bumps and ridges; a cube beside a blob in one mesh) — at two resolutions, under Gaussian noise
// (σ 0.1–0.7 mean edge lengths), noise along the normals, impulsive, striped and depth-direction noise. Each
// case adds its vertices' features and labels (reading_samples()) with the weights scaled so that every case
// counts as much per vertex. Then a weighted logistic regression (train_reading_model()); the weights are
// written as C++ (--out, default stdout) with this command and the seed in their comment.
// scripts/train_reading.sh runs it and writes src/denoise/reading_weights.inc.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/reading_model.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/toolkit/refine.h"

using namespace geotex;

namespace {

// A sphere displaced along its normals by a sum of smooth waves: organic relief at the given frequency
// (waves per radian) and amplitude (in radii).
Mesh blob(int level, double frequency, double amplitude, uint64_t seed) {
  Mesh m = icosphere(level, 1.0);
  MatrixX3d V = positions(m);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 2 * M_PI);
  struct Wave { Vec3 k; double phase, a; };
  std::vector<Wave> waves;
  for (int w = 0; w < 12; ++w) {
    Vec3 k(g(rng), g(rng), g(rng));
    waves.push_back({k.normalized() * frequency * (0.7 + 0.6 * (w % 3) / 2.0), u(rng), amplitude / std::sqrt(12.0)});
  }
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    const Vec3 p = V.row(i).transpose();
    double r = 1;
    for (const auto& w : waves) r += w.a * std::sin(w.k.dot(p) + w.phase);
    V.row(i) = (p * r).transpose();
  }
  set_positions(m, V);
  return m;
}

Mesh sharp_sphere(int level, double cut) {
  Mesh m = icosphere(level, 1.0);
  MatrixX3d V = positions(m);
  for (Eigen::Index i = 0; i < V.rows(); ++i) V(i, 2) = std::clamp(V(i, 2), -cut, cut);
  set_positions(m, V);
  return m;
}

// Two meshes in one, the second scaled to the first's mean edge length and set beside it.
Mesh side_by_side(const Mesh& a, const Mesh& b) {
  const MatrixX3d A = positions(a);
  MatrixX3d B = positions(b) * (mean_edge_length(a) / mean_edge_length(b));
  const double width = (A.colwise().maxCoeff() - A.colwise().minCoeff()).maxCoeff();
  B.rowwise() += (A.colwise().mean() - B.colwise().mean());
  B.col(0).array() += 1.5 * width;
  MatrixX3d V(A.rows() + B.rows(), 3);
  V << A, B;
  const MatrixX3i FA = faces(a), FB = faces(b);
  MatrixX3i F(FA.rows() + FB.rows(), 3);
  F << FA, (FB.array() + static_cast<int>(A.rows())).matrix();
  return make_mesh(V, F);
}

struct Model {
  std::string name;
  Mesh mesh;
};

std::vector<Model> training_models(bool quick) {
  std::vector<Model> m;
  const std::filesystem::path shipped = std::filesystem::path(GEOTEX_SOURCE_DIR) / "data" / "spot.obj";
  if (!std::filesystem::exists(shipped)) throw IoError("the shipped model is missing: " + shipped.string());
  const Mesh spot = read_mesh(shipped);
  m.push_back({"spot", spot});
  m.push_back({"cube20", subdivided_cube(20)});
  m.push_back({"sharp-sphere0.6", sharp_sphere(4, 0.6)});
  m.push_back({"blob-relief", blob(5, 9, 0.05, 3)});
  if (quick) return m;
  m.push_back({"cube40", subdivided_cube(40)});
  m.push_back({"sharp-sphere0.3", sharp_sphere(5, 0.3)});
  m.push_back({"cylinder", cylinder(0.5, 1.0, 96, 48)});
  m.push_back({"cylinder-coarse", cylinder(0.5, 1.0, 48, 24)});
  m.push_back({"sphere", icosphere(5, 1.0)});
  m.push_back({"torus", torus(1.0, 0.35, 160, 60)});
  m.push_back({"capsule", make_shape("capsule", 2).textured});
  m.push_back({"blob", blob(5, 3, 0.15, 1)});
  m.push_back({"blob-coarse-relief", blob(4, 7, 0.06, 2)});
  m.push_back({"bumpy-plate", make_shape("bumpy-plate", 2).textured});
  m.push_back({"ridge-plate", make_shape("ridge-plate", 2).textured});
  m.push_back({"spiky-sphere", make_shape("spiky-sphere", 2).textured});
  {
    // spot at twice the resolution (smooth refinement): a dense organic surface.
    RefineOptions ro;
    ro.max_edge = 0.55 * mean_edge_length(spot);
    m.push_back({"spot-fine", refine_region(spot, std::vector<char>(spot.n_vertices(), 1), ro).mesh});
  }
  m.push_back({"blob-fine-relief", blob(6, 16, 0.02, 5)});
  m.push_back({"cube+blob", side_by_side(subdivided_cube(24), blob(4, 7, 0.06, 4))});
  m.push_back({"sharp-sphere+spot", side_by_side(sharp_sphere(4, 0.5), spot)});
  return m;
}

struct Noise {
  std::string name;
  NoiseOptions options;
};

std::vector<Noise> training_noises() {
  std::vector<Noise> n;
  for (double s : {0.1, 0.2, 0.3, 0.5, 0.7}) {
    NoiseOptions o;
    o.sigma = s;
    n.push_back({fmt::format("g{}", s), o});
  }
  NoiseOptions o;
  o.sigma = 0.3;
  o.direction = NoiseDirection::Normal;
  n.push_back({"n0.3", o});
  o = {};
  o.sigma = 0.6;
  o.impulsive_fraction = 0.1;
  n.push_back({"imp0.6", o});
  o = {};
  o.sigma = 0.3;
  o.pattern = NoisePattern::Striped;
  o.axis = Vec3(0.3, 0.4, 0.866).normalized();
  n.push_back({"striped0.3", o});
  o = {};
  o.sigma = 0.3;
  o.direction = NoiseDirection::Depth;
  o.axis = Vec3(0.3, 0.4, 0.866).normalized();
  n.push_back({"depth0.3", o});
  return n;
}

int cmd_train(int argc, char** argv) {
  uint64_t seed = 1;
  std::string out;
  bool quick = false;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed" && i + 1 < argc) seed = std::stoull(argv[++i]);
    else if (a == "--out" && i + 1 < argc) out = argv[++i];
    else if (a == "--quick") quick = true;
    else throw InvalidOption("reading_bench train: unknown argument '" + a + "' (--seed N, --out FILE, --quick)");
  }
  constexpr Eigen::Index kMaxPerCase = 4000;
  ReadingSamples all;
  const auto t0 = std::chrono::steady_clock::now();
  const auto models = training_models(quick);
  const auto noises = training_noises();
  int cases = 0;
  for (const auto& model : models) {
    const MatrixX3d clean = positions(model.mesh);
    for (size_t k = 0; k < noises.size(); ++k) {
      NoiseOptions no = noises[k].options;
      no.seed = seed * 1000 + static_cast<uint64_t>(cases);
      Mesh noisy = model.mesh;
      set_positions(noisy, add_noise(model.mesh, no));
      ReadingSamples s;
      try {
        s = reading_samples(noisy, clean);
      } catch (const InvalidInput& e) {
        std::fprintf(stderr, "%s %s: skipped (%s)\n", model.name.c_str(), noises[k].name.c_str(), e.what());
        continue;
      }
      // At most kMaxPerCase vertices (evenly strided), each case with the same weight per vertex.
      const Eigen::Index n = s.features.rows(), stride = std::max<Eigen::Index>(1, (n + kMaxPerCase - 1) / kMaxPerCase);
      ReadingSamples kept;
      const Eigen::Index m = (n + stride - 1) / stride;
      kept.features.resize(m, s.features.cols());
      kept.sharp_better.resize(m);
      kept.weight.resize(m);
      for (Eigen::Index i = 0; i < m; ++i) {
        kept.features.row(i) = s.features.row(i * stride);
        kept.sharp_better[i] = s.sharp_better[i * stride];
        kept.weight[i] = s.weight[i * stride] * 1000.0 / m;
      }
      double sharp_share = kept.sharp_better.dot(kept.weight) / std::max(kept.weight.sum(), 1e-300);
      std::fprintf(stderr, "%-20s %-10s %7ld vertices, sharp better (weighted) %.2f, mean |difference| %.2f deg\n",
                   model.name.c_str(), noises[k].name.c_str(), static_cast<long>(n), sharp_share,
                   s.weight.mean());
      all.append(kept);
      ++cases;
    }
  }
  const ReadingModel model = train_reading_model(all);
  const ReadingScore score = score_reading_model(model, all);
  Eigen::VectorXd rule = rule_reading(all.features);
  double rule_right = 0;
  for (Eigen::Index i = 0; i < rule.size(); ++i) rule_right += all.weight[i] * ((rule[i] > 0.5) == (all.sharp_better[i] > 0.5));
  rule_right /= all.weight.sum();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::fprintf(stderr, "%d cases, %ld samples, %.0f s: weighted accuracy %.3f (the hand-made rule %.3f), log-loss %.3f\n",
               cases, static_cast<long>(all.features.rows()), seconds, score.accuracy, rule_right, score.log_loss);
  std::string names;
  for (const auto& n : reading_feature_names()) names += (names.empty() ? "" : ", ") + n;
  const std::string source = reading_model_source(
      model, fmt::format("Made by `bash scripts/train_reading.sh` (reading_bench train --seed {}{}): {} cases of synthetic\n"
                         "noise on data/spot.obj and generated shapes, {} samples; weighted accuracy on them {:.3f}\n"
                         "(the hand-made rule: {:.3f}). Features: {}.",
                         seed, quick ? " --quick" : "", cases, all.features.rows(), score.accuracy, rule_right, names));
  if (out.empty()) {
    std::fputs(source.c_str(), stdout);
  } else {
    const std::string tmp = out + ".tmp";
    std::ofstream(tmp) << source;
    std::filesystem::rename(tmp, out);
    std::fprintf(stderr, "wrote %s\n", out.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc >= 2 && std::strcmp(argv[1], "train") == 0) return cmd_train(argc, argv);
    std::fprintf(stderr, "usage: reading_bench train [--seed N] [--out FILE] [--quick]\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reading_bench: %s\n", e.what());
    return 1;
  }
}
