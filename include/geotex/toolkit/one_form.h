#pragma once
//! \file one_form.h Discrete 1-forms on triangle meshes (thesis Sec. 5.3, 8.2): tangent vector fields
//! stored as one scalar per edge, c_ij = ∫_{e_ij} t·ds (Eq. 5.67–5.69).
//!
//! Edge orientation: the rows of edges(mesh), (i, j), with e_ij = x_j − x_i (Eq. 5.68). e^⊥ is the edge
//! rotated by π/2 in its face's plane (n_f × e), so that ∇φ_i = e_jk^⊥ / (2A) (Eq. 5.72).

#include <functional>

#include "geotex/toolkit/linear_solver.h"
#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

//! Line integrals of an ambient vector field along every edge (Eq. 5.69), by 5-point Gauss–Legendre.
//! \return #E coefficients.
Eigen::VectorXd one_form_from_function(const Mesh& mesh, const std::function<Vec3(const Vec3&)>& field);

//! The averaging estimate c_ij = ½ (t_i + t_j)·e_ij from a per-vertex field (Eq. 5.80).
//! \param T #V by 3 vectors. \return #E coefficients.
Eigen::VectorXd one_form_average(const Mesh& mesh, const MatrixX3d& T);

//! Whitney basis function of the face's local edge \p local_edge (0: v0→v1, 1: v1→v2, 2: v2→v0, in
//! the face's corner order) at barycentric coordinates \p bary (Eq. 5.71, 5.73), for the edge taken
//! in the face's orientation.
Vec3 whitney_basis(const Mesh& mesh, int face, int local_edge, const Vec3& bary);

//! Whitney interpolation of a 1-form inside a face (Eq. 5.77). \param c #E coefficients;
//! \param bary weights of the face's corners in faces(mesh) order. \return the tangent vector.
Vec3 whitney_interpolate(const Mesh& mesh, const Eigen::VectorXd& c, int face, const Vec3& bary);

//! Per-vertex field: face contributions (Eq. 5.78) averaged over the incident faces (Eq. 5.79; the
//! thesis divides by the valence, which equals the number of incident faces for interior vertices —
//! we divide by the face count, so boundary vertices are averaged too). \return #V by 3.
MatrixX3d one_form_to_vertices(const Mesh& mesh, const Eigen::VectorXd& c);

//! The 3#V by #E matrix [P^x; P^y; P^z] of Eq. (5.81)–(5.82): one_form_to_vertices() as a matrix.
SparseMatrix one_form_reconstruction_matrix(const Mesh& mesh);

struct OneFormFitOptions {
  //! Fit only the components tangent to the vertex normals (2#V equations against #E ≈ 3#V unknowns:
  //! an exact fit where the thesis' full system, Eq. 5.81, is a compromise with the normal parts of
  //! P c). On icosphere(3) with a rotation field the full fit reproduces the field to 1.4e-7, the
  //! tangential one its tangent parts to 3e-12 (one_form_test). Direct tangential fits without the
  //! bound solve the 2#V × 2#V vertex form of the same normal equations (one third the unknowns of
  //! the #E system, on the vertex graph). Off by default here: a general field's normal parts count;
  //! a texture's tilt is tangent (TextureOptions::tangential_fit).
  bool tangential = false;
  //! Keep |c_ij| ≤ ‖e_ij‖ (Sec. 8.5: a tilt has magnitude at most one).
  bool bound_by_edge_length = false;
  //! Weight of the pull towards the averaging estimate (Eq. 5.80), relative to the mean diagonal of
  //! PᵀP: it makes the normal equations definite where Eq. (5.81) leaves coefficients undetermined.
  double regularization = 1e-9;
  int bound_rounds = 6;  //!< active-set rounds that pin violating coefficients to ±‖e_ij‖
  double bound_stiffness = 1e3;  //!< penalty pinning a violator, relative to the mean diagonal
  static const OptionTable<OneFormFitOptions>& table();
};

struct IterativeFitOptions {
  int max_iterations = 1000;  //!< CGLS iterations at most
  int check_every = 10;       //!< ask the monitor every this many iterations
};

//! Called during an iterative fit with the current coefficients c (#E) and their vertex field P c
//! (3#V: all x, then all y, then all z; Eq. 5.79). Return true to stop (converged).
using OneFormFitMonitor = std::function<bool(const Eigen::VectorXd& c, const Eigen::VectorXd& Pc)>;

struct IterativeFitResult {
  Eigen::VectorXd c;       //!< #E coefficients after the last iteration
  int iterations = 0;      //!< CGLS iterations done
  bool converged = false;  //!< the monitor returned true
};

//! Least-squares 1-form fit (Eq. 5.81–5.82): argmin_c ‖P c − t‖² (+ a small pull towards Eq. 5.80).
//! Direct: the normal equations are analysed and factored (CHOLMOD) on first use and reused for every
//! field. Iterative: CGLS on the same objective, warm-started from Eq. (5.80), no factorization.
class OneFormFitter {
 public:
  //! \param normals #V by 3 unit normals, used by OneFormFitOptions::tangential (default: area-weighted).
  explicit OneFormFitter(const Mesh& mesh, const OneFormFitOptions& options = {},
                         const MatrixX3d& normals = MatrixX3d());
  ~OneFormFitter();
  OneFormFitter(OneFormFitter&&) noexcept;
  OneFormFitter& operator=(OneFormFitter&&) noexcept;

  //! \param T #V by 3 field at vertices. \return #E coefficients. \throw InvalidInput on a size mismatch.
  Eigen::VectorXd fit(const MatrixX3d& T);
  //! Weighted fit: argmin Σ_i w_i ‖(P c)_i − t_i‖² (+ the pull to Eq. 5.80). Refactors the normal
  //! equations numerically (the symbolic analysis is reused). \param weights #V positive weights.
  Eigen::VectorXd fit(const MatrixX3d& T, const Eigen::VectorXd& weights);
  //! The same (weighted) objective by CGLS with Jacobi column scaling, started from the averaging
  //! estimate (Eq. 5.80), which also takes the place of the regularization: CGLS never changes the
  //! start's component in the null space of P. Stops when \p converged returns true or after
  //! options.max_iterations. Honours OneFormFitOptions::tangential (the monitor still gets the
  //! unprojected P c); ignores ::bound_by_edge_length (the caller uses fit() for it).
  //! \param weights #V positive weights, or empty for all ones.
  IterativeFitResult fit_iterative(const MatrixX3d& T, const Eigen::VectorXd& weights,
                                   const OneFormFitMonitor& converged, const IterativeFitOptions& options = {});

  //! The reconstruction matrix P (3#V by #E).
  const SparseMatrix& matrix() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! One-shot convenience: OneFormFitter(mesh, options).fit(T).
Eigen::VectorXd fit_one_form(const Mesh& mesh, const MatrixX3d& T, const OneFormFitOptions& options = {});

}  // namespace geotex
