#pragma once
//! \file mesh_repair.h Soup-level repairs behind make_mesh()'s BuildOptions: drop the third face on
//! an edge, turn faces round to agree with their neighbours, split non-manifold vertices.

#include <array>
#include <vector>

#include "geotex/core/mesh.h"

namespace geotex::detail {

struct SoupRepair {
  std::vector<std::array<int, 3>> faces;  //!< kept faces, repaired (file order)
  int n_vertices = 0;                     //!< input vertices + copies
  std::vector<int> copy_of;               //!< for each appended vertex, the input vertex it copies
  size_t dropped_faces = 0;               //!< third (and later) faces on an edge
  size_t flipped_faces = 0;               //!< faces turned round
  size_t split_vertices = 0;              //!< input vertices that were split
};

//! \pre faces are non-degenerate, without duplicates (as sets), indices in [0, n_vertices).
SoupRepair repair_soup(int n_vertices, std::vector<std::array<int, 3>> faces, const BuildOptions& options);

}  // namespace geotex::detail
