// Step 6a of the default denoiser: a white change is kept, a coherent one beyond the noise given back.

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "geotex/core/geometry.h"
#include "geotex/core/io.h"
#include "geotex/denoise/auto_denoise.h"
#include "geotex/denoise/coherent_change.h"
#include "geotex/tools/metrics.h"
#include "geotex/tools/noise.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

namespace {

// Changes along the normals of \p mesh: white (independent Gaussian, standard deviation \p s) or coherent
// (a smooth wave of amplitude \p s over the sphere, several rings wide).
MatrixX3d normal_change(const Mesh& mesh, double s, bool white) {
  const MatrixX3d X = positions(mesh), N = vertex_normals(mesh);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> gauss(0.0, s);
  MatrixX3d D(X.rows(), 3);
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    D.row(v) = N.row(v) * (white ? gauss(rng) : s * std::sin(3 * X(v, 0)) * std::cos(2 * X(v, 1)));
  return D;
}

}  // namespace

TEST(CoherentChange, AWhiteChangeIsKeptACoherentOneGivenBack) {
  const Mesh sphere = icosphere(4);
  const Neighborhoods N = one_ring_neighborhoods(sphere);
  const MatrixX3d normals = vertex_normals(sphere);
  const double s = 0.1 * mean_edge_length(sphere);
  // The noise the change removes is as large as the change itself: a white change is all noise.
  const Eigen::VectorXd white = coherent_change_gain(N, normals, normal_change(sphere, s, true), s * s);
  EXPECT_GT(white.mean(), 0.95);
  // A smooth change larger than the noise is shape, not noise: the more of it, the more is given back.
  const Eigen::VectorXd smooth3 = coherent_change_gain(N, normals, normal_change(sphere, 3 * s, false), s * s);
  const Eigen::VectorXd smooth10 = coherent_change_gain(N, normals, normal_change(sphere, 10 * s, false), s * s);
  EXPECT_LT(smooth3.mean(), 0.8);
  EXPECT_LT(smooth10.mean(), 0.5 * smooth3.mean());
  EXPECT_LT(smooth10.mean(), 0.25);
  // Weight 0 keeps every change; no noise at all gives a coherent change back whole.
  CoherentChangeOptions off;
  off.weight = 0;
  EXPECT_EQ(coherent_change_gain(N, normals, normal_change(sphere, 3 * s, false), s * s, off).minCoeff(), 1.0);
  EXPECT_LT(coherent_change_gain(N, normals, normal_change(sphere, 3 * s, false), 0.0).maxCoeff(), 1e-12);
  EXPECT_THROW(coherent_change_gain(N, normals.topRows(10), normal_change(sphere, s, true), s * s), InvalidInput);
}

TEST(CoherentChange, ACoarseCleanModelIsLeftNearerItself) {
  GEOTEX_REQUIRE_DATA();
  // The cow (2,904 vertices, facets the size of its features): its own roughness read as noise (σ 0.09, the
  // estimate before misfit_growth.h told its facets from noise), and the smooth reading smooths its facets away.
  // Step 6a gives that coherent change back.
  const Mesh cow = read_mesh(test::data_dir() / "cow.obj");
  AutoDenoiseOptions on, off;
  on.sigma = off.sigma = 0.09;
  off.coherence_weight = 0;
  const AutoDenoiseResult before = auto_denoise(cow, off), after = auto_denoise(cow, on);
  const auto error = [&](const MatrixX3d& X) {
    Mesh out = cow;
    set_positions(out, X);
    return compare_meshes(out, cow).mean_normal_error_deg;
  };
  EXPECT_GT(error(before.positions), 5.0) << "the cow is damaged without step 6a (else the test cannot fail)";
  EXPECT_LT(error(after.positions), 0.8 * error(before.positions));
  EXPECT_LT(after.change_kept_share, 0.9);
  EXPECT_EQ(after.change_kept.size(), static_cast<Eigen::Index>(cow.n_faces()));
  EXPECT_EQ(before.change_kept_share, 1.0);
  // With the noise estimated, the clean cow's facets are not read as noise at all: it is left as it is.
  EXPECT_LT(error(auto_denoise(cow).positions), 0.5 * error(after.positions));
  // A dense noisy sphere's change is noise: nearly all of it is kept.
  NoiseOptions n;
  n.sigma = 0.3;
  Mesh noisy = icosphere(4);
  set_positions(noisy, add_noise(noisy, n));
  EXPECT_GT(auto_denoise(noisy).change_kept_share, 0.9);
}
