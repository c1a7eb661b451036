// Scanner stripes along one world axis (issue 24, fifteenth session): the axis fitted in 3D and the residual's
// spectrum along it (stripes.cpp).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "geotex/core/mesh.h"

namespace geotex::detail {

//! Bands along one axis across a part: what fit_stripes() read.
struct StripeFit {
  Vec3 axis = Vec3::UnitZ();  //!< unit; the bands are planes orthogonal to it
  double period = 0;          //!< the bands' period, in mean edge lengths (0: none fitted)
  double share = 0;           //!< share of the residual's variance one sinusoid along axis explains, in [0, 1]
};

//! Stripes across one part, whatever the direction they take on each of its faces. A scanner's bands displace
//! the surface along its normals by f(a·x) for one axis a: on a face of unit normal n, the residual's gradient g
//! is f' × (a − (a·n) n), so a lies in the plane of g and n, a·(g × n) = 0. The axis is the least-squares
//! solution over the part's faces (area-weighted), measured against what a direction-free residual would give
//! (E[(g × n)(g × n)ᵀ] = |g|² (I − n nᵀ) / 2): a generalized eigenproblem, whose smallest vector is a. It is
//! then refined (a pattern search over directions, steps 0.15 to 0.005 rad) to the axis along which one
//! sinusoid of period 3-32 edges explains most of the residual's variance; that share is at most 0.12 under white
//! noise (a small part with impulses more) and 0.19-0.83 under stripes (bench/denoise.md, fifteenth session).
//! \p X #V by 3 positions along which the bands are measured, \p Xs #V by 3 the fit whose faces carry the
//! gradient, \p F #F by 3, \p faces and \p verts the part's faces (rows of F) and vertices, \p r #V residual
//! along the normals, \p h the mean edge length. A part of fewer than 3 faces or a residual of no variance reads
//! share 0.
StripeFit fit_stripes(const MatrixX3d& X, const MatrixX3d& Xs, const MatrixX3i& F, const std::vector<int>& faces,
                      const std::vector<int>& verts, const Eigen::VectorXd& r, double h);

}  // namespace geotex::detail
