#pragma once
//! \file protrusion_placement.h Protrusions placed as rigid pieces (thesis ch. 9: features keep their
//! shape and size), for feature-aware resizing (resize.h, ResizeOptions::rigid_protrusions).
//!
//! A protrusion (a tentacle, an ear, a horn) is a connected region of high importance that stands out of
//! its foot: a single foot ring (the vertices next to the region) and a reach from the ring's centroid of
//! more than its radius. Instead of letting a deformation's per-vertex similarities bend and grow it, the
//! whole region is put back as one similarity x ↦ σ R x + t fitted to where the deformation moved its
//! foot ring (R, t: Umeyama's fit of the ring; σ: the ring's smallest stretch in its plane, so a
//! stretch keeps a protrusion's size and a uniform scale scales it, as the similarity method's s_i).
//! What the region's placement moves at its foot is spread over a band around it (harmonic interpolation
//! of the displacement, fading to nothing at the band's outer rim): no step at the seam. When protrusions
//! reach the box, the rest of the model is stretched a little more per axis so that the box holds them
//! at their size (fit_box_around_protrusions()).

#include <optional>
#include <vector>

#include "geotex/core/mesh.h"
#include "geotex/core/weld.h"

namespace geotex {

//! One protrusion: its rigid region and its foot ring (the vertices next to it, outside it).
struct RigidProtrusion {
  std::vector<int> vertices;
  std::vector<int> foot;
  double scale = 1;  //!< σ: the scale it is placed at (set_protrusion_scales())
};

//! The protrusions of weights \p f (#V in [0, 1]) on \p mesh at positions \p X (#V by 3): connected
//! regions of f ≥ 0.9 grown over their flared foot (to twice the radius of the core's own foot ring),
//! kept when their foot ring is one connected piece, they touch neither another region nor the mesh
//! boundary, span at most half the model's largest extent, and reach from their foot ring's centroid at
//! least 1.5 times the ring's mean radius (a bump, a patch of relief, a face or a whole body is not a
//! protrusion; on the shared models of bench/resize.md every region touches another or the boundary).
std::vector<RigidProtrusion> find_protrusions(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f);

//! Each protrusion's scale σ from the map \p C (#V by 3) of \p X: the smallest stretch of its foot ring in
//! the ring's own plane (\p keep_size; a stretch keeps its size, a uniform scale scales it, as the
//! similarity method's s_i), else the geometric mean of the two.
void set_protrusion_scales(const MatrixX3d& X, const MatrixX3d& C, std::vector<RigidProtrusion>& protrusions,
                           bool keep_size);

//! \p Y (#V by 3, a deformation of \p X) with every protrusion replaced by its original shape scaled by
//! its σ, turned and moved onto where \p Y put its foot ring (Umeyama's rotation of the ring, the ring's
//! centroid onto its centroid). The vertices reached from a protrusion within \p blend times its foot
//! ring's mean radius of the ring's centre take the protrusion's displacement, fading out biharmonically
//! (matching slope at both ends: no crease, no streaks) to nothing at the band's rim (0: no blend).
//! \return #V by 3 positions.
MatrixX3d place_protrusions(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y,
                            const std::vector<RigidProtrusion>& protrusions, double blend = 1.5);

//! \p protrusions without those a tie (weld.h: a point contact welded per fan, a rim resting on another part's faces)
//! joins to the rest: some but not all of the tie's vertex and corners (of nonzero weight) among the vertices
//! place_protrusions() moves for it (its own, and its band for \p blend). Placed as one piece, such a protrusion would
//! pull its tied vertices off their points; left out, it stays where the method put it, with the tie held.
std::vector<RigidProtrusion> untied_protrusions(const Mesh& mesh, const MatrixX3d& X,
                                                std::vector<RigidProtrusion> protrusions,
                                                const std::vector<SurfaceTie>& ties, double blend = 1.5);

//! Faces of \p Y turned over against the map \p C (#V by 3 both): their vertices and 2, 4, … rings around
//! them (not the protrusions') take the displacement Y − C harmonically interpolated from around them, for up
//! to \p rounds rounds. \return the faces still turned.
int relax_turned_faces(const Mesh& mesh, const MatrixX3d& C, const std::vector<RigidProtrusion>& protrusions,
                       MatrixX3d& Y, int rounds = 4);

//! \p B (#V by 3, a deformation of \p X) stretched per axis about its box centre and moved so that
//! place_protrusions() of it has the box [\p lo, \p hi]: the rest of the model takes the room the
//! protrusions, kept at their size, do not. Along each axis the room goes by a piecewise-linear profile over
//! 64 slabs, most where the rest's surface lies across the axis (its faces keep their shape under a stretch
//! along their normal), at least a tenth of a uniform share elsewhere; one factor per axis scales it (secant
//! steps). \return nothing when the factors do not settle within (0.2, 5) in 20 steps
//! (no room: the protrusions cannot be held at their size in the box; cheburashka ×2 x and ×2 y).
std::optional<MatrixX3d> fit_box_around_protrusions(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& B,
                                                    const Vec3& lo, const Vec3& hi,
                                                    const std::vector<RigidProtrusion>& protrusions);

//! The share of what is not a protrusion that is important: the area of the faces of \p mesh at \p X not
//! inside a protrusion whose mean weight \p f (#V in [0, 1]) is at least 1/2, over the area of all those faces.
//! The room fit_box_around_protrusions() makes is one factor per axis over all of them, so it is only given
//! where at most half of them are important (the tentacle stick's body: 0.29 at level 1, 0.43 at level 0;
//! the tentacle plane 0.01; cheburashka's head and body 0.92; bench/resize.md, twelfth session).
double important_share_of_rest(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& f,
                               const std::vector<RigidProtrusion>& protrusions);

}  // namespace geotex
