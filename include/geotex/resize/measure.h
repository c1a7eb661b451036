#pragma once
//! \file measure.h Measurements for feature-aware resizing (thesis ch. 9): what must hold after a
//! resize — features keep their shape (aspect, height, length, angle to the local base) and leave no
//! crease around their rims. Its test shapes (bumpy_plate(), ridge_plate()) are in tools/shapes.h.

#include <vector>

#include "geotex/core/mesh.h"

namespace geotex {

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
struct ProtrusionPose {
  double length = 0;     //!< |tip − c|
  double angle_deg = 0;  //!< angle between tip − c and n
};

//! Measure a protrusion on positions \p X (#V by 3) of \p mesh. \param tip its tip vertex;
//! \param footprint #V 0/1 membership of its footprint; the foot ring is the vertices outside it next to it.
//! \throw InvalidInput if the foot ring has fewer than 3 vertices.
ProtrusionPose measure_protrusion(const Mesh& mesh, const MatrixX3d& X, int tip, const Eigen::VectorXd& footprint);

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
