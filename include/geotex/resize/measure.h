#pragma once
//! \file measure.h Test shapes and measurements for feature-aware resizing (thesis ch. 9): a plate
//! with bumps and a ridge, and what must hold after a resize — features keep their shape (aspect,
//! height, length, angle to the local base) and leave no crease around their rims.

#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

struct BumpyPlateOptions {
  int n = 80;             //!< n × n quads over [−1, 1]²
  int bumps = 3;          //!< bumps × bumps round bumps on a regular grid
  double spacing = 0.6;   //!< distance between bump centres
  double radius = 0.2;    //!< footprint radius
  double height = 0.15;   //!< bump height (profile h (1 − r²/R²)², C¹ at the rim)
  //! A ridge: the bump's profile swept along a segment of this length (0: none) on the y axis,
  //! centred at the origin (rounded ends). Scaling along x would widen it.
  double ridge_length = 0;
};

struct BumpyPlate {
  Mesh mesh;
  std::vector<Vec3> centres;  //!< footprint centres of the round bumps (z = 0)
  double radius = 0, height = 0;
  Eigen::VectorXd truth;      //!< 1 inside a footprint (bumps and ridge), else 0
  Eigen::VectorXd ridge;      //!< 1 inside the ridge's footprint, else 0
};

//! A flat square plate with round bumps (and optionally a ridge): the test shape of feature-aware resizing.
//! \throw InvalidInput for bad options or features that overlap.
BumpyPlate bumpy_plate(const BumpyPlateOptions& options = {});

//! The ridge plate: 2 × 2 bumps 1.0 apart and a ridge of length 1.2 between them (bumpy_plate()).
BumpyPlate ridge_plate(int n = 80);

//! Shape of one deformed bump, measured on the vertices that were in its footprint.
struct BumpShape {
  double aspect = 1;   //!< footprint aspect ratio (√ of the covariance's in-plane eigenvalue ratio) of the rim ring
  double height = 0;   //!< tip's distance from the plane fitted to the rim ring
  double tilt_deg = 0; //!< angle between the rim plane's normal and the rim-centroid-to-tip direction
};

//! Measure the bump at \p centre (original coordinates, radius \p radius): the rim ring is the
//! vertices whose original distance from the centre is in [0.7, 0.95] radius; the tip the one nearest the centre.
BumpShape measure_bump(const MatrixX3d& original, const MatrixX3d& deformed, const Vec3& centre, double radius);

//! A protrusion seen from its local base: the foot ring (vertices around its footprint) gives the base
//! plane (centroid c, normal n by PCA, turned to agree with the ring's vertex normals).
struct Protrusion {
  double length = 0;     //!< |tip − c|
  double angle_deg = 0;  //!< angle between tip − c and n
};

//! Measure a protrusion on positions \p X (#V by 3) of \p mesh. \param tip its tip vertex;
//! \param footprint #V 0/1 membership of its footprint; the foot ring is the vertices outside it next to it.
//! \throw InvalidInput if the foot ring has fewer than 3 vertices.
Protrusion measure_protrusion(const Mesh& mesh, const MatrixX3d& X, int tip, const Eigen::VectorXd& footprint);

//! Principal extents of each connected feature region (vertices with f > ½): the square roots of the
//! eigenvalues, descending, of the area-weighted covariance of the region's vertices. The areas are
//! the vertices' shares of \p mesh's (original) surface, so that regions are compared point for point.
struct RegionExtents {
  std::vector<int> vertices;    //!< the region's vertices
  Vec3 extents = Vec3::Zero();  //!< e1 ≥ e2 ≥ e3
};
std::vector<RegionExtents> region_extents(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f);

//! Change of a region's aspect between two configurations: max(|a'/a − 1|) over the ratios e2/e1 and
//! e3/e1 of its extents (0: same proportions, whatever the size and orientation).
double aspect_change(const Vec3& before, const Vec3& after);

//! Largest crease near feature rims: the largest |dihedral angle| (degrees) over edges (i, j) with
//! both ends within \p rings rings of a rim (a vertex with f > ½ next to one with f ≤ ½). The dihedral
//! angle is the jump of the surface normal across an edge (the curvature integrated across it);
//! unlike a mean-curvature estimate it does not see how triangles are stretched within the surface.
//! Compare an output's value with the input's and the plain map's: a ring around a feature shows as a
//! larger crease. \p q below 1 gives that quantile of the band's |angles| instead of the maximum.
double rim_crease_deg(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f, int rings = 2, double q = 1.0);

}  // namespace geotex
