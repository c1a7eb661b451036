// SpdSolver: plain and coordinate-blocked analysis solve the same systems.

#include <cstdlib>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "geotex/core/error.h"
#include "geotex/toolkit/laplace.h"
#include "geotex/toolkit/linear_solver.h"
#include "geotex/core/random.h"
#include "geotex/tools/shapes.h"

using namespace geotex;

namespace {

// A 3#V × 3#V SPD system stacked [x; y; z]: the cotangent Laplacian on each coordinate plus a
// random SPD 3×3 block per vertex coupling its x, y and z (like resize's normal terms).
SparseMatrix stacked_system(const Mesh& mesh, uint64_t seed) {
  const SparseMatrix L = cotan_matrix(mesh);
  const int n = static_cast<int>(L.rows());
  Rng rng(seed);
  std::vector<Triplet> t;
  for (int c = 0; c < n; ++c)
    for (SparseMatrix::InnerIterator it(L, c); it; ++it)
      for (int d = 0; d < 3; ++d) t.emplace_back(d * n + it.row(), d * n + c, -it.value());
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix3d B;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) B(a, b) = rng.normal();
    const Eigen::Matrix3d S = B * B.transpose() + 0.1 * Eigen::Matrix3d::Identity();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) t.emplace_back(a * n + i, b * n + i, S(a, b));
  }
  SparseMatrix A(3 * n, 3 * n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

}  // namespace

TEST(SpdSolver, BlockedAnalysisSolvesTheSameSystem) {
  const Mesh mesh = icosphere(3);
  const SparseMatrix A = stacked_system(mesh, 7);
  Rng rng(3);
  Eigen::MatrixXd B(A.rows(), 2);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = rng.normal();
  SpdSolver plain, blocked;
  plain.compute(A);
  blocked.analyze(A, 3);
  blocked.factorize(A);
  const Eigen::MatrixXd X1 = plain.solve(B), X3 = blocked.solve(B);
  EXPECT_LT((A * X3 - B).norm(), 1e-9 * B.norm());
  EXPECT_LT((X3 - X1).norm(), 1e-9 * X1.norm());
  // New values on the same pattern reuse the blocked analysis.
  const SparseMatrix A2 = stacked_system(mesh, 8);
  blocked.factorize(A2);
  EXPECT_LT((A2 * blocked.solve(B) - B).norm(), 1e-9 * B.norm());
}

TEST(SpdSolver, EveryBlockOrderingSolvesTheSameSystem) {
  const Mesh mesh = icosphere(3);
  const SparseMatrix A = stacked_system(mesh, 5);
  Rng rng(4);
  Eigen::VectorXd b(A.rows());
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = rng.normal();
  SpdSolver plain;
  plain.compute(A);
  const Eigen::VectorXd x = plain.solve(b);
  for (const BlockOrdering o : {BlockOrdering::MinimumDegree, BlockOrdering::NestedDissection}) {
    SpdSolver s;
    s.analyze(A, 3, o);
    s.factorize(A);
    EXPECT_LT((s.solve(b) - x).norm(), 1e-9 * x.norm());
  }
}

TEST(SpdSolver, BlockSizeMustDivideTheUnknowns) {
  const SparseMatrix A = stacked_system(icosphere(1), 1);
  SpdSolver s;
  EXPECT_THROW(s.analyze(A, 5), SolverError);
  EXPECT_THROW(s.analyze(A, 0), SolverError);
}

TEST(LeastSquaresSolver, LongRowsByWoodburyMatchTheDenseNormalEquations) {
  // A sparse G with a few long rows (a high-valence vertex couples all its neighbours), and a diagonal
  // that leaves one unknown constrained only by the long rows (the base matrix is singular then).
  const int n = 300;
  Rng rng(7);
  std::vector<Triplet> t;
  int row = 0;
  for (int i = 0; i + 1 < n - 1; ++i, ++row) {  // a chain of differences over unknowns 0..n-2
    t.emplace_back(row, i, 1.0);
    t.emplace_back(row, i + 1, -1.0);
  }
  for (int k = 0; k < 3; ++k, ++row)  // three long rows, each over every unknown
    for (int j = 0; j < n; ++j) t.emplace_back(row, j, rng.normal());
  SparseMatrix G(row, n);
  G.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  d[0] = 2.0;  // pins the chain
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 2);
  const Eigen::MatrixXd A = Eigen::MatrixXd(G).transpose() * Eigen::MatrixXd(G) + Eigen::MatrixXd(d.asDiagonal());
  const Eigen::MatrixXd reference = A.ldlt().solve(B);
  for (int dense_row_nnz : {1000, 100}) {  // all rows factored, or the three long ones by the update
    LeastSquaresSolver s;
    s.compute(G, d, 1, dense_row_nnz);
    EXPECT_EQ(s.dense_rows(), dense_row_nnz == 100 ? 3 : 0);
    const Eigen::MatrixXd X = s.solve(B);
    EXPECT_LT((X - reference).norm(), 1e-7 * reference.norm()) << dense_row_nnz;
  }
}

TEST(LeastSquaresSolver, FanBiLaplacianWithTinyWeightsAfterRefactorMatchesDenseSolve) {
  // The base-shape fit's system (texture/base_shape.cpp) on a fan of 600 triangles: G = D^{-1/2} K, the
  // hub's row long (left to the update), weights down to 1e-8 (protrusions); refactor() with new
  // weights reuses the analysis and must give the new system's solution.
  const int k = 600, n = k + 1;
  std::vector<Triplet> t;
  auto edge = [&](int i, int j) {
    t.emplace_back(i, j, -1.0);
    t.emplace_back(j, i, -1.0);
    t.emplace_back(i, i, 1.0);
    t.emplace_back(j, j, 1.0);
  };
  for (int i = 0; i < k; ++i) {
    edge(0, 1 + i);
    edge(1 + i, 1 + (i + 1) % k);
  }
  SparseMatrix K(n, n);
  K.setFromTriplets(t.begin(), t.end());  // D − A
  const Eigen::VectorXd deg = K.diagonal();
  const SparseMatrix G = (50.0 / deg.array().sqrt()).matrix().asDiagonal() * K;
  Rng rng(3);
  Eigen::VectorXd w1 = Eigen::VectorXd::Ones(n), w2(n);
  for (int i = 0; i < n; ++i) w2[i] = i % 7 == 0 ? 1e-8 : rng.uniform();
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 3);
  LeastSquaresSolver s;
  s.compute(G, w1);
  EXPECT_EQ(s.dense_rows(), 1);
  for (int pass = 0; pass < 2; ++pass) {
    const Eigen::VectorXd& w = pass == 0 ? w1 : w2;
    if (pass == 1) s.refactor(w);
    const Eigen::MatrixXd A = Eigen::MatrixXd(G).transpose() * Eigen::MatrixXd(G) + Eigen::MatrixXd(w.asDiagonal());
    const Eigen::MatrixXd X = s.solve(B);
    EXPECT_LT((A * X - B).norm(), 1e-7 * B.norm());
  }
}

// Issue 33: an exactly singular matrix is refused whatever rounding does to its last pivot (a
// factorization may fail, or "succeed" with a pivot of round-off size: both are a SolverError).
TEST(SpdSolver, NumericallySingularMatrixIsRefusedOnEveryKernel) {
  for (int n : {4, 50, 2000}) {
    // The path graph's Laplacian (rows sum to zero): singular, with the constants as null space.
    std::vector<Triplet> t;
    for (int i = 0; i + 1 < n; ++i) {
      t.emplace_back(i, i, 1.0);
      t.emplace_back(i + 1, i + 1, 1.0);
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
    SparseMatrix A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    SpdSolver s;
    EXPECT_THROW(s.compute(A), SolverError) << n;
    // Pinned at one end it is SPD (its smallest pivot relative to the diagonal is ~1/n, far above the
    // threshold) and solves.
    A.coeffRef(0, 0) += 1.0;
    ASSERT_NO_THROW(s.compute(A)) << n;
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
    EXPECT_LT((A * s.solve(b) - b).norm(), 1e-8 * n) << n;
  }
}

TEST(FactorEstimate, APathOfBlocksHasTheFactorOfItsBlockTridiagonalSystem) {
  // R lower bidiagonal: R Rᵀ is a path, whose Cholesky factor has no fill. Its 3 × 3-blocked system is
  // block tridiagonal: 6 nonzeros in each diagonal block's lower half and 9 in each off-diagonal block,
  // 15 n − 9 in all; 2 n − 1 unblocked.
  if (std::string(SpdSolver::backend()) != "cholmod-supernodal") GTEST_SKIP() << "the estimate is CHOLMOD's analysis";
  for (int n : {1, 2, 50, 1000}) {
    std::vector<Triplet> t;
    for (int i = 0; i < n; ++i) {
      t.emplace_back(i, i, 1.0);
      if (i > 0) t.emplace_back(i, i - 1, 1.0);
    }
    SparseMatrix R(n, n);
    R.setFromTriplets(t.begin(), t.end());
    // Minimum degree finds the no-fill order; nested dissection's separators fill (more, never less).
    for (BlockOrdering o : {BlockOrdering::Auto, BlockOrdering::MinimumDegree, BlockOrdering::NestedDissection}) {
      const FactorEstimate e1 = estimate_block_factor(R, 1, o), e = estimate_block_factor(R, 3, o);
      if (o != BlockOrdering::NestedDissection) {
        EXPECT_DOUBLE_EQ(e1.nonzeros, 2.0 * n - 1) << n;
        EXPECT_DOUBLE_EQ(e.nonzeros, 15.0 * n - 9) << n;
      }
      EXPECT_GE(e1.nonzeros, 2.0 * n - 1) << n;
      EXPECT_GT(e.flops, e1.flops) << n;
      EXPECT_GE(e.values, e.nonzeros) << n;  // supernodes store whole blocks
      EXPECT_GE(e.bytes, 8 * e.values) << n;
    }
  }
}

TEST(FactorEstimate, AGraphsFactorTooLargeForTheMemoryLeftIsRefusedByName) {
  if (std::string(SpdSolver::backend()) != "cholmod-supernodal") GTEST_SKIP() << "the estimate is CHOLMOD's analysis";
  SparseMatrix R(2000, 2000);  // the complete graph: a dense factor of 2000 × 2000 blocks of 3 × 3
  {
    std::vector<Triplet> t;
    for (int i = 1; i < 2000; ++i) t.emplace_back(i, 0, 1.0);  // R Rᵀ: every pair through column 0
    for (int i = 0; i < 2000; ++i) t.emplace_back(i, i, 1.0);
    R.setFromTriplets(t.begin(), t.end());
  }
  ::setenv("GEOTEX_MAX_MEMORY", "1M", 1);
  std::string what;
  try {
    require_block_factor_memory("a test method", R, 3);
  } catch (const OutOfMemory& e) {
    what = e.what();
  }
  ::unsetenv("GEOTEX_MAX_MEMORY");
  EXPECT_NE(what.find("a test method: factoring its 6000 x 6000 system"), std::string::npos) << what;
  EXPECT_NE(what.find("estimated from its 2000-vertex graph"), std::string::npos) << what;
  EXPECT_NO_THROW(require_block_factor_memory("a test method", R, 3));  // 144 MB without the cap
}

// Closed 1-rings of a mesh as the columns of a pattern matrix (R Rᵀ: the 2-ring), as the linear edit builds it.
SparseMatrix ring_pattern(const Mesh& mesh) {
  std::vector<Triplet> t;
  for (auto v : mesh.vertices()) {
    t.emplace_back(v.idx(), v.idx(), 1.0);
    for (auto w : mesh.vv_range(v)) t.emplace_back(w.idx(), v.idx(), 1.0);
  }
  SparseMatrix R(mesh.n_vertices(), mesh.n_vertices());
  R.setFromTriplets(t.begin(), t.end());
  return R;
}

TEST(FactorEstimate, ExtrapolatedFromSamplesItIsNearTheWholeGraphsAnalysis) {
  // A 41k-vertex sphere's 2-ring, estimated from breadth-first samples of 2.5k and 10k vertices (a 4×
  // extrapolation), against the analysis of the whole graph; and disjoint triangles, whose factor is
  // exactly linear in their number: the growth exponent is 1 and the extrapolation exact.
  if (std::string(SpdSolver::backend()) != "cholmod-supernodal") GTEST_SKIP() << "the estimate is CHOLMOD's analysis";
  const SparseMatrix R = ring_pattern(icosphere(6));
  const BlockOrdering nd = BlockOrdering::NestedDissection;  // the ordering of the graphs sampled in use
  const FactorEstimate whole = estimate_block_factor(R, 3, nd), guess = extrapolate_block_factor(R, 3, 10000, nd);
  EXPECT_EQ(whole.sampled_vertices, 0);
  EXPECT_EQ(guess.sampled_vertices, 10000);
  EXPECT_GT(guess.values, 0.7 * whole.values);
  EXPECT_LT(guess.values, 1.4 * whole.values);
  EXPECT_GT(guess.flops, 0.5 * whole.flops);
  EXPECT_LT(guess.flops, 2.0 * whole.flops);
  EXPECT_GT(guess.bytes, 0.7 * whole.bytes);
  EXPECT_LT(guess.bytes, 1.4 * whole.bytes);

  const int triangles = 20000;
  std::vector<Triplet> t;
  for (int f = 0; f < triangles; ++f)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) t.emplace_back(3 * f + a, 3 * f + b, 1.0);
  SparseMatrix soup(3 * triangles, 3 * triangles);
  soup.setFromTriplets(t.begin(), t.end());
  const FactorEstimate s_whole = estimate_block_factor(soup, 3), s_guess = extrapolate_block_factor(soup, 3, 6000);
  EXPECT_NEAR(s_guess.nonzeros, s_whole.nonzeros, 1e-6 * s_whole.nonzeros);
  EXPECT_NEAR(s_guess.flops, s_whole.flops, 1e-6 * s_whole.flops);
  // A sample as large as the graph is the whole graph's analysis.
  EXPECT_EQ(extrapolate_block_factor(soup, 3, 3 * triangles).sampled_vertices, 0);
}

TEST(SpdSolver, AFactorBeyondTheMemoryLeftIsRefusedByItsAnalysis) {
  // The symbolic analysis knows the factor's size (issue 30): with no memory left beside the process's
  // resident set (GEOTEX_MAX_MEMORY below it), the analysis refuses with the estimate; without the cap
  // the same system factors.
  const SparseMatrix A = stacked_system(icosphere(2), 5);
  ::setenv("GEOTEX_MAX_MEMORY", "1", 1);
  SpdSolver capped;
  std::string what;
  try {
    capped.analyze(A);
  } catch (const OutOfMemory& e) {
    what = e.what();
  }
  ::unsetenv("GEOTEX_MAX_MEMORY");
  if (std::string(SpdSolver::backend()) != "cholmod-supernodal") GTEST_SKIP() << "the estimate is CHOLMOD's analysis";
  EXPECT_NE(what.find(fmt::format("factoring a {} x {} system", A.rows(), A.rows())), std::string::npos) << what;
  EXPECT_NE(what.find("needs about"), std::string::npos) << what;
  SpdSolver free;
  free.compute(A);
  EXPECT_TRUE(free.solve(Eigen::VectorXd::Ones(A.rows())).allFinite());
}
