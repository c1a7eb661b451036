#pragma once
//! \file base_shape.h The base shape under a textured surface (thesis Sec. 8.3.1): a smooth surface with
//! the textured mesh's connectivity, one base vertex per textured vertex, from which the texture is the
//! displacement d_i = x_i − b_i (Eq. 8.4).
//!
//! The default (BaseMethod::Robust) fits a smooth surface to the textured one and lets protrusions go:
//!  1. a screened bi-Laplacian fit, argmin_B Σ w_i ‖b_i − x_i‖² + μ ‖L B‖² (L the umbrella operator of
//!     the textured mesh; μ from BaseShapeOptions::scale), its shrinking undone by one more pass of the
//!     same filter (B ← 2B − S B: shapes the filter keeps come back to second order);
//!  2. reweighted: vertices farther from the fit than a robust bound get weight 0 (Tukey), so a
//!     protrusion is filled from around its foot instead of being cut halfway (no step cap);
//!  3. projected (Sec. 8.3.1, "we define the base shape and project the textured geometry to it"):
//!     each base vertex moves to the projection of its textured vertex onto the fitted surface along
//!     its Phong normals (Sec. 5.2), so displacements lie along the base normal — except on protrusions
//!     and wherever the projection would fold the base, which keep the fitted position.
//! The thesis' own method (implicit smoothing until the shape stops changing) is BaseMethod::Smoothing.

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"
#include "geotex/core/progress.h"
#include "geotex/toolkit/laplace.h"

namespace geotex {

enum class BaseMethod {
  Robust,     //!< reweighted screened bi-Laplacian fit, then projection (default; see the file comment)
  Smoothing,  //!< implicit Laplacian smoothing until the shape stops changing (Sec. 8.3.1, Eq. 5.14)
};
//! "robust", "smoothing" (also "thesis").
const EnumNames<BaseMethod>& base_method_names();

struct BaseShapeOptions {
  BaseMethod method = BaseMethod::Robust;
  //! Robust: cutoff wavelength of the fit, in mean edge lengths: bumps narrower than about this are
  //! texture. μ = (scale/π)⁴/6 makes the bi-Laplacian term equal the data term at that wavelength.
  double scale = 20.0;
  //! Robust: a vertex farther from the first fit than outlier × 1.4826 × the median distance (a robust
  //! standard deviation) has weight 0 and is filled from around (Tukey's biweight below it).
  double outlier = 3.0;
  //! Robust: the cutoff wavelength at most this share of its connected component's size (√area, in mean
  //! edges): the legs and ears of a coarse model, or a small separate piece, are shape rather than texture
  //! (issue 26: spot's base kept 0.77 of its area, a 19-part teapot's 0.19). 0: the cutoff alone.
  double size_share = 0.2;
  //! Robust: an open surface's boundary vertices hold their place: a flat or open model keeps its outline
  //! (woody's base kept 0.52 of its area, its "texture" 90° off the normal).
  bool hold_boundary = true;
  int robust_passes = 3;  //!< robust: reweighted fits after the first
  //! Robust: project the textured vertices onto the fitted surface along its Phong normals where that
  //! helps (not on protrusions, not where it would fold the base), so displacements lie along the normal.
  bool project = true;

  //! Smoothing: umbrella or cotangent (mean-curvature flow proper, Eq. 5.11). Overhanging textures give
  //! negative cotangent weights and an indefinite system (seen on spiky-sphere), so umbrella is the default.
  LaplacianType laplacian = LaplacianType::Umbrella;
  double lambda = 1.0;          //!< smoothing: implicit step (umbrella: dimensionless; cotangent: in squared mean edges)
  int steps = 0;                //!< smoothing: number of steps; 0 = automatic: step until the shape stops changing
  int max_steps = 30;           //!< smoothing, automatic mode: at most this many steps
  double stop_tolerance = 0.05; //!< smoothing, automatic mode: stop when a step moves no vertex more than this × mean edge
  ProgressFn progress;          //!< called after each step or pass
  //! Table; preset "thesis": implicit umbrella smoothing until the shape stops changing (at most 30
  //! steps), no projection.
  static const OptionTable<BaseShapeOptions>& table();
};

//! A base shape and how well its displacements follow its normals.
struct BaseShape {
  MatrixX3d positions;  //!< #V by 3 base positions, the textured mesh's connectivity and vertex order
  //! #V angles (degrees, in [0, 90]) between each displacement x_i − b_i and the base's vertex normal
  //! ±n_i (angle-weighted, TextureOptions' default); 0 where the displacement is below 1e-9 mean edges.
  Eigen::VectorXd off_normal_deg;
  //! #V: 1 where the base vertex is the projection of its textured vertex, 0 where it is the fit.
  Eigen::VectorXd projected;
  //! #V robust weights of the last fit: 1 follows the textured surface, 0 a protrusion (filled).
  Eigen::VectorXd weight;
  int passes = 0;          //!< smoothing steps taken, or fits solved (robust)
  bool stopped = true;     //!< smoothing, automatic: stopped by the tolerance (false: max_steps ran out)
  size_t unfolded = 0;     //!< vertices that kept the fit because projecting them folded the base
  double median_off_normal_deg = 0;  //!< median of off_normal_deg
};

//! The base shape of \p textured (Sec. 8.3.1). \throw InvalidInput for an empty mesh, non-finite
//! coordinates or bad options; SolverError if a solve fails.
BaseShape base_shape(const Mesh& textured, const BaseShapeOptions& options = {});

//! base_shape(textured, options).positions: #V by 3, same connectivity and order as \p textured.
MatrixX3d extract_base_shape(const Mesh& textured, const BaseShapeOptions& options = {});

//! A base of any connectivity: each vertex of \p textured projected onto \p base along the Phong
//! normal field (Sec. 5.2). \return a mesh with textured's connectivity at the projected points;
//! \p missed (optional) counts vertices with no inside solution (they take the closest point).
Mesh project_onto_base(const Mesh& textured, const Mesh& base, size_t* missed = nullptr);

//! Angle (degrees, [0, 90]) between each displacement \p textured − base and the base's angle-weighted
//! vertex normal ±n_i; 0 where the displacement is shorter than 1e-9 mean edges. \return #V.
Eigen::VectorXd off_normal_angles(const Mesh& base, const MatrixX3d& textured);

}  // namespace geotex
