#include "geotex/toolkit/diffusion.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <Spectra/SymEigsShiftSolver.h>

#include "geotex/core/error.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

const OptionTable<DiffusionOptions>& DiffusionOptions::table() {
  using O = DiffusionOptions;
  static const auto t = OptionTable<O>()
      .add("t", &O::t, "diffusion time in units of 1/lambda_1 (small t shows small features)", positive(),
           "Sec. 9.4 (Gebal et al. 2009)")
      .add("eigenpairs", &O::eigenpairs, "number of Laplace eigenpairs summed", between(2, 1000));
  return t;
}

namespace {

// Shift-invert operator of the symmetric standard problem A y = λ y with A = M^{-1/2} K M^{-1/2},
// K = −C: (A − σI)⁻¹ x = M^{1/2} (K − σM)⁻¹ M^{1/2} x, with one Cholesky factor of K − σM.
class ShiftInvertOp {
 public:
  using Scalar = double;
  ShiftInvertOp(const SparseMatrix& K, const Eigen::VectorXd& m) : K_(K), sqrt_m_(m.cwiseSqrt()), m_(m) {}
  Eigen::Index rows() const { return K_.rows(); }
  Eigen::Index cols() const { return K_.cols(); }
  void set_shift(double sigma) {
    SparseMatrix A = K_;
    for (Eigen::Index i = 0; i < A.rows(); ++i) A.coeffRef(i, i) -= sigma * m_[i];
    solver_.compute(A);
  }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, rows());
    Eigen::Map<Eigen::VectorXd> y(y_out, rows());
    const Eigen::VectorXd b = sqrt_m_.cwiseProduct(x);
    y = sqrt_m_.cwiseProduct(solver_.solve(b).col(0));
  }

 private:
  const SparseMatrix& K_;
  Eigen::VectorXd sqrt_m_, m_;
  SpdSolver solver_;
};

// φ = M^{-1/2} y (M-orthonormal), with φ = 0 at the isolated vertices left out of the solve.
LaplaceSpectrum finish_spectrum(LaplaceSpectrum s, const Eigen::MatrixXd& y, const Eigen::VectorXd& m,
                                const std::vector<int>& keep, int n_all) {
  const int n = static_cast<int>(keep.size());
  const Eigen::MatrixXd phi = m.cwiseSqrt().cwiseInverse().asDiagonal() * y;  // φ = M^{-1/2} y, M-orthonormal
  if (n == n_all) {
    s.vectors = phi;
  } else {
    s.vectors = Eigen::MatrixXd::Zero(n_all, phi.cols());
    for (int k = 0; k < n; ++k) s.vectors.row(keep[k]) = phi.row(k);
  }
  return s;
}

}  // namespace

LaplaceSpectrum laplace_spectrum(const Mesh& mesh, int count) {
  require_valid(mesh, "spectrum input");
  const int n_all = static_cast<int>(mesh.n_vertices());
  // Isolated vertices (in no face) carry no Laplacian: each would add a spurious λ = 0 mode that
  // crowds out the real ones. Solve on the others and give isolated vertices φ = 0.
  std::vector<int> keep;
  keep.reserve(n_all);
  for (auto v : mesh.vertices())
    if (!mesh.is_isolated(v)) keep.push_back(v.idx());
  const int n = static_cast<int>(keep.size());
  if (count < 2 || count >= n)
    throw InvalidInput(fmt::format("eigenpair count {} must lie in [2, {})", count, n));
  SparseMatrix K = -cotan_matrix(mesh);
  Eigen::VectorXd m = mass_diagonal(mesh, MassType::Voronoi);
  if (n < n_all) {
    std::vector<int> index(n_all, -1);
    for (int k = 0; k < n; ++k) index[keep[k]] = k;
    std::vector<Triplet> t;
    t.reserve(K.nonZeros());
    for (int c = 0; c < K.outerSize(); ++c)
      for (SparseMatrix::InnerIterator it(K, c); it; ++it)
        if (index[it.row()] >= 0 && index[it.col()] >= 0) t.emplace_back(index[it.row()], index[it.col()], it.value());
    K.resize(n, n);
    K.setFromTriplets(t.begin(), t.end());
    Eigen::VectorXd mk(n);
    for (int k = 0; k < n; ++k) mk[k] = m[keep[k]];
    m = mk;
  }
  LaplaceSpectrum s;
  Eigen::MatrixXd y;  // orthonormal eigenvectors of M^{-1/2} K M^{-1/2}
  if (2 * count > n) {
    // Most of the spectrum of a small mesh: a dense solve (n < 2000 here, as count <= 1000) is both
    // faster and surer than Lanczos with a subspace as large as the matrix.
    const Eigen::VectorXd r = m.cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd A = r.asDiagonal() * Eigen::MatrixXd(K) * r.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(A);
    if (dense.info() != Eigen::Success)
      throw SolverError(fmt::format("Laplace eigenproblem: the dense solver failed for {} eigenpairs", count));
    s.values = dense.eigenvalues().head(count);  // ascending
    y = dense.eigenvectors().leftCols(count);
    return finish_spectrum(std::move(s), y, m, keep, n_all);
  }
  // All λ ≥ 0: a small negative shift makes K − σM positive definite and picks the smallest λ.
  const double sigma = -1e-6 * (K.diagonal().array() / m.array()).mean();
  ShiftInvertOp op(K, m);
  // The Krylov basis: room for multiple eigenvalues (spheres) and for convergence without many
  // restarts, but each Lanczos step orthogonalises against all of it: n × ncv reads, twice or more,
  // so ncv² n per factorisation. On 10^5 vertices that is most of the time (a fan: 300 vectors,
  // converged in one factorisation, 13 s; 160 vectors, three restarts, 8.6 s; issue 30).
  const int ncv = std::min(n, count + std::max(40, 3 * count / 5));
  Spectra::SymEigsShiftSolver<ShiftInvertOp> eigs(op, count, ncv, sigma);
  eigs.init();
  eigs.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10, Spectra::SortRule::SmallestAlge);
  if (eigs.info() != Spectra::CompInfo::Successful)
    throw SolverError(fmt::format("Laplace eigenproblem: Lanczos did not converge for {} eigenpairs", count));
  s.values = eigs.eigenvalues();
  y = eigs.eigenvectors();
  return finish_spectrum(std::move(s), y, m, keep, n_all);
}


Eigen::VectorXd auto_diffusion_function(const LaplaceSpectrum& s, double t) {
  if (!(t > 0)) throw InvalidInput("diffusion time t must be positive");
  const Eigen::Index k = s.values.size();
  if (k == 0) throw InvalidInput("empty spectrum");
  const double tiny = 1e-8 * s.values.cwiseAbs().maxCoeff();
  Eigen::Index first = 0;
  while (first < k && s.values[first] <= tiny) ++first;
  if (first == k) throw InvalidInput("the spectrum holds no non-zero eigenvalue");
  const double lambda1 = s.values[first];
  Eigen::VectorXd adf = Eigen::VectorXd::Zero(s.vectors.rows());
  for (Eigen::Index i = first; i < k; ++i)
    adf += std::exp(-s.values[i] * t / lambda1) * s.vectors.col(i).cwiseAbs2();  // Gębal et al. Eq. (2)
  return adf;
}

Eigen::VectorXd auto_diffusion_function(const Mesh& mesh, const DiffusionOptions& options) {
  check_options(options);
  return auto_diffusion_function(laplace_spectrum(mesh, std::min(options.eigenpairs, vertices_in_faces(mesh) - 1)),
                                 options.t);
}

}  // namespace geotex
