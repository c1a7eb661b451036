#pragma once
//! \file transfer.h Texture transfer between surfaces (thesis Sec. 8.3.3).

#include <vector>

#include "geotex/texture/texture.h"

namespace geotex {

//! A disk-shaped piece of a mesh and where it came from.
struct DiskPatch {
  Mesh mesh;
  std::vector<int> vertices;  //!< patch vertex → original vertex
  std::vector<int> faces;     //!< patch face → original face
};

//! The faces within geodesic (edge-path) distance \p radius of vertex \p center, as a disk patch.
//! \throw InvalidInput if the centre is out of range or the result is not a disk (one boundary loop,
//! Euler characteristic 1).
DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius);

struct TransferOptions {
  int source_center = 0;       //!< source base vertex at the patch centre
  double source_radius = 0;    //!< geodesic radius of the source patch
  int target_center = 0;       //!< target base vertex at the patch centre
  double target_radius = 0;    //!< geodesic radius of the target patch
  double rotation_deg = 0;     //!< rotate the source disk by this angle before resampling
  int edge_samples = 5;        //!< samples per target edge for the tilt (the thesis uses 5)
  TextureOptions texture;      //!< normals used on both surfaces
};

struct TransferResult {
  Texture texture;             //!< on the whole target base (zero outside the patch)
  DiskPatch source_patch, target_patch;
  size_t target_vertices = 0;  //!< target vertices that received a height
};

TransferResult transfer_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                                const TransferOptions& options);

}  // namespace geotex
