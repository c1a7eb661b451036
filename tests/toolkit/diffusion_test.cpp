#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "geotex/toolkit/diffusion.h"
#include "geotex/core/error.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/tools/shapes.h"
#include "test_util.h"

using namespace geotex;

TEST(Diffusion, SphereSpectrumIsLTimesLPlusOne) {
  // Laplace–Beltrami on the unit sphere: λ = l(l+1) with multiplicity 2l+1.
  const Mesh s = icosphere(4);
  const LaplaceSpectrum sp = laplace_spectrum(s, 16);
  ASSERT_EQ(sp.values.size(), 16);
  EXPECT_NEAR(sp.values[0], 0.0, 1e-8);
  int i = 1;
  for (int l = 1; l <= 3; ++l)
    for (int k = 0; k < 2 * l + 1; ++k, ++i) EXPECT_NEAR(sp.values[i], l * (l + 1), 0.01 * l * (l + 1)) << i;
  // M-orthonormal eigenvectors that solve C φ = −λ M φ.
  const SparseMatrix C = cotan_matrix(s);
  const Eigen::VectorXd m = mass_diagonal(s);
  const Eigen::MatrixXd G = sp.vectors.transpose() * m.asDiagonal() * sp.vectors;
  EXPECT_LT((G - Eigen::MatrixXd::Identity(16, 16)).cwiseAbs().maxCoeff(), 1e-8);
  for (int j = 0; j < 16; ++j) {
    const Eigen::VectorXd r = C * sp.vectors.col(j) + sp.values[j] * m.cwiseProduct(sp.vectors.col(j));
    EXPECT_LT(r.norm(), 1e-7 * (1 + sp.values[j])) << j;
  }
}

TEST(Diffusion, AdfOfASphereOverWholeBandsIsConstant) {
  // Addition theorem: Σ_m Y_lm(x)² is constant on the sphere, so complete bands give a constant ADF.
  const Mesh s = icosphere(4);
  const Eigen::VectorXd adf = auto_diffusion_function(s, {.t = 0.5, .eigenpairs = 16});
  const double mean = adf.mean();
  EXPECT_LT((adf.array() - mean).abs().maxCoeff() / mean, 0.02);
  // and it equals Σ_{l=1..3} (2l+1)/(4π) exp(−l(l+1) t / 2) for the unit sphere
  double expect = 0;
  for (int l = 1; l <= 3; ++l) expect += (2 * l + 1) / (4 * M_PI) * std::exp(-l * (l + 1) * 0.5 / 2.0);
  EXPECT_NEAR(mean, expect, 0.02 * expect);
}

TEST(Diffusion, AdfPeaksAtProtrusionTips) {
  const TexturedShape sh = make_shape("spiky-sphere", 0);
  const Eigen::VectorXd adf = auto_diffusion_function(sh.textured, {.t = 0.1, .eigenpairs = 120});
  Eigen::VectorXd sorted = adf;
  std::sort(sorted.data(), sorted.data() + sorted.size());
  const double p75 = sorted[static_cast<Eigen::Index>(0.75 * (sorted.size() - 1))];
  int above = 0;
  for (int tip : sh.spike_centres) above += adf[tip] > p75;
  EXPECT_GE(above, static_cast<int>(0.9 * sh.spike_centres.size())) << above << " of " << sh.spike_centres.size();
}

TEST(Diffusion, OutOfRangeEigenpairsAndTimesThrow) {
  const Mesh s = icosphere(1);
  EXPECT_THROW(laplace_spectrum(s, 1), InvalidInput);
  EXPECT_THROW(laplace_spectrum(s, static_cast<int>(s.n_vertices())), InvalidInput);
  EXPECT_THROW(auto_diffusion_function(s, {.t = -1}), InvalidInput);
}

TEST(Diffusion, IsolatedVerticesLeaveTheSpectrumAlone) {
  // Scans come with vertices in no face (the bunny has 1113): each would be a spurious λ = 0 mode.
  const Mesh s = icosphere(2);
  Mesh with = s;
  for (int k = 0; k < 30; ++k) with.add_vertex(Mesh::Point(5.0 + k, 0, 0));
  const LaplaceSpectrum a = laplace_spectrum(s, 12), b = laplace_spectrum(with, 12);
  ASSERT_EQ(b.vectors.rows(), static_cast<Eigen::Index>(with.n_vertices()));
  EXPECT_LT((a.values - b.values).cwiseAbs().maxCoeff(), 1e-8 * (1 + a.values.maxCoeff()));
  EXPECT_EQ(b.vectors.bottomRows(30).cwiseAbs().maxCoeff(), 0.0);
  const Eigen::VectorXd adf = auto_diffusion_function(with, {0.1, 12});
  EXPECT_TRUE(adf.allFinite());
  EXPECT_LT((adf.head(s.n_vertices()) - auto_diffusion_function(s, {0.1, 12})).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Diffusion, MostOfASmallSpectrumComesFromTheDenseSolverAndAgrees) {
  // Asking for more than half of the eigenpairs (e.g. --eigenpairs 1000 on a 642-vertex mesh) takes
  // the dense path (Lanczos with a subspace as large as the matrix did not finish in minutes). Its
  // first eigenvalues are the Lanczos ones, and its vectors solve the same problem, M-orthonormal.
  const Mesh s = icosphere(3);
  const int n = static_cast<int>(s.n_vertices());
  const LaplaceSpectrum few = laplace_spectrum(s, 16), most = laplace_spectrum(s, n - 1);
  ASSERT_EQ(most.values.size(), n - 1);
  EXPECT_LT((most.values.head(16) - few.values).cwiseAbs().maxCoeff(), 1e-8 * few.values.maxCoeff());
  const SparseMatrix C = cotan_matrix(s);
  const Eigen::VectorXd m = mass_diagonal(s);
  const Eigen::MatrixXd G = most.vectors.transpose() * m.asDiagonal() * most.vectors;
  EXPECT_LT((G - Eigen::MatrixXd::Identity(n - 1, n - 1)).cwiseAbs().maxCoeff(), 1e-8);
  for (int j = 0; j < n - 1; j += 37) {
    const Eigen::VectorXd r = C * most.vectors.col(j) + most.values[j] * m.cwiseProduct(most.vectors.col(j));
    EXPECT_LT(r.norm(), 1e-7 * (1 + most.values[j])) << j;
  }
}
