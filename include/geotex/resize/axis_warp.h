#pragma once
//! \file axis_warp.h An axis-aligned, importance-weighted warp for resizing by a box scale, after
//! Kraevoy, Sheffer, Shamir and Cohen-Or, "Non-homogeneous resizing of complex models" (SIGGRAPH Asia
//! 2008): the model sits in a grid whose lines stay straight and axis-aligned, so the deformation is
//! separable, x' = g_x(x), y' = g_y(y), z' = g_z(z), each g_a monotone.
//!
//! Each g_a has a piecewise-linear derivative σ_a over the nodes t_{a,m} of a uniform grid along the
//! box (cells of about 1/\ref AxisWarpOptions::cells of its diagonal), so g_a is C¹ and the stretch has
//! no crease at a cell's rim. The unknowns are the node values σ_{a,m}; with s(p) = (σ_x(p_x), σ_y(p_y),
//! σ_z(p_z)) the local scales at a face's centroid p, they minimize
//!   Σ_f a_f v_f s(p_f)ᵀ M(n_f) s(p_f) / Σ_f a_f v_f                 in-plane anisotropy (below)
//! + μ Σ_f a_f v_f Σ_k (1 − n_{f,k}²)(s_k(p_f) − s̄)² / Σ_f a_f v_f   important faces keep their size in their plane
//! + λ Σ_a K_a Σ_m (σ_{a,m+1} − σ_{a,m})²                             smooth along each axis
//! + ε Σ_a Σ_m (w_{a,m} / L_a) (σ_{a,m} − λ_a)²                       weakly the plain stretch
//! + μ_s Σ_a Σ_m (w_{a,m} / L_a) v̄/(1 − v̄) (σ_{a,m} − s̄)²              opt-in: full slabs keep their size
//! subject to Σ_m w_{a,m} σ_{a,m} = λ_a L_a (the box exactly as asked; w the trapezoid weights) and
//! σ_{a,m} ≥ s_min > 0 (g_a increasing: no face turns over, no self-intersection appears).
//! v_f is the face's mean importance f (feature_map.h), s̄ the asked scale's smallest factor, K_a the
//! cells along axis a, L_a the box's extent, λ_a the asked stretch. M(n) is the in-plane anisotropy of
//! diag(s) on a face with unit normal n, to first order: with P = I − n nᵀ, |dev(P diag(s) P)|² =
//! sᵀ M s, M_kl = P_kl² − ½ P_kk P_ll. It vanishes for s ∝ 1 (a similarity) and does not see the scale
//! along the normal (a face perpendicular to the stretch shows none of it): Kraevoy's slippage in its
//! simplest form. The size term is blind to it too (1 − n_k² = P_kk, the share of axis k in the face's
//! plane; AxisWarpOptions::in_plane_size), so such a face takes the stretch for free. The problem is a small QP (a few hundred unknowns, dense through the faces), solved
//! by a primal active-set method: exact, milliseconds.
//!
//! Limits (bench/resize.md, ninth session): a slab is stretched as a whole, so where important surface
//! fills every slab along an axis (tentacles all along a stick, a cow's uniformly important body) it cannot
//! stay similar; slabs that hold only a protrusion's far end (a tentacle's, the teapot lid's knob) take the
//! stretch and the protrusion grows longer (\ref AxisWarpOptions::max_scale bounds it, opt-in). A skinny triangle
//! spanning cells of different slope could turn over (a linear diag(s) never turns a face): where one does,
//! λ is raised tenfold over the intervals it spans and the QP solved again, until none does.

#include <array>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

struct AxisWarpOptions {
  //! Cells along the box's diagonal: each axis has about cells · L_a / diagonal of them (at least 1).
  int cells = 64;
  double smoothness = 1e-5;   //!< λ: weight of the stretch's variation along each axis (bench/resize.md)
  double size_weight = 0.1;   //!< μ: weight of important faces keeping the asked scale's smallest factor
  //! The size term counts axis k by 1 − n_k², its share in the face's plane (the scale along a face's normal does
  //! not change the face); false: every axis fully, as before issue 25's twelfth session. True lowered the ruler's
  //! ratio on 22 of 29 ×2 runs and raised it by at most 0.007 (igea ×2 y 0.534 → 0.469, beetle ×2 y 0.694 → 0.590;
  //! bench/resize.md).
  bool in_plane_size = true;
  double plain_weight = 1e-3; //!< ε: weight of each node's pull to the plain stretch λ_a
  //! μ_s: weight of each slab (along each axis) keeping the asked scale's smallest factor, times v̄ / (1 − v̄),
  //! v̄ its faces' mean importance: a slab holding only a protrusion's end (a tentacle's) takes no stretch.
  //! 0 (off): on cow, cheburashka, fandisk and the bunny it raised axis-similarity's ratio (bench/resize.md).
  double slab_weight = 0;
  //! s_min as a share of the asked scale's smallest factor: no cell is squeezed below it.
  double min_scale = 0.5;
  //! σ_{a,m} ≤ max_scale · λ_a (values below 1 count as 1); 0: no limit. A slab holding only a protrusion's
  //! neck (the teapot lid's knob) otherwise takes up to 4× the asked stretch.
  double max_scale = 0;
  //! AxisSimilarity: weight β of every edge following the warp in the similarity stage (the similarity
  //! method's background_smoothness, 0.002, is for the plain map). The warp has spread the stretch smoothly
  //! over slabs, so its edges are worth following: with 0.002 the similarity stage gathered igea's stretch
  //! into creases and turned 989 faces before its relaxation rounds (8 left); with 0.03 none are left and no
  //! crease (bench/resize.md, eleventh session).
  double follow_weight = 0.03;
  //! AxisSimilarity: p of the follow weight's falloff with importance, β (1 − f_ij)^p on an edge: an important
  //! region follows only its similarity, not the warp's stretch of its slabs, and may turn, shear off the axes
  //! or scale as a whole while the unimportant rest takes the stretch in whatever direction it goes. 0: β on
  //! every edge (the stage before; fandisk ×2 x 0.601 -> 0.570 with 2, bench/resize.md, thirteenth session).
  double follow_falloff = 2.0;
  static const OptionTable<AxisWarpOptions>& table();
};

//! The separable map: per axis, nodes t_{a,0} < … < t_{a,K} (uniform, over the input's box) and the
//! derivative σ_{a,m} at each; an axis along which the box is flat has no nodes and is scaled plainly.
struct AxisWarp {
  std::array<double, 3> lo{}, step{};           //!< t_{a,m} = lo_a + m step_a
  std::array<Eigen::VectorXd, 3> scales;        //!< σ_{a,m}, K_a + 1 values (empty: a flat axis)
  std::array<double, 3> out_lo{}, stretch{};    //!< g_a(lo_a), λ_a (a flat axis: x' = out_lo + λ_a (x − lo_a))
  //! g_a(x) (exact piecewise-quadratic integral of σ_a; clamped linear continuation outside the box).
  double map(int axis, double x) const;
  //! #V by 3: every row through g_x, g_y, g_z.
  MatrixX3d apply(const MatrixX3d& X) const;
  //! ∫ σ_a over the box (= λ_a L_a by the constraint, up to rounding).
  double length(int axis) const;
};

//! The warp for a box scale by \p stretch (λ_x, λ_y, λ_z > 0) of \p mesh whose output box starts at
//! \p out_lo, with per-vertex importance \p f in [0, 1]. \throw InvalidInput for bad sizes or options.
AxisWarp axis_warp(const Mesh& mesh, const Vec3& stretch, const Vec3& out_lo, const Eigen::VectorXd& f,
                   const AxisWarpOptions& options = {});

//! If \p C is a box scale of \p X (each column an increasing affine function of the same column of X,
//! within 1e-6 of the box diagonal), its factors λ_a and the output box's lower corner; else false.
bool box_scale_of(const MatrixX3d& X, const MatrixX3d& C, Vec3& stretch, Vec3& out_lo);

}  // namespace geotex
