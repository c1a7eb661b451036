#pragma once
//! \file resize.h Feature-aware resizing and deformation (thesis ch. 9): a spatial deformation (space
//! map or an edited mesh) is applied while the features, given by per-vertex weights f_i ∈ [0, 1],
//! keep their shape and size.
//!
//! Two formulations.
//!  - ResizeMethod::Thesis, Eq. (9.2–9.3): feature vertices keep their Laplacian coordinates rotated
//!    by T_i (fitted by SVD between the original and the space-mapped 1-rings), every vertex is pulled
//!    to its space-mapped position c_i with weight w p_i, p_i = 1 − f_i.
//!  - ResizeMethod::Sliding (default; what Sec. 9.5 and ch. 10 propose): background vertices are held
//!    only to the deformed base surface, along its normal, so they can slide along it and make room;
//!    the outer frame (mesh boundary and the vertices at the extremes of the bounding box) is pinned to
//!    the space map, and a weak Laplacian term spreads the stretch evenly over the background. Each
//!    connected feature region is kept rigid: its edges keep their original vectors, turned by one
//!    rotation fitted (SVD) on the region's foot ring, i.e. with the tangent plane of its base.
//!    (Laplacian coordinates alone cannot do this: an in-plane affine map of a flat region leaves them
//!    unchanged, so a feature whose rim is stretched stretches along.) The stretch collects in the
//!    background between the features, which keep their shape and size.

#include <functional>
#include <string>
#include <vector>

#include "geotex/toolkit/laplace.h"
#include "geotex/core/mesh.h"
#include "geotex/core/progress.h"

namespace geotex {

//! A space map R³ → R³ applied to every vertex.
using SpaceMap = std::function<Vec3(const Vec3&)>;

//! Anisotropic scaling about \p centre: x ↦ centre + diag(s) (x − centre).
SpaceMap scale_map(const Vec3& s, const Vec3& centre = Vec3::Zero());
//! Shear-type bend along x: z ↦ z + κ (x − x0)² / 2 (verticals stay vertical, so protrusions
//! tilt against the bent base under the plain map).
SpaceMap bend_map(double kappa, double x0 = 0.0);
//! Twist about the x axis: rotation by τ (x − x0) radians about the line through (x0, 0, 0) along x.
SpaceMap twist_map(double tau, double x0 = 0.0);

enum class ResizeMethod {
  Sliding,  //!< background slides along the deformed surface; frame pinned (default, beyond the thesis)
  Thesis    //!< Eq. (9.2–9.3): weighted Laplacian least squares with p_i = 1 − f_i
};

struct ResizeOptions {
  ResizeMethod method = ResizeMethod::Sliding;
  //! w of Eq. (9.2): weight of the position terms against the feature terms.
  double position_weight = 1.0;
  //! Features keep their size (T_i a rotation, default), or scale with the map (T_i a similarity).
  bool keep_feature_size = true;
  //! Sliding: weight of the background's Laplacian term (keeps the background smooth and spreads
  //! the stretch); small, so that the background gives way before the features do.
  double background_smoothness = 0.002;
  //! Sliding: weight of pinning the frame (boundary and bounding-box extremes) to the space map.
  double frame_weight = 10.0;
  //! Sliding: vertices within this many mean edge lengths of a bounding-box face belong to the frame,
  //! for axes along which the mesh extends at least a quarter of its largest extent.
  double frame_band = 1.5;
  //! Sliding: re-project onto the deformed surface and re-solve this many extra times (curved bases).
  int refinements = 1;
  LaplacianType laplacian = LaplacianType::Umbrella;  //!< Eq. (9.1) uses the umbrella operator
  ProgressFn progress;
};

//! Feature-aware deformation. \param mesh the original, \param deformed #V by 3 positions after the
//! spatial deformation (c_i), \param features #V weights f_i in [0, 1]. \return #V by 3 positions.
//! \throw InvalidInput on size mismatch, weights outside [0, 1] or non-finite input; SolverError.
MatrixX3d feature_aware_resize(const Mesh& mesh, const MatrixX3d& deformed, const Eigen::VectorXd& features,
                               const ResizeOptions& options = {});

//! Convenience: apply \p map to every vertex and call the function above.
MatrixX3d feature_aware_resize(const Mesh& mesh, const SpaceMap& map, const Eigen::VectorXd& features,
                               const ResizeOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Feature maps

struct FeatureMapOptions {
  //! Height source: the height of each vertex over a smoothed base (implicit cotangent smoothing of
  //! \p smoothing_time squared mean edge lengths), in mean edge lengths; features where |height| exceeds
  //! \p height_threshold, grown by \p dilate rings so that each feature includes its foot.
  double smoothing_time = 200.0;
  double height_threshold = 0.5;
  int dilate = 2;
};

//! Features from the height over a smoothed base (the texture height of ch. 8): f_i ∈ {0, 1}.
Eigen::VectorXd features_from_height(const Mesh& mesh, const FeatureMapOptions& options = {});

//! Features from a height field (e.g. a texture PLY's "height"): |h_i| > threshold, dilated by \p dilate rings.
Eigen::VectorXd features_from_values(const Mesh& mesh, const Eigen::VectorXd& height, double threshold, int dilate);

//! Features by thresholding the auto diffusion function (Sec. 9.4, Fig. 9.5): ADF normalised to [0, 1]
//! by its range, f_i = 1 where it exceeds \p threshold, dilated by \p dilate rings.
//! Suited to protrusions (the tentacles of Fig. 9.5). On a plate with low bumps the ADF peaks at the
//! plate's corners and rim instead (measured: IoU 0 against the bumps of bumpy_plate for t in
//! [0.02, 0.1]), which is why the CLI's `--features auto` uses features_from_height().
Eigen::VectorXd features_from_adf(const Mesh& mesh, double t = 0.1, int eigenpairs = 100, double threshold = 0.5,
                                  int dilate = 1);

//! Grow a 0/1 feature map by \p rings vertex rings.
Eigen::VectorXd dilate_features(const Mesh& mesh, const Eigen::VectorXd& f, int rings);

// ---------------------------------------------------------------------------------------------
// Test shape and measurements

struct BumpyPlateOptions {
  int n = 80;             //!< n × n quads over [−1, 1]²
  int bumps = 3;          //!< bumps × bumps round bumps on a regular grid
  double spacing = 0.6;   //!< distance between bump centres
  double radius = 0.2;    //!< footprint radius
  double height = 0.15;   //!< bump height (profile h (1 − r²/R²)², C¹ at the rim)
};

struct BumpyPlate {
  Mesh mesh;
  std::vector<Vec3> centres;  //!< footprint centres (z = 0)
  double radius = 0, height = 0;
  Eigen::VectorXd truth;      //!< 1 inside a footprint, else 0
};

//! A flat square plate with round bumps: the test shape of feature-aware resizing.
BumpyPlate bumpy_plate(const BumpyPlateOptions& options = {});

//! Shape of one deformed bump, measured on the vertices that were in its footprint.
struct BumpShape {
  double aspect = 1;   //!< footprint aspect ratio (√ of the covariance's in-plane eigenvalue ratio) of the rim ring
  double height = 0;   //!< tip's distance from the plane fitted to the rim ring
  double tilt_deg = 0; //!< angle between the rim plane's normal and the rim-centroid-to-tip direction
};

//! Measure the bump at \p centre (original coordinates, radius \p radius): the rim ring is the
//! vertices whose original distance from the centre is in [0.7, 0.95] radius; the tip the one nearest the centre.
BumpShape measure_bump(const MatrixX3d& original, const MatrixX3d& deformed, const Vec3& centre, double radius);

}  // namespace geotex
