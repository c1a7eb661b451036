#pragma once
//! \file refine.h Local refinement of a triangle mesh: longest-edge bisection restricted to a region,
//! with the new vertices placed on a smooth surface through the old ones (Phong tessellation,
//! Boubekeur and Alexa 2008, then bi-Laplacian fairing) so that a coarse mesh refined is not left faceted.
//!
//! OpenMesh's subdividers (Loop, √3, LongestEdgeT) refine the whole mesh; this uses the same edge-split
//! primitive (TriConnectivity::split) as LongestEdgeT, but only on the edges that touch the region.

#include <vector>

#include "geotex/core/mesh.h"
#include "geotex/core/progress.h"

namespace geotex {

struct RefineOptions {
  double max_edge = 0;     //!< split (longest first) every region edge longer than this (model units)
  //! Place a new vertex by Phong tessellation of its edge (shape factor 3/4, normals interpolated);
  //! false: at the edge's midpoint (the facets stay flat).
  bool smooth = true;
  //! Then fair the new vertices: minimise the umbrella bi-Laplacian energy ‖L X‖² over them with the
  //! old vertices fixed (a discrete thin plate through the old vertices, which also evens out their
  //! spacing: edges may end up slightly longer than max_edge). Phong tessellation alone leaves creases
  //! along the old edges, which tilt the normals of a texture applied on top (folds after a transfer).
  bool fair = true;
  size_t max_vertices = 5'000'000;  //!< stop splitting beyond this many vertices (a guard, not a target)
  //! Called every few thousand splits (fraction of \ref expected_added done) and around the fairing; a
  //! callback that throws stops the refinement (Ctrl-C in Python).
  ProgressFn progress;
  size_t expected_added = 0;  //!< vertices the caller expects to be added (for the progress fraction only)
};

struct RefineResult {
  Mesh mesh;              //!< the refined mesh: the input's vertices first, in order, then the new ones
  size_t added = 0;       //!< vertices added
  //! Per vertex of \ref mesh: the input's region value; a new vertex takes the smaller of its edge's two
  //! ends' (with flags 0/1: in the region when both ends are). Non-zero values all count as the region,
  //! so a caller can mark a sub-region with a larger value and learn which new vertices descend from it.
  std::vector<char> region;
  bool capped = false;    //!< RefineOptions::max_vertices stopped the refinement (then nothing is faired)
};

//! Split the edges longer than options.max_edge with at least one end in \p region (#V flags) until
//! none is left (before fairing). A new vertex is in the region when both ends of its edge are, so refinement stops one
//! ring outside. \throw InvalidInput for a bad size, max_edge ≤ 0 or an invalid mesh.
RefineResult refine_region(const Mesh& mesh, const std::vector<char>& region, const RefineOptions& options);

}  // namespace geotex
