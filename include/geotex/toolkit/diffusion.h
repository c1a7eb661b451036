#pragma once
//! \file diffusion.h Spectrum of the cotangent Laplacian and the auto diffusion function (ADF) of
//! Gębal, Bærentzen, Aanæs and Larsen, "Shape analysis using the auto diffusion function" (SGP 2009),
//! used for feature maps in thesis ch. 9 (Fig. 9.5).
//!
//! The generalised eigenproblem is C φ = −λ M φ with the cotangent matrix C (laplace.h) and the
//! Voronoi mass matrix M: λ_0 = 0 ≤ λ_1 ≤ …, eigenvectors M-orthonormal (φ_iᵀ M φ_j = δ_ij).
//! ADF_t(x) = Σ_{i≥1} exp(−λ_i t / λ_1) φ_i(x)², summed over the computed eigenpairs.

#include "geotex/toolkit/laplace.h"
#include "geotex/core/mesh.h"

namespace geotex {

struct LaplaceSpectrum {
  Eigen::VectorXd values;   //!< k eigenvalues λ, ascending (λ_0 ≈ 0 per connected component)
  Eigen::MatrixXd vectors;  //!< #V by k, M-orthonormal columns
};

//! The \p count smallest eigenpairs of C φ = −λ M φ, by shift-invert Lanczos (Spectra) on a
//! CHOLMOD factor of −C − σM with a small negative σ. Isolated vertices (in no face) are left out of
//! the problem and get φ = 0. \throw InvalidInput if count < 2 or count ≥ the number of vertices in
//! faces; SolverError if Lanczos does not converge.
LaplaceSpectrum laplace_spectrum(const Mesh& mesh, int count);

struct DiffusionOptions {
  double t = 0.1;        //!< diffusion time in units of 1/λ_1 (Gębal et al.: small t shows small features)
  int eigenpairs = 100;  //!< number of eigenpairs summed (λ_0 included, then skipped)
  static const OptionTable<DiffusionOptions>& table();
};

//! Auto diffusion function at every vertex (#V values), Gębal et al. 2009, Eq. (2):
//! ADF_t(x) = Σ_{i≥1} exp(−λ_i t / λ_1) φ_i(x)². Eigenvalues below 1e-8 λ_max (the constant
//! modes of each component) are skipped. \throw like laplace_spectrum.
Eigen::VectorXd auto_diffusion_function(const Mesh& mesh, const DiffusionOptions& options = {});

//! ADF from a precomputed spectrum (to evaluate several t cheaply).
Eigen::VectorXd auto_diffusion_function(const LaplaceSpectrum& spectrum, double t);

}  // namespace geotex
