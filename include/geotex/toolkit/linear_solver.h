#pragma once
//! \file linear_solver.h Sparse symmetric positive-definite solves: CHOLMOD's supernodal Cholesky
//! when geotex was built with it, Eigen's SimplicialLDLT otherwise. The symbolic analysis is done
//! once per sparsity pattern; factorize() may then be called again for new values.

#include <memory>
#include <string>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace geotex {

using SparseMatrix = Eigen::SparseMatrix<double>;
using RowSparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using Triplet = Eigen::Triplet<double>;

//! Fill-reducing ordering of a blocked analysis (SpdSolver::analyze with block_size > 1).
enum class BlockOrdering {
  Auto,              //!< minimum degree below 50k vertices, nested dissection above
  MinimumDegree,     //!< AMD on the vertex graph
  NestedDissection,  //!< METIS on the vertex graph (CHOLMOD backend; else minimum degree)
};

//! The Cholesky factor of a system not yet assembled, estimated from its vertex graph (issue 30).
struct FactorEstimate {
  double values = 0;     //!< stored values of the supernodal factor
  double nonzeros = 0;   //!< nonzeros of the factor
  double flops = 0;      //!< floating-point operations of the numeric factorization
  double bytes = 0;      //!< memory of the numeric factorization (values, update block, row indices)
  double cpu_seconds = 0;  //!< flops at the factorization rate measured on a linear edit (one core)
  int sampled_vertices = 0;  //!< 0: the whole graph analysed; else the larger sample it was extrapolated from
};

//! Estimates the factor of a system with \p block_size unknowns per vertex, vertices i and j coupled
//! wherever (R Rᵀ)_ij ≠ 0 (R: #vertices rows, e.g. each vertex's closed ring as a column: R Rᵀ is then the
//! 2-ring; a column for a row that LeastSquaresSolver keeps out of its factor is left out of R), ordered as SpdSolver::analyze orders a blocked system: by CHOLMOD's symbolic analysis of the
//! vertex graph alone, each scalar value becoming a block_size × block_size block. Seconds where the
//! system's assembly and its own analysis take minutes. All zero without CHOLMOD.
FactorEstimate estimate_block_factor(const SparseMatrix& R, int block_size,
                                     BlockOrdering ordering = BlockOrdering::Auto);

//! The same estimate extrapolated from two nested samples of the graph (the first \p sample / 4 and
//! \p sample vertices reached breadth first, component after component): each quantity q grows as
//! q(sample) · (n / sample)^e, e its growth exponent between the two samples (clamped to [1, 2]; nested
//! dissection of a surface mesh: values ~ n log n, flops ~ n^1.5). Seconds at any size; a guide for
//! refusing far too large systems, not an exact figure (a 2.6 M-vertex sphere from 200k: within 10%).
FactorEstimate extrapolate_block_factor(const SparseMatrix& R, int block_size, int sample,
                                        BlockOrdering ordering = BlockOrdering::Auto);

//! Throws OutOfMemory naming \p what and the estimate when the factor estimated by
//! estimate_block_factor() would not fit in the memory left, or would exceed CHOLMOD's 32-bit indices:
//! a mesh too large for a method is refused before its system is assembled.
void require_block_factor_memory(const std::string& what, const SparseMatrix& R, int block_size,
                                 BlockOrdering ordering = BlockOrdering::Auto);

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

//! The normal equations (GᵀG + diag(d)) x = b of a sparse least-squares problem, factored without the
//! dense block that a long row of G puts into GᵀG (the row of a vertex of valence k couples its k
//! neighbours: a k × k block, 8 GB for a fan of 8000). Rows with more than \p dense_row_nnz nonzeros
//! are left out of the factored matrix S = G_sᵀG_s + diag(d) and added back by the Sherman–Morrison–
//! Woodbury identity, (S + UUᵀ)⁻¹ = S⁻¹ − S⁻¹U (I + UᵀS⁻¹U)⁻¹ UᵀS⁻¹, U the long rows' transposes:
//! memory and time stay linear in the nonzeros of G. Without long rows it is a plain Cholesky solve.
//! LeastSquaresSolver's default: rows of G with more nonzeros are left out of its factor (Woodbury).
constexpr int kDenseRowNonzeros = 512;

class LeastSquaresSolver {
 public:
  //! \param G #rows by #unknowns; \param d #unknowns non-negative diagonal; \param block_size as SpdSolver::analyze.
  //! \throw SolverError if GᵀG + diag(d) is singular.
  void compute(RowSparseMatrix G, const Eigen::VectorXd& d, int block_size = 1, int dense_row_nnz = kDenseRowNonzeros);
  void compute(const SparseMatrix& G, const Eigen::VectorXd& d, int block_size = 1,
               int dense_row_nnz = kDenseRowNonzeros) {
    compute(RowSparseMatrix(G), d, block_size, dense_row_nnz);
  }
  //! Factor GᵀG + diag(\p d) for the G of the last compute() and a new diagonal, reusing its analysis.
  void refactor(const Eigen::VectorXd& d);
  //! \return (GᵀG + diag(d))⁻¹ B.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;
  //! Long rows handled by the low-rank update in the last compute().
  Eigen::Index dense_rows() const { return U_.cols(); }

 private:
  SpdSolver base_;
  void factor();  // S = GsᵀGs + diag(d), then the capacitance matrix
  void set_diagonal(double shift);
  RowSparseMatrix G_;         // kept for the refinement step (products only)
  SparseMatrix S_;            // G_sᵀG_s + diag(d), the short rows' normal matrix: its lower triangle
  Eigen::VectorXd gtg_diagonal_;  // G_sᵀG_s's diagonal
  Eigen::VectorXd d_;
  SparseMatrix U_;            // #unknowns by #long rows
  Eigen::MatrixXd Z_;         // S⁻¹ U
  Eigen::MatrixXd capacitance_inverse_;  // (I + Uᵀ S⁻¹ U)⁻¹
  bool regularized_ = false;  // S needed a tiny shift to factor: refine against the true matrix
};

}  // namespace geotex
