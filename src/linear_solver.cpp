#include "geotex/linear_solver.h"

#include <fmt/format.h>
#include <Eigen/SparseCholesky>
#ifdef GEOTEX_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

#include "geotex/error.h"

namespace geotex {

struct SpdSolver::Impl {
#ifdef GEOTEX_HAVE_CHOLMOD
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> chol;
#else
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> chol;
#endif
  bool analyzed = false;
  bool factorized = false;
  Eigen::Index n = 0;
};

SpdSolver::SpdSolver() : impl_(std::make_unique<Impl>()) {}
SpdSolver::~SpdSolver() = default;
SpdSolver::SpdSolver(SpdSolver&&) noexcept = default;
SpdSolver& SpdSolver::operator=(SpdSolver&&) noexcept = default;

void SpdSolver::analyze(const SparseMatrix& A) {
  if (A.rows() != A.cols()) throw SolverError("SpdSolver: matrix is not square");
  impl_->chol.analyzePattern(A);
  impl_->analyzed = true;
  impl_->factorized = false;
  impl_->n = A.rows();
}

void SpdSolver::factorize(const SparseMatrix& A) {
  if (!impl_->analyzed || A.rows() != impl_->n) analyze(A);
  impl_->chol.factorize(A);
  if (impl_->chol.info() != Eigen::Success)
    throw SolverError(fmt::format("sparse Cholesky failed on a {}x{} system (not positive definite?)",
                                  A.rows(), A.cols()));
  impl_->factorized = true;
}

Eigen::MatrixXd SpdSolver::solve(const Eigen::MatrixXd& B) const {
  if (!impl_->factorized) throw SolverError("SpdSolver: solve() before factorize()");
  if (B.rows() != impl_->n) throw SolverError("SpdSolver: right-hand side has the wrong size");
  Eigen::MatrixXd X = impl_->chol.solve(B);
  if (impl_->chol.info() != Eigen::Success || !X.allFinite())
    throw SolverError("sparse solve failed (non-finite result)");
  return X;
}

bool SpdSolver::analyzed() const { return impl_->analyzed; }

const char* SpdSolver::backend() {
#ifdef GEOTEX_HAVE_CHOLMOD
  return "cholmod-supernodal";
#else
  return "eigen-simplicial-ldlt";
#endif
}

}  // namespace geotex
