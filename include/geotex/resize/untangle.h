#pragma once
//! \file untangle.h Self-intersections a resize adds beyond the input's own, and their repair: where the
//! result crosses itself and a safe result (the axis warp, monotone per axis and so injective, or the plain
//! stretch, an affine map) does not, the parts that cross are first moved apart (each crossing edge pushed off the
//! face it crosses, the pushes spread over the surface around them: fourteenth session), and what that leaves is
//! blended towards the safe result with a smooth bump around the crossing faces, widened until nothing crosses
//! beyond the input's own (issue 25, thirteenth session).

#include <cstddef>
#include <string>
#include <vector>

#include "geotex/core/mesh.h"
#include "geotex/core/progress.h"
#include "geotex/core/weld.h"

namespace geotex {

//! Faces crossed by an edge of a non-adjacent face (self_intersecting_faces(), core/self_intersections.h, the
//! ruler's faces_hit) in the input and in a resize's result, before and after untangle_resize().
struct UntangleReport {
  size_t base = 0;     //!< faces crossed in the input (its own)
  size_t before = 0;   //!< faces crossed in the result as the method made it
  size_t after = 0;    //!< faces crossed in the result returned
  size_t blended = 0;  //!< vertices moved towards the safe result (blend weight t > 0)
  int rounds = 0;      //!< blends tried (each widening the bump)
  size_t shifted = 0;  //!< vertices moved by the parts' shift apart (before any blend)
  int shift_rounds = 0;  //!< pushes applied
  size_t excess_before() const { return before > base ? before - base : 0; }
  size_t excess_after() const { return after > base ? after - base : 0; }
  //! "n faces intersected beyond the input's own; blended back over k vertices" (or "none …").
  std::string describe() const;
};

//! How untangle_resize() repairs: first move the parts that cross apart, each kept as it is (crossing edges pushed
//! off the faces they cross, the pushes spread over the surface around them), blending back only where that
//! leaves crossings; or blend back alone (the thirteenth session's repair).
enum class UntangleRepair { ShiftThenBlend, Blend };

//! Counts the faces \p Y crosses (against the input's own, \p X) and, when \p repair and \p Y crosses more faces
//! than X, some of which neither X nor \p safe crosses, repairs it (\p how). ShiftThenBlend first pushes each
//! crossing edge's end off the face it crosses (to the side its midpoint lies on in \p safe) and that face the other
//! way, by half the depth each, spreads the pushes over the surface (graph distance, a plateau of 4 edges, 0 at 12)
//! and repeats 8 times, keeping the round that crosses the fewest faces; what crosses then is blended. The blend
//! takes Y towards \p safe with weight t_i = a b(d_i): b = 1
//! within r of those faces' vertices (d_i the distance in the input), a smoothstep down to 0 at 3r (no crease);
//! a = 1/4, 1/2, 1 at each r, then r doubles from one mean edge length; faces crossed anew or turned over by a blend
//! join the seeds. After each blend Y is scaled per axis back onto the box of \p safe (an affine map: it adds no
//! crossing). Done when no more faces cross than in X, or those beyond are crossed in \p safe too; at the latest
//! \p safe itself. The vertices of \p ties (when given) move with their points after each shift and blend
//! (hold_ties(): a contact the solve held stays shut). \param X, Y, safe #V by 3 over \p mesh's faces.
//! \return #V by 3 positions.
MatrixX3d untangle_resize(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& Y, const MatrixX3d& safe, bool repair,
                          UntangleReport& counts, const ProgressFn& progress = {},
                          UntangleRepair how = UntangleRepair::ShiftThenBlend,
                          const std::vector<SurfaceTie>* ties = nullptr);

//! \p Y scaled per axis onto the bounding box of \p B (axes where either box is flat are left as they are): the
//! box fit the similarity stage and the repair end with (an affine map: it turns no face and adds no crossing).
void fit_box_onto(MatrixX3d& Y, const MatrixX3d& B);

}  // namespace geotex
