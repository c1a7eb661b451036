#pragma once
//! \file laplace.h Discrete Laplacians (thesis Sec. 5.1): the umbrella operator (Eq. 5.8), the
//! cotangent matrix and mass matrices behind the cotangent Laplacian (Eq. 5.11), and the mean
//! curvature normal (Eq. 5.10).
//!
//! Conventions. Matrices are #V by #V, rows and columns in vertex-index order. Every Laplacian here
//! has rows summing to zero, so L·1 = 0. The cotangent Laplacian is factored as L = M⁻¹ C with a
//! symmetric, negative semi-definite C and a diagonal, positive M; solvers use the symmetric pair.
//!
//! Boundaries. A boundary edge has one opposite angle, so its cotangent weight has the single term
//! ½ cot α; boundary vertices keep only their actual neighbours in the umbrella operator. That is the
//! natural (Neumann) discretization: on a flat patch, boundary rows do not vanish. Smoothing fixes
//! boundary vertices by default (SmoothingOptions::fix_boundary). Isolated vertices get a zero row.

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/toolkit/linear_solver.h"

namespace geotex {

enum class LaplacianType { Umbrella, Cotangent };
//! "umbrella", "cotan" (also "cotangent").
const EnumNames<LaplacianType>& laplacian_names();

//! Umbrella operator, Eq. (5.7–5.8): (L x)_i = (1/d_i) Σ_{j∈N_i} x_j − x_i. Not symmetric.
SparseMatrix umbrella_laplacian(const Mesh& mesh);

//! Vertex adjacency matrix (1 for every edge) and the valences d_i.
SparseMatrix adjacency_matrix(const Mesh& mesh);

struct CotanOptions {
  //! |cot| is bounded by this, so that zero-area or needle triangles give large but finite weights. The
  //! bound floors each triangle's area (the same for its three corners), which keeps C negative
  //! semi-definite on meshes with zero-area triangles; other triangles are unaffected.
  double max_cot = 1e4;
};

//! Cotangent matrix: C_ij = ½(cot α_ij + cot β_ij) for each edge, C_ii = −Σ_j C_ij. Symmetric,
//! negative semi-definite for Delaunay meshes. Eq. (5.11) up to the mass normalization.
SparseMatrix cotan_matrix(const Mesh& mesh, const CotanOptions& options = {});

enum class MassType {
  Voronoi,      //!< mixed Voronoi areas (Meyer et al. 2003); sums to the surface area
  Barycentric,  //!< one third of the 1-ring area; sums to the surface area
  Thesis        //!< 2 × 1-ring area A_i, so that M⁻¹C is exactly Eq. (5.11)'s 1/(4A_i) Σ (cot α + cot β)
};
//! "voronoi", "barycentric", "thesis".
const EnumNames<MassType>& mass_names();

//! Diagonal of the mass matrix (#V). Isolated vertices get 1, so M stays invertible.
Eigen::VectorXd mass_diagonal(const Mesh& mesh, MassType type = MassType::Voronoi);

//! Diagonal mass matrix as a sparse matrix.
SparseMatrix mass_matrix(const Mesh& mesh, MassType type = MassType::Voronoi);

//! Cotangent Laplacian L = M⁻¹ C. With MassType::Thesis this is Eq. (5.11) verbatim; with Voronoi
//! it approximates the Laplace–Beltrami operator (L x = −2H n on a smooth surface).
SparseMatrix cotan_laplacian(const Mesh& mesh, MassType type = MassType::Voronoi,
                             const CotanOptions& options = {});

//! Laplacian of the given type (umbrella, or cotangent with the given mass).
SparseMatrix laplacian(const Mesh& mesh, LaplacianType type, MassType mass = MassType::Voronoi);

//! Mean curvature normal H_i n_i (Eq. 5.9–5.10) with Voronoi areas: −½ (M⁻¹ C X)_i.
//! On a sphere of radius r with outward orientation it is n/r. \return #V by 3.
MatrixX3d mean_curvature_normals(const Mesh& mesh);

}  // namespace geotex
