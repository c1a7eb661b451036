// The learned reading of a surface per vertex (reading_model.h): features from the two fits, a weighted
// logistic model trained by Newton's method, and the weights compiled in.

#include "geotex/denoise/reading_model.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"

namespace geotex {

namespace {

// Parts under this many vertices take the whole mesh's look (too few angles for quartiles).
constexpr int kMinComponent = 100;
// A part's own look counts as much as the whole mesh's when it has this many vertices: a small part's quartiles
// are noisy (the teapot's Bezier patches of 111–121 vertices read 38–98 % creased on their own look where the
// smooth reading is right: the default 1.02–1.06× the forced smooth reading; shrunk with 400, 1.00–1.015×;
// teapot σ 0.1 with 0 / 100 / 200 / 400: 6.33 / 6.17 / 6.08 / 6.04°, forced smooth 5.96°). Parts of thousands of
// vertices keep nearly their own look. The learned model was trained on the unshrunk look (its training shapes
// are parts of thousands of vertices, where the two differ little).
constexpr double kLookPrior = 400;

// A part's look, from two fits' vertex normals across the mesh edges: how much of the angle between
// neighbouring normals the sharp fit keeps, sqrt((q50_sharp / q50_smooth) (q75_sharp / q75_smooth)). On a
// CAD part the sharp fit flattens the faces between creases (most angles near 0: 0.21–0.53 on fandisk, the
// cube and woody at σ 0.1–0.5); on an organic one it turns curvature into facets of a few edges, whose
// angles stay (0.73–1.1 on spot, cheburashka, the teapot and the cow). \return one value per vertex, and
// the whole mesh's in \p whole. \p comp: the mesh's connected components (connected_components()).
Eigen::VectorXd component_look(const Eigen::VectorXi& comp, const Neighborhoods& N, const MatrixX3d& Ns,
                               const MatrixX3d& Nm, double* whole) {
  const Eigen::Index n = N.size();
  const int n_components = comp.size() > 0 ? comp.maxCoeff() + 1 : 0;
  std::vector<std::vector<int>> members(n_components);
  for (Eigen::Index v = 0; v < n; ++v) members[comp[v]].push_back(static_cast<int>(v));
  const auto angle = [](const MatrixX3d& Nv, int i, int j) {
    const Vec3 p = Nv.row(i), q = Nv.row(j);
    return std::atan2(p.cross(q).norm(), p.dot(q));
  };
  auto look = [&](const std::vector<int>& vs) {
    std::vector<double> as, am;
    for (int i : vs)
      for (int k = N.offsets[i]; k < N.offsets[i + 1]; ++k)
        if (const int j = N.indices[k]; j > i) as.push_back(angle(Ns, i, j)), am.push_back(angle(Nm, i, j));
    if (am.empty()) return 1.0;
    auto q = [](std::vector<double>& a, double p) {
      const auto it = a.begin() + static_cast<std::ptrdiff_t>(p * double(a.size() - 1));
      std::nth_element(a.begin(), it, a.end());
      return *it;
    };
    const double m50 = q(am, 0.5), m75 = q(am, 0.75), s50 = q(as, 0.5), s75 = q(as, 0.75);
    if (!(m50 > 0 && m75 > 0)) return 0.0;  // the smooth fit is flat: so is the part
    return std::sqrt((s50 / m50) * (s75 / m75));
  };
  std::vector<int> all(n);
  for (Eigen::Index v = 0; v < n; ++v) all[v] = static_cast<int>(v);
  *whole = look(all);
  Eigen::VectorXd ratio(n);
  for (const auto& m : members) {
    // Shrunk towards the whole mesh's look in proportion to the part's size (a geometric mean weighted n : n0).
    const double nm = double(m.size()), own = m.size() >= kMinComponent ? look(m) : *whole;
    const auto log_of = [](double x) { return std::log(std::clamp(x, 1e-3, 10.0)); };
    const double r = std::exp((nm * log_of(own) + kLookPrior * log_of(*whole)) / (nm + kLookPrior));
    for (int v : m) ratio[v] = r;
  }
  return ratio;
}

// The mean angle (radians) between a vertex's normal and its one-ring's.
Eigen::VectorXd ring_angle(const Neighborhoods& N, const MatrixX3d& Nv) {
  Eigen::VectorXd a = Eigen::VectorXd::Zero(N.size());
#pragma omp parallel for schedule(static)
  for (Eigen::Index v = 0; v < N.size(); ++v) {
    const Vec3 p = Nv.row(v);
    double sum = 0;
    for (int k = N.offsets[v]; k < N.offsets[v + 1]; ++k) {
      const Vec3 q = Nv.row(N.indices[k]);
      sum += std::atan2(p.cross(q).norm(), p.dot(q));
    }
    if (const int d = N.offsets[v + 1] - N.offsets[v]; d > 0) a[v] = sum / d;
  }
  return a;
}

// The hand-made rule's threshold on z5 for a part of log-look \p log_look: 0.3 on a part that looks creased
// (look <= 0.55), −0.5 on one that looks organic (>= 0.70), log-linear between (chosen on synthetic noise of
// the shared clean models, bench/denoise.md).
double rule_threshold(double log_look) {
  constexpr double kRatioCreased = 0.55, kRatioSmooth = 0.70, kThresholdCreased = 0.3, kThresholdSmooth = -0.5;
  const double u = std::clamp((log_look - std::log(kRatioCreased)) / std::log(kRatioSmooth / kRatioCreased), 0.0, 1.0);
  return kThresholdCreased + u * (kThresholdSmooth - kThresholdCreased);
}

double sigmoid(double t) { return t >= 0 ? 1 / (1 + std::exp(-t)) : std::exp(t) / (1 + std::exp(t)); }

}  // namespace

namespace {
// Each vertex's value and its one-ring's summed (divided by their count when \p mean), \p rounds times.
Eigen::VectorXd ring_rounds(const Neighborhoods& N, Eigen::VectorXd x, int rounds, bool mean) {
  for (int round = 0; round < rounds; ++round) {
    Eigen::VectorXd next(x.size());
#pragma omp parallel for schedule(static)
    for (Eigen::Index v = 0; v < x.size(); ++v) {
      double sum = x[v];
      for (int k = N.offsets[v]; k < N.offsets[v + 1]; ++k) sum += x[N.indices[k]];
      next[v] = mean ? sum / (1 + N.offsets[v + 1] - N.offsets[v]) : sum;
    }
    x.swap(next);
  }
  return x;
}
}  // namespace

Eigen::VectorXd ring_average(const Neighborhoods& N, Eigen::VectorXd x, int rounds) {
  return ring_rounds(N, std::move(x), rounds, true);
}

Eigen::VectorXd ring_sum(const Neighborhoods& N, Eigen::VectorXd x, int rounds) {
  return ring_rounds(N, std::move(x), rounds, false);
}

const std::vector<std::string>& reading_feature_names() {
  static const std::vector<std::string> names = {
      "z5",               // log(r_sharp / r_smooth), residuals along the normals averaged over 5 rings
      "z1",               // the same over 1 ring
      "sharp_residual",   // log(r_sharp / noise²), 5 rings
      "smooth_residual",  // log(r_smooth / noise²), 5 rings
      "look",             // log of the part's look (component_look())
      "look_whole",       // log of the whole mesh's look
      "local_look",       // log(ring angle of the sharp fit / of the smooth fit), 2 rings
      "smooth_angle",     // log(ring angle of the smooth fit in degrees + 0.01)
      "noise",            // log(normal noise in mean edge lengths)
      "z5_look",          // z5 × look
      "noise_look",       // noise × look
      "rule_margin",      // t − z5, the hand-made rule's margin (rule_reading(): sharp where positive)
  };
  return names;
}

Eigen::MatrixXd reading_features(const Mesh& mesh, const Neighborhoods& N, const MatrixX3d& X, const MatrixX3d& Xs,
                                 const MatrixX3d& Xm, double normal_noise, const Eigen::VectorXi* components) {
  const Eigen::Index n = X.rows();
  Mesh fit = mesh;
  set_positions(fit, Xs);
  const MatrixX3d Ns = vertex_normals(fit);
  set_positions(fit, Xm);
  const MatrixX3d Nm = vertex_normals(fit);
  Eigen::VectorXd rs(n), rm(n);
  for (Eigen::Index v = 0; v < n; ++v) {
    rs[v] = std::pow(Nm.row(v).dot(Xs.row(v) - X.row(v)), 2);
    rm[v] = std::pow(Nm.row(v).dot(Xm.row(v) - X.row(v)), 2);
  }
  const Eigen::VectorXd rs1 = ring_average(N, rs, 1), rm1 = ring_average(N, rm, 1);
  const Eigen::VectorXd rs5 = ring_average(N, rs1, 4), rm5 = ring_average(N, rm1, 4);
  const double eps = 1e-12 * (rm.mean() + rs.mean()) + std::numeric_limits<double>::min();
  const double unit = mean_edge_length(mesh);
  const double noise = std::max(normal_noise, 1e-3), noise2 = std::pow(noise * unit, 2);
  double whole = 1;
  const Eigen::VectorXi own = components ? Eigen::VectorXi() : connected_components(mesh);
  const Eigen::VectorXd look = component_look(components ? *components : own, N, Ns, Nm, &whole);
  const Eigen::VectorXd as = ring_average(N, ring_angle(N, Ns), 2), am = ring_average(N, ring_angle(N, Nm), 2);
  const double log_whole = std::log(std::clamp(whole, 1e-3, 10.0));
  Eigen::MatrixXd x(n, static_cast<Eigen::Index>(reading_feature_names().size()));
  for (Eigen::Index v = 0; v < n; ++v) {
    const double z5 = std::log((rs5[v] + eps) / (rm5[v] + eps));
    const double lk = std::log(std::clamp(look[v], 1e-3, 10.0));
    const double ln = std::log(noise);
    x(v, 0) = z5;
    x(v, 1) = std::log((rs1[v] + eps) / (rm1[v] + eps));
    x(v, 2) = std::log((rs5[v] + eps) / noise2 + 1e-6);
    x(v, 3) = std::log((rm5[v] + eps) / noise2 + 1e-6);
    x(v, 4) = lk;
    x(v, 5) = log_whole;
    x(v, 6) = std::log((as[v] + 1e-4) / (am[v] + 1e-4));
    x(v, 7) = std::log(am[v] * 180 / M_PI + 0.01);
    x(v, 8) = ln;
    x(v, 9) = z5 * lk;
    x(v, 10) = ln * lk;
    x(v, 11) = rule_threshold(lk) - z5;
  }
  return x;
}

Eigen::VectorXd rule_reading(const Eigen::MatrixXd& x) {
  Eigen::VectorXd sharp(x.rows());
  for (Eigen::Index v = 0; v < x.rows(); ++v) sharp[v] = x(v, 0) < rule_threshold(x(v, 4)) ? 1.0 : 0.0;
  return sharp;
}

Eigen::VectorXd ReadingModel::probability(const Eigen::MatrixXd& features) const {
  if (features.cols() != weights.size())
    throw InvalidInput(fmt::format("reading model: {} features given, the model has {}", features.cols(), weights.size()));
  Eigen::VectorXd p(features.rows());
  for (Eigen::Index i = 0; i < features.rows(); ++i) {
    double t = bias;
    for (Eigen::Index k = 0; k < weights.size(); ++k) t += weights[k] * (features(i, k) - mean[k]) / scale[k];
    p[i] = sigmoid(t);
  }
  return p;
}

void ReadingSamples::append(const ReadingSamples& other) {
  if (features.size() == 0) {
    *this = other;
    return;
  }
  const Eigen::Index n = features.rows(), m = other.features.rows();
  features.conservativeResize(n + m, Eigen::NoChange);
  features.bottomRows(m) = other.features;
  sharp_better.conservativeResize(n + m);
  sharp_better.tail(m) = other.sharp_better;
  weight.conservativeResize(n + m);
  weight.tail(m) = other.weight;
}

ReadingModel train_reading_model(const ReadingSamples& s, const ReadingTrainOptions& options) {
  const Eigen::Index n = s.features.rows(), d = s.features.cols();
  if (n == 0 || d == 0 || s.sharp_better.size() != n || s.weight.size() != n)
    throw InvalidInput("reading model: no samples, or labels and weights that do not match the features");
  const double total = s.weight.sum();
  if (!(total > 0)) throw InvalidInput("reading model: the sample weights sum to zero");
  ReadingModel m;
  // Standardise each feature by its weighted mean and spread, so that one penalty fits all of them.
  m.mean = (s.features.transpose() * s.weight) / total;
  m.scale.resize(d);
  for (Eigen::Index k = 0; k < d; ++k) {
    const double var = (s.weight.array() * (s.features.col(k).array() - m.mean[k]).square()).sum() / total;
    m.scale[k] = var > 1e-24 ? std::sqrt(var) : 1.0;
  }
  Eigen::MatrixXd Z(n, d + 1);
  for (Eigen::Index k = 0; k < d; ++k) Z.col(k) = (s.features.col(k).array() - m.mean[k]) / m.scale[k];
  Z.col(d).setOnes();
  // Newton's method on the weighted log-loss plus l2 / 2 |w|² (the bias not penalised), per unit weight.
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(d + 1);
  for (int it = 0; it < options.iterations; ++it) {
    const Eigen::VectorXd t = Z * beta;
    Eigen::VectorXd g = Eigen::VectorXd::Zero(d + 1);
    Eigen::VectorXd c(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double p = sigmoid(t[i]), w = s.weight[i] / total;
      g += (w * (p - s.sharp_better[i])) * Z.row(i).transpose();
      c[i] = w * p * (1 - p);
    }
    Eigen::MatrixXd H = Z.transpose() * c.asDiagonal() * Z;
    for (Eigen::Index k = 0; k < d; ++k) {
      g[k] += options.l2 * beta[k];
      H(k, k) += options.l2;
    }
    H(d, d) += 1e-12;
    const Eigen::VectorXd step = H.ldlt().solve(g);
    beta -= step;
    if (step.norm() < 1e-10) break;
  }
  m.weights = beta.head(d);
  m.bias = beta[d];
  return m;
}

ReadingScore score_reading_model(const ReadingModel& model, const ReadingSamples& s) {
  const Eigen::VectorXd p = model.probability(s.features);
  ReadingScore r;
  const double total = s.weight.sum();
  if (!(total > 0)) return r;
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    const double y = s.sharp_better[i], q = std::clamp(p[i], 1e-12, 1 - 1e-12);
    r.log_loss -= s.weight[i] * (y * std::log(q) + (1 - y) * std::log(1 - q));
    r.accuracy += s.weight[i] * ((p[i] > 0.5) == (y > 0.5));
  }
  r.log_loss /= total;
  r.accuracy /= total;
  return r;
}

std::string reading_model_source(const ReadingModel& model, const std::string& provenance) {
  std::string out = "// The learned reading's weights (reading_model.h), written by reading_model_source().\n";
  for (size_t start = 0; start < provenance.size();) {
    const size_t end = provenance.find('\n', start);
    out += "// " + provenance.substr(start, end == std::string::npos ? std::string::npos : end - start) + "\n";
    if (end == std::string::npos) break;
    start = end + 1;
  }
  auto list = [](const Eigen::VectorXd& v) {
    std::string s;
    for (Eigen::Index k = 0; k < v.size(); ++k) s += fmt::format("{}{:.17g}", k ? ", " : "", v[k]);
    return s;
  };
  out += fmt::format("constexpr double kReadingMean[] = {{{}}};\n", list(model.mean));
  out += fmt::format("constexpr double kReadingScale[] = {{{}}};\n", list(model.scale));
  out += fmt::format("constexpr double kReadingWeights[] = {{{}}};\n", list(model.weights));
  out += fmt::format("constexpr double kReadingBias = {:.17g};\n", model.bias);
  return out;
}

namespace {
#include "reading_weights.inc"
}  // namespace

const ReadingModel& default_reading_model() {
  static const ReadingModel m = [] {
    ReadingModel r;
    constexpr Eigen::Index d = std::size(kReadingWeights);
    static_assert(std::size(kReadingMean) == d && std::size(kReadingScale) == d);
    r.mean = Eigen::Map<const Eigen::VectorXd>(kReadingMean, d);
    r.scale = Eigen::Map<const Eigen::VectorXd>(kReadingScale, d);
    r.weights = Eigen::Map<const Eigen::VectorXd>(kReadingWeights, d);
    r.bias = kReadingBias;
    if (static_cast<size_t>(d) != reading_feature_names().size())
      throw InvalidInput("reading model: the compiled-in weights do not match the features (retrain: scripts/train_reading.sh)");
    return r;
  }();
  return m;
}

}  // namespace geotex
