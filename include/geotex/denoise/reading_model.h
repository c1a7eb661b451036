#pragma once
//! \file reading_model.h The learned reading of a surface, per vertex (issue 24).
//!
//! The default denoiser fits two readings of every input: a sharp one (CAD-like: flat faces between creases)
//! and a smooth one (organic: curvature kept). Which one a vertex takes is decided here, from what the two
//! fits leave around it (reading_features()): their residuals against the input along the normals, over
//! one and five rings, against each other and against the noise level; how much of the angle between
//! neighbouring normals the sharp fit keeps, locally and over the vertex's part; the noise level. A logistic
//! model of these (ReadingModel) gives the probability that the sharp fit is nearer the truth.
//!
//! The model is trained (train_reading_model(), by `bash scripts/train_reading.sh`) only on synthetic noise
//! of models the project ships or generates (data/spot.obj and `geotex generate`'s shapes), never on the
//! shared noisy pairs nor the shared clean models, which are the test (bench/denoise.md). Its weights are
//! compiled in (src/denoise/reading_weights.inc, with the command and seed that made them).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"
#include "geotex/denoise/surfel.h"

namespace geotex {

//! The names of the columns of reading_features(), in order.
const std::vector<std::string>& reading_feature_names();

//! \return #V by reading_feature_names().size(): the features of every vertex of \p mesh (input positions
//! \p X) given the sharp fit \p Xs and the smooth fit \p Xm (both #V by 3, the same connectivity), \p N the
//! one-rings, \p normal_noise the noise along the normals in mean edge lengths (the estimate's RMS), \p components
//! the mesh's connected components (connected_components(); computed here when null).
Eigen::MatrixXd reading_features(const Mesh& mesh, const Neighborhoods& N, const MatrixX3d& X, const MatrixX3d& Xs,
                                 const MatrixX3d& Xm, double normal_noise, const Eigen::VectorXi* components = nullptr);

//! The previous release's hand-made rule on the same features: sharp (1) where z5 < t, with t from 0.3 on a
//! part that looks creased (look <= 0.55) to −0.5 on one that looks organic (look >= 0.70), log-linear
//! between (AutoDenoiseOptions::reading = rule). \return #V values, 0 or 1.
Eigen::VectorXd rule_reading(const Eigen::MatrixXd& features);

//! Average a per-vertex quantity with its one-ring's, \p rounds times (Jacobi).
Eigen::VectorXd ring_average(const Neighborhoods& N, Eigen::VectorXd x, int rounds);
//! Sum a per-vertex quantity with its one-ring's, \p rounds times (the neighbourhood grows a ring a round).
Eigen::VectorXd ring_sum(const Neighborhoods& N, Eigen::VectorXd x, int rounds);

//! A logistic model p = 1 / (1 + exp(−(w · (x − mean) / scale + bias))): the probability that the sharp
//! fit is the better one at a vertex of features x.
struct ReadingModel {
  Eigen::VectorXd mean, scale, weights;  //!< one entry per feature
  double bias = 0;
  //! \return #rows probabilities in (0, 1). \throw InvalidInput when the column count is not the model's.
  Eigen::VectorXd probability(const Eigen::MatrixXd& features) const;
};

//! The model compiled into the library (src/denoise/reading_weights.inc).
const ReadingModel& default_reading_model();

//! Training samples: features, the label (1 where the sharp fit is nearer the truth) and a weight (how much
//! the choice matters there).
struct ReadingSamples {
  Eigen::MatrixXd features;
  Eigen::VectorXd sharp_better;
  Eigen::VectorXd weight;
  //! Append \p other's rows.
  void append(const ReadingSamples& other);
};

struct ReadingTrainOptions {
  double l2 = 1e-3;      //!< ridge penalty on the standardised weights, per unit of total sample weight
  int iterations = 30;   //!< Newton steps (the loss is convex: a handful suffice)
};

//! Weighted L2-regularised logistic regression by Newton's method (deterministic: no seed).
//! \throw InvalidInput for empty or inconsistent samples.
ReadingModel train_reading_model(const ReadingSamples& samples, const ReadingTrainOptions& options = {});

//! The weighted mean log-loss of \p model on \p samples, and the weighted share it gets right.
struct ReadingScore {
  double log_loss = 0;
  double accuracy = 0;
};
ReadingScore score_reading_model(const ReadingModel& model, const ReadingSamples& samples);

//! The C++ source of \p model's weights (what src/denoise/reading_weights.inc holds), with \p provenance as
//! its comment.
std::string reading_model_source(const ReadingModel& model, const std::string& provenance);

}  // namespace geotex
