#include <cmath>

#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "geotex/core/random.h"
#include "geotex/toolkit/smoothing.h"
#include "test_util.h"

using namespace geotex;

namespace {
double mean_radius(const MatrixX3d& X) { return X.rowwise().norm().mean(); }
}  // namespace

TEST(Smoothing, ImplicitStepOfSphereFollowsMeanCurvatureFlow) {
  // Mean-curvature flow of a sphere: dr/dt = -2/r, so r(T) = sqrt(r0^2 - 4T). Eq. (5.14) builds L on
  // the current surface (linearized backward Euler, Desbrun et al. 1999), where L x = -2 x / r0^2,
  // so one step of length t gives r1 = r0 - 2 t r1 / r0^2, i.e. r1 = r0 / (1 + 2t / r0^2).
  const Mesh m = icosphere(5, 1.0);
  const double h = mean_edge_length(m);
  const double t = 0.05;
  SmoothingOptions o;
  o.lambda = t / (h * h);
  EXPECT_NEAR(mean_radius(smooth(m, o)), 1.0 / (1 + 2 * t), 0.001);
  // Many small steps follow the same recurrence and approach the continuous solution.
  o.steps = 40;
  o.lambda /= o.steps;
  double r = 1.0;
  for (int k = 0; k < o.steps; ++k) r = r / (1 + 2 * (t / o.steps) / (r * r));
  const double got = mean_radius(smooth(m, o));
  EXPECT_NEAR(got, r, 0.001);
  EXPECT_NEAR(got, std::sqrt(1 - 4 * t), 0.005);
}

TEST(Smoothing, SphereStaysRoundAndShrinksUniformly) {
  const Mesh m = icosphere(4, 1.0);
  SmoothingOptions o;
  o.steps = 3;
  const MatrixX3d X = smooth(m, o);
  const Eigen::VectorXd r = X.rowwise().norm();
  EXPECT_LT(r.maxCoeff() - r.minCoeff(), 0.01 * r.mean());
  EXPECT_LT(r.mean(), 1.0);
}

TEST(Smoothing, RescaleKeepsVolumeAndCentroid) {
  Mesh m = icosphere(3, 1.0);
  NoiseOptions n;
  n.sigma = 0.3;
  set_positions(m, add_noise(m, n));
  const double vol = signed_volume(m);
  const Vec3 c = surface_centroid(m);
  SmoothingOptions o;
  o.steps = 5;
  o.rescale = true;
  Mesh out = m;
  set_positions(out, smooth(m, o));
  EXPECT_NEAR(signed_volume(out), vol, 1e-9 * vol);
  EXPECT_LT((surface_centroid(out) - c).norm(), 1e-9);
  // and it smoothed: the normals are closer to a sphere's
  const MatrixX3d N = vertex_normals(out), X = positions(out);
  double dev = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) dev += 1 - N.row(i).dot((X.row(i) - c.transpose()).normalized());
  EXPECT_LT(dev / X.rows(), 0.01);
}

TEST(Smoothing, EveryVariantReducesNoiseOnACube) {
  const Mesh clean = subdivided_cube(12);
  Mesh noisy = clean;
  NoiseOptions n;
  n.sigma = 0.2;
  set_positions(noisy, add_noise(clean, n));
  const double before = compare_meshes(noisy, clean).mean_normal_error_deg;
  for (auto lap : {LaplacianType::Umbrella, LaplacianType::Cotangent})
    for (bool implicit : {true, false}) {
      SmoothingOptions o;
      o.laplacian = lap;
      o.implicit = implicit;
      // Explicit cotangent steps are stable only for λ ≲ 0.05 (in h² units); implicit ones for any λ.
      o.lambda = implicit ? 0.2 : 0.05;
      o.steps = implicit ? 1 : 5;
      Mesh out = noisy;
      set_positions(out, smooth(noisy, o));
      EXPECT_LT(compare_meshes(out, clean).mean_normal_error_deg, before)
          << (lap == LaplacianType::Umbrella ? "umbrella" : "cotan") << (implicit ? " implicit" : " explicit");
    }
}

TEST(Smoothing, ImplicitUmbrellaMatchesDenseSolve) {
  // (I - λL) X' = X solved densely with L from umbrella_laplacian, against the symmetrized factored path.
  const Mesh m = icosphere(2);
  SmoothingOptions o;
  o.laplacian = LaplacianType::Umbrella;
  o.lambda = 2.0;
  const Eigen::MatrixXd L(umbrella_laplacian(m));
  const Eigen::MatrixXd A = Eigen::MatrixXd::Identity(L.rows(), L.cols()) - o.lambda * L;
  const Eigen::MatrixXd expect = A.fullPivLu().solve(Eigen::MatrixXd(positions(m)));
  EXPECT_LT((smooth(m, o) - expect).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Smoothing, BoundaryIsFixedByDefaultAndFlatStaysFlat) {
  Mesh m = plane(10);
  MatrixX3d X = positions(m);
  Rng rng(5);
  for (Eigen::Index i = 0; i < X.rows(); ++i) X(i, 2) = 0.01 * rng.normal();
  for (auto v : m.vertices())
    if (m.is_boundary(v)) X(v.idx(), 2) = 0;
  set_positions(m, X);
  SmoothingOptions o;
  o.steps = 10;
  const MatrixX3d Y = smooth(m, o);
  for (auto v : m.vertices())
    if (m.is_boundary(v)) EXPECT_TRUE(Y.row(v.idx()) == X.row(v.idx()));
  EXPECT_LT(Y.col(2).cwiseAbs().maxCoeff(), X.col(2).cwiseAbs().maxCoeff() / 5);
}

TEST(Smoothing, FrozenWeightsMatchUpdatedForOneStep) {
  const Mesh m = icosphere(3);
  SmoothingOptions a, b;
  b.update_weights = false;
  EXPECT_LT((smooth(m, a) - smooth(m, b)).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(Smoothing, StopToleranceEndsAtTheFirstSmallStepAndMatchesThatManySteps) {
  NoiseOptions no;
  no.sigma = 0.5;
  Mesh m = icosphere(3);
  set_positions(m, add_noise(m, no));
  const double h = mean_edge_length(m);
  for (const LaplacianType type : {LaplacianType::Umbrella, LaplacianType::Cotangent}) {
    SmoothingOptions o;
    o.laplacian = type;
    o.lambda = 0.5;
    o.steps = 40;
    o.stop_tolerance = 0.05;
    int calls = 0;
    o.progress = [&](double, std::string_view) { ++calls; };
    const MatrixX3d stopped = smooth(m, o);
    ASSERT_GT(calls, 1);
    ASSERT_LT(calls, o.steps);  // it stopped early...
    SmoothingOptions fixed = o;
    fixed.stop_tolerance = 0;
    fixed.progress = nullptr;
    fixed.steps = calls;  // ...after exactly `calls` steps
    EXPECT_LT((smooth(m, fixed) - stopped).cwiseAbs().maxCoeff(), 1e-12);
    fixed.steps = calls - 1;  // and the step before moved more than the tolerance
    const MatrixX3d before = smooth(m, fixed);
    EXPECT_LT((stopped - before).rowwise().norm().maxCoeff(), o.stop_tolerance * h);
    fixed.steps = calls - 2;
    EXPECT_GE((before - smooth(m, fixed)).rowwise().norm().maxCoeff(), o.stop_tolerance * h);
  }
}

TEST(Smoothing, BadOptionsAreRejected) {
  const Mesh m = icosphere(1);
  SmoothingOptions o;
  o.lambda = -1;
  EXPECT_THROW(smooth(m, o), InvalidInput);
  o.lambda = 1;
  o.steps = -2;
  EXPECT_THROW(smooth(m, o), InvalidInput);
  EXPECT_THROW(smooth(Mesh(), {}), InvalidInput);
}

TEST(Smoothing, ExplicitBlowUpIsReported) {
  Mesh m = icosphere(3);
  set_positions(m, add_noise(m, {}));
  // Explicit umbrella steps amplify the highest frequencies by |1 - 2λ| per step: λ = 3 diverges.
  SmoothingOptions o;
  o.laplacian = LaplacianType::Umbrella;
  o.implicit = false;
  o.lambda = 3;
  o.steps = 1000;
  EXPECT_THROW(smooth(m, o), SolverError);
}

// Parts at very different scales (issue 30): a unit sphere ×10^6 beside one ×10^-6, inside the promised
// coordinate range. The cotangent step is taken per part (λ times its own squared edge length), so each
// part is smoothed exactly as it would be alone; one step length for the whole mesh made the small part's
// system singular ("sparse Cholesky failed").
TEST(Smoothing, PartsAtDifferentScalesAreEachSmoothedAsAlone) {
  const Mesh s = icosphere(3);
  const MatrixX3d V = positions(s);
  const MatrixX3i F = faces(s);
  const MatrixX3d big = (1e6 * V).rowwise() + Eigen::RowVector3d(5e6, 0, 0), small = 1e-6 * V;
  MatrixX3d V2(2 * V.rows(), 3);
  V2 << big, small;
  MatrixX3i F2(2 * F.rows(), 3);
  F2 << F, F.array() + static_cast<int>(V.rows());
  for (LaplacianType lap : {LaplacianType::Cotangent, LaplacianType::Umbrella}) {
    SmoothingOptions o;
    o.steps = 3;
    o.laplacian = lap;
    o.rescale = false;
    const MatrixX3d X = smooth(make_mesh(V2, F2), o);
    const MatrixX3d a = smooth(make_mesh(big, F), o), b = smooth(make_mesh(small, F), o);
    EXPECT_LT((X.topRows(V.rows()) - a).cwiseAbs().maxCoeff(), 1e-9 * 1e6);
    EXPECT_LT((X.bottomRows(V.rows()) - b).cwiseAbs().maxCoeff(), 1e-9 * 1e-6);
    EXPECT_GT((b - small).cwiseAbs().maxCoeff(), 1e-3 * 1e-6) << "the small part moved (was smoothed)";
  }
}
