#pragma once
//! \file editing.h Laplacian surface editing (thesis Sec. 5.1.4, Eq. 5.15–5.24): handles as soft
//! position constraints over a Laplacian, with three ways of treating rotation and scale:
//! none (Eq. 5.20), per-vertex similarities fitted to a membrane solution (Eq. 5.23–5.24, after
//! Lipman et al. 2004), and similarities kept linear in the unknown positions (Eq. 5.22, after
//! Sorkine et al. 2004, "Laplacian surface editing").
//!
//! Laplacian. The umbrella operator of Eq. (5.8), or cotangent weights normalised per row
//! ((L x)_i = Σ_j w_ij x_j / Σ_j w_ij − x_i), so that both give Laplacian coordinates δ_i in units
//! of length and one handle weight means the same for both.

#include <vector>

#include "geotex/toolkit/laplace.h"
#include "geotex/core/options.h"
#include "geotex/core/mesh.h"

namespace geotex {

enum class EditMethod {
  Plain,        //!< Eq. (5.20): keep δ_i as they are (translation-invariant only)
  MembraneFit,  //!< Eq. (5.22) with T_i fitted by SVD to a membrane solution, Eq. (5.23–5.24)
  Linear        //!< Eq. (5.22) with T_i linear in the unknown positions (Sorkine et al. 2004)
};

//! "plain", "membrane-fit", "linear".
const EnumNames<EditMethod>& edit_method_names();

struct EditOptions {
  EditMethod method = EditMethod::Linear;          //!< how rotations and scales of δ_i are handled
  LaplacianType laplacian = LaplacianType::Umbrella;  //!< the thesis writes Eq. (5.21) with the umbrella
  double handle_weight = 1.0;                      //!< w_i of Eq. (5.19) when a handle vertex has none of its own
  bool allow_scale = true;                         //!< T_i a similarity (rotation + isotropic scale), else a rotation
  //! MembraneFit: fit T_i between the membrane of the rest pose and the deformed membrane (true), or,
  //! as Eq. (5.24) literally says, between the original 1-ring and the deformed membrane (false). The
  //! literal form makes T_i ≠ I even when nothing moves, because the membrane flattens the detail.
  bool fit_to_rest_membrane = true;
  static const OptionTable<EditOptions>& table();
};

//! A similarity x ↦ s R x + t.
struct Similarity {
  double s = 1;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Vec3 t = Vec3::Zero();
  Vec3 operator()(const Vec3& x) const { return s * (R * x) + t; }
  Eigen::Matrix3d linear() const { return s * R; }
};

//! Least-squares similarity (Umeyama 1991, by SVD) mapping the rows of P onto the rows of Q
//! (Eq. 5.24): argmin Σ_k |s R p_k + t − q_k|². With \p allow_scale false, s = 1. Degenerate input
//! (all points equal) gives the translation between the centroids. \pre P, Q: k by 3, k ≥ 1.
Similarity fit_similarity(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q, bool allow_scale = true);

//! One similarity per vertex, fitted between the closed 1-rings ({i} ∪ N_i) of \p X0 and \p X1
//! (both #V by 3, same connectivity as \p mesh). OpenMP-parallel.
std::vector<Similarity> one_ring_similarities(const Mesh& mesh, const MatrixX3d& X0, const MatrixX3d& X1,
                                              bool allow_scale = true);

//! The Laplacian used for editing (see the file comment): #V by #V, rows summing to 0.
SparseMatrix editing_laplacian(const Mesh& mesh, LaplacianType type);

//! Factor once, re-solve when only handle targets move.
class LaplacianEditor {
 public:
  //! \param handles vertex indices of the handles (distinct), \param weights one w_i per handle, or
  //! empty for EditOptions::handle_weight. \throw InvalidInput for bad indices, weights ≤ 0, no
  //! handles, or a connected component without a handle (decided on the mesh, before factoring).
  //! Linear with fewer than three non-collinear handles in a component: the similarity the handles
  //! leave free is fixed by weak anchors at the place the handles' own motion takes them (a
  //! translation for one handle, the minimal rotation and scale of the two extreme handles for
  //! collinear ones), the same result on every machine. MembraneFit there keeps the details' rest
  //! frame (the plain method), as the membrane of such handles is a point or a line. Isolated vertices
  //! stay where they are.
  //! \pre \p mesh outlives the editor (it is referenced, not copied).
  LaplacianEditor(const Mesh& mesh, std::vector<int> handles, std::vector<double> weights = {},
                  const EditOptions& options = {});

  //! Deformed positions for handle targets \p C (#handles by 3, in the order given). \return #V by 3.
  MatrixX3d solve(const MatrixX3d& C) const;

  //! The membrane solution of Eq. (5.23) for targets C (#V by 3).
  MatrixX3d membrane(const MatrixX3d& C) const;

  const std::vector<int>& handles() const { return handles_; }
  const EditOptions& options() const { return options_; }
  //! Laplacian coordinates D = L X of the rest pose, Eq. (5.16). #V by 3.
  const MatrixX3d& laplacian_coordinates() const { return D_; }

 private:
  //! A weak pin fixing a similarity the linear method's handles leave free (see the constructor).
  struct Anchor {
    int vertex = -1;           // the pinned vertex
    int a = -1, b = -1;        // the extreme handles (indices into handles_); b < 0: a translation
    double w2 = 0;             // its weight²
    std::vector<int> handles;  // translation: the handles whose mean displacement it follows
  };
  std::vector<Anchor> anchors(const Mesh& mesh) const;
  Vec3 anchor_target(const Anchor& anchor, const MatrixX3d& C) const;
  MatrixX3d handle_rhs(const MatrixX3d& C) const;  // W² C scattered to #V rows, plus the pins'
  std::vector<int> isolated_;  // isolated vertices: held at rest (weight 1)
  std::vector<Anchor> anchors_;
  std::vector<char> rest_frame_;  // MembraneFit: vertices whose component's membrane is degenerate
  const Mesh* mesh_;
  std::vector<int> handles_;
  std::vector<double> w2_;
  EditOptions options_;
  MatrixX3d X_, D_;
  SparseMatrix L_;
  LeastSquaresSolver solver_;         // LᵀL + W² (Plain, MembraneFit)
  LeastSquaresSolver linear_solver_;  // GᵀG + W² ⊗ I₃ (Linear), unknowns ordered x-block, y-block, z-block
  MatrixX3d membrane_rest_;  // MembraneFit: membrane of the rest pose
};

//! One-shot editing: LaplacianEditor(mesh, handles, weights, options).solve(targets).
MatrixX3d laplacian_edit(const Mesh& mesh, const std::vector<int>& handles, const MatrixX3d& targets,
                         const EditOptions& options = {});

//! Per-vertex detail error of a deformation: for each vertex, |δ'_i − s_i R_i δ_i| / mean_j |δ_j|,
//! with (s_i, R_i) the similarity fitted between the 1-rings of the rest pose X0 and the deformed X1.
//! Zero when every 1-ring's Laplacian coordinate followed its ring's rotation and scale.
//! \return #V values (relative to the mean rest |δ|).
Eigen::VectorXd detail_error(const Mesh& mesh, const MatrixX3d& X0, const MatrixX3d& X1,
                             LaplacianType type = LaplacianType::Umbrella);

}  // namespace geotex
