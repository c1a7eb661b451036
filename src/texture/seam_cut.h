#pragma once
// Graph-cut seams between overlapping texture patches (Kwatra, Schödl, Essa, Turk and Bobick, "Graphcut
// textures", SIGGRAPH 2003), shared by what pastes patches over a canvas of per-vertex displacements: the
// atlas and synthesis (cut_paste) both paste through seam_cut().

#include <functional>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex::detail {

//! Maximum flow (Dinic: BFS levels, blocking flows by DFS) on a small graph; what graph-cut seams need.
class MaxFlow {
 public:
  explicit MaxFlow(int nodes);
  //! An edge a → b of capacity \p ab and its reverse of capacity \p ba.
  void add(int a, int b, double ab, double ba);
  //! \return the maximum flow from \p s to \p t.
  double run(int s, int t);
  //! After run(): the nodes reachable from \p s in the residual graph (the source side of a minimum cut).
  std::vector<char> source_side(int s) const;

 private:
  void link(int a, int b, double c);
  bool levels(int s, int t);
  double push(int a, int t, double f);
  std::vector<int> head_, level_, it_, to_, next_;
  std::vector<double> cap_;
};

//! Paste a patch over a canvas along a minimum cut of their overlap. On the overlap (patch vertices the
//! canvas already holds), the vertices next to written ones outside the patch keep the canvas' value,
//! those next to unwritten patch vertices take the patch's, and the border between the two runs along the
//! edges (a, b) of least |old − new|(a) + |old − new|(b), where the two agree. A patch the canvas holds
//! everywhere takes at least vertices[0] (its centre) when \p take_centre (synthesis must progress; an atlas,
//! whose disks cover the surface anyway, would paste a lone vertex of the patch: a needle). Data costs, when given, add to the cut what taking
//! the patch's value (\p cost_fresh) or keeping the canvas' (\p cost_old) costs at each overlap vertex
//! (e.g. a feature the patch's rim cuts through). The cut is then feathered over \p feather rings on
//! either side within the overlap (the mix goes from about ½ at the cut to all at `feather` rings).
//! \param mesh         the connectivity (vertex indices of \p vertices and \p written)
//! \param vertices     the patch's vertices, its centre first
//! \param fresh, old   per patch vertex: the patch's value, and the canvas' (read where written)
//! \param written      per mesh vertex: whether the canvas holds a value there
//! \param cost_fresh, cost_old  per patch vertex, or empty (none)
//! \return per patch vertex the share of the patch's value it takes (1 outside the overlap, 0: keeps the
//!         canvas', between: feathered)
std::vector<double> seam_cut(const Mesh& mesh, const std::vector<int>& vertices, const std::vector<Vec3>& fresh,
                             const std::vector<Vec3>& old, const std::function<bool(int)>& written, int feather,
                             const std::vector<double>& cost_fresh = {}, const std::vector<double>& cost_old = {},
                             bool take_centre = true);

}  // namespace geotex::detail
