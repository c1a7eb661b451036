// The learned reading (denoise/reading_model.h): the logistic model learns a known rule, a tiny model trained
// on noisy generated shapes learns to tell creased from smooth on noise it was not trained on, the compiled-in
// model is what its source says, and the hand-made rule is still reachable.

#include <cmath>
#include <random>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/reading_model.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

Mesh noisy(const Mesh& clean, double sigma, uint64_t seed) {
  NoiseOptions o;
  o.sigma = sigma;
  o.seed = seed;
  Mesh m = clean;
  set_positions(m, add_noise(clean, o));
  return m;
}

double mean_probability(const ReadingModel& model, const ReadingSamples& s) {
  return model.probability(s.features).mean();
}

}  // namespace

TEST(ReadingModel, LogisticRegressionRecoversALinearRuleAndBeatsAConstant) {
  // Labels from a known linear rule with 5% flipped: the fit must reach the rule's accuracy (0.95) and a
  // lower log-loss than the best constant predictor.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0, 1);
  std::uniform_real_distribution<double> u(0, 1);
  ReadingSamples s;
  const int n = 4000, d = 3;
  s.features.resize(n, d);
  s.sharp_better.resize(n);
  s.weight.setOnes(n);
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < d; ++k) s.features(i, k) = 3 + 2 * g(rng);
    const bool y = 2 * s.features(i, 0) - s.features(i, 1) > 3;
    s.sharp_better[i] = (u(rng) < 0.05 ? !y : y) ? 1.0 : 0.0;
  }
  const ReadingModel m = train_reading_model(s);
  const ReadingScore score = score_reading_model(m, s);
  EXPECT_GT(score.accuracy, 0.93);
  const double p = s.sharp_better.mean();
  const double constant_loss = -(p * std::log(p) + (1 - p) * std::log(1 - p));
  EXPECT_LT(score.log_loss, 0.5 * constant_loss);
  // The direction of the rule: the weight of feature 0 (in its own units) is about -2 times feature 1's,
  // and feature 2 plays no part.
  const double w0 = m.weights[0] / m.scale[0], w1 = m.weights[1] / m.scale[1], w2 = m.weights[2] / m.scale[2];
  EXPECT_NEAR(w0 / w1, -2.0, 0.4);
  EXPECT_LT(std::abs(w2), 0.1 * std::abs(w1));
}

TEST(ReadingModel, ATinyModelTrainedOnNoisyShapesTellsACubeFromABlobOnNewNoise) {
  // Train on a cube (creased) and a sphere (smooth) at two noise levels; test on other draws at a third.
  const Mesh cube = subdivided_cube(10), sphere = icosphere(3, 1.0);
  ReadingSamples train;
  for (const double sigma : {0.2, 0.5}) {
    train.append(reading_samples(noisy(cube, sigma, 1), positions(cube)));
    train.append(reading_samples(noisy(sphere, sigma, 2), positions(sphere)));
  }
  const ReadingModel m = train_reading_model(train);
  const ReadingScore score = score_reading_model(m, train);
  EXPECT_GT(score.accuracy, 0.75);
  const ReadingSamples cube_test = reading_samples(noisy(cube, 0.35, 7), positions(cube));
  const ReadingSamples sphere_test = reading_samples(noisy(sphere, 0.35, 8), positions(sphere));
  // Where it matters, the truth says sharp on the cube and smooth on the sphere (checks the labels) ...
  EXPECT_GT(cube_test.sharp_better.dot(cube_test.weight) / cube_test.weight.sum(), 0.6);
  EXPECT_LT(sphere_test.sharp_better.dot(sphere_test.weight) / sphere_test.weight.sum(), 0.4);
  // ... and the model, on noise it has not seen, agrees.
  EXPECT_GT(mean_probability(m, cube_test), 0.6);
  EXPECT_LT(mean_probability(m, sphere_test), 0.4);
  EXPECT_GT(score_reading_model(m, cube_test).accuracy, 0.7);
  EXPECT_GT(score_reading_model(m, sphere_test).accuracy, 0.7);
}

TEST(ReadingModel, TheCompiledModelMatchesTheFeaturesAndItsFormula) {
  const ReadingModel& m = default_reading_model();
  ASSERT_EQ(static_cast<size_t>(m.weights.size()), reading_feature_names().size());
  Eigen::MatrixXd x = Eigen::MatrixXd::Random(5, m.weights.size());
  const Eigen::VectorXd p = m.probability(x);
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    double t = m.bias;
    for (Eigen::Index k = 0; k < m.weights.size(); ++k) t += m.weights[k] * (x(i, k) - m.mean[k]) / m.scale[k];
    EXPECT_NEAR(p[i], 1 / (1 + std::exp(-t)), 1e-12);
  }
  EXPECT_THROW(m.probability(Eigen::MatrixXd::Zero(2, m.weights.size() + 1)), InvalidInput);
  // Its source holds every weight to full precision.
  const std::string src = reading_model_source(m, "test\nprovenance");
  EXPECT_NE(src.find("// test\n// provenance\n"), std::string::npos);
  EXPECT_NE(src.find(fmt::format("kReadingBias = {:.17g};", m.bias)), std::string::npos);
}

TEST(ReadingModel, TheHandMadeRuleIsReachableAndBothReadTheCubeAsCreased) {
  const Mesh cube = subdivided_cube(12);
  const Mesh in = noisy(cube, 0.3, 3);
  AutoDenoiseOptions rule;
  rule.reading = ReadingRule::Rule;
  const AutoDenoiseResult a = auto_denoise(in), b = auto_denoise(in, rule);
  EXPECT_GT(a.creased_share, 0.8);
  EXPECT_GT(b.creased_share, 0.8);
  bool said = false;
  for (const auto& c : b.choices) said |= c.find("hand-made rule") != std::string::npos;
  EXPECT_TRUE(said);
  // The rule of the features is the previous release's threshold: z5 < 0.3 on a creased-looking part.
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(2, reading_feature_names().size());
  x(0, 4) = x(1, 4) = std::log(0.3);
  x(0, 0) = 0.29;
  x(1, 0) = 0.31;
  const Eigen::VectorXd r = rule_reading(x);
  EXPECT_EQ(r[0], 1.0);
  EXPECT_EQ(r[1], 0.0);
}

TEST(ReadingModel, SamplesRefuseMismatchedTruthAndNoiselessInput) {
  const Mesh cube = subdivided_cube(6);
  EXPECT_THROW(reading_samples(noisy(cube, 0.3, 1), MatrixX3d::Zero(3, 3)), InvalidInput);
  AutoDenoiseOptions noiseless;
  noiseless.sigma = 0.0;
  EXPECT_THROW(reading_samples(cube, positions(cube), noiseless), InvalidInput);
  ReadingSamples empty;
  EXPECT_THROW(train_reading_model(empty), InvalidInput);
}
