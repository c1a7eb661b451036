#pragma once
//! \file linear_solver.h Sparse symmetric positive-definite solves: CHOLMOD's supernodal Cholesky
//! when geotex was built with it, Eigen's SimplicialLDLT otherwise. The symbolic analysis is done
//! once per sparsity pattern; factorize() may then be called again for new values.

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace geotex {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

//! Fill-reducing ordering of a blocked analysis (SpdSolver::analyze with block_size > 1).
enum class BlockOrdering {
  Auto,              //!< minimum degree below 300k vertices, nested dissection above
  MinimumDegree,     //!< AMD on the vertex graph
  NestedDissection,  //!< METIS on the vertex graph (CHOLMOD backend; else minimum degree)
};

class SpdSolver {
 public:
  SpdSolver();
  ~SpdSolver();
  SpdSolver(SpdSolver&&) noexcept;
  SpdSolver& operator=(SpdSolver&&) noexcept;

  //! Symbolic analysis (fill-reducing ordering); reusable for every matrix of the same pattern.
  //! \param block_size for systems whose unknowns are stacked by coordinate, [x; y; z] with
  //! block_size = 3 blocks of #V: the ordering is computed on the #V-vertex graph and each vertex's
  //! unknowns are kept together, which is several times faster to analyze than ordering all
  //! 3#V unknowns and gives supernodes of whole vertices (CHOLMOD backend; ignored otherwise).
  //! \param ordering the vertex graph's ordering (blocked analysis only).
  void analyze(const SparseMatrix& A, int block_size = 1, BlockOrdering ordering = BlockOrdering::Auto);
  //! Numeric factorization. \throw SolverError if A is not positive definite.
  void factorize(const SparseMatrix& A);
  //! analyze() then factorize().
  void compute(const SparseMatrix& A) { analyze(A); factorize(A); }
  //! \return A⁻¹ B for the last factorized A. \throw SolverError if nothing is factorized.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  bool analyzed() const;

  //! "cholmod-supernodal" or "eigen-simplicial-ldlt".
  static const char* backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace geotex
