#pragma once

#include "geotex/core/progress.h"
// Pieces shared by the one-disk transfer (texture_transfer.cpp) and the atlas (texture_atlas.cpp).

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "geotex/core/spatial.h"
#include "geotex/texture/transfer.h"

namespace geotex::detail {

//! #F by 3: the unit 3D image of the uv direction +u in each face of \p mesh mapped to \p uv.
MatrixX3d face_u_directions(const Mesh& mesh, const MatrixX2d& uv);
//! #V by 3: the sum of the incident faces' \p face_e1 (a tangent hint per vertex; not normalised).
MatrixX3d vertex_u_directions(const Mesh& mesh, const MatrixX3d& face_e1);
//! 1 inside, smoothstep to 0 over the unit-disk radius [1 − width, 1] (width 0: 1 up to the rim).
double smoothstep_falloff(double radius, double width);
//! A local displacement (x, y, z in (e1, e2, n)) with its length and its lean from ±n both times \p w.
Vec3 fade(const Vec3& d, double w);
//! Per face of \p mesh's connectivity at positions \p P (#V by 3): 1 where it is folded (folded_faces()'s
//! test: its normal against the sum of its neighbours') or crossed by an edge of a non-adjacent face
//! (self_intersecting_faces(), core/self_intersections.h), else 0.
std::vector<char> damaged_faces(const Mesh& mesh, const MatrixX3d& P);
//! What source heights are multiplied by: the rule's factor times \p scale.
double height_factor(HeightRule rule, double source_radius, double target_radius, double scale);

//! The source side of a transfer: its disk, the disk's map, a point locator in the unit disk and the
//! texture sampler.
struct SourceDisk {
  SourceDisk(const Mesh& base, const Texture& texture, int center, double radius, const Vec3& anchor,
             double rotation_deg, const HeatGeodesicOptions& geodesic, const TextureOptions& options);
  //! The source displacement at unit-disk coordinate \p z, in the local frame (+u, +v, n) there.
  Vec3 sample(const Eigen::Vector2d& z) const;
  //! The area-weighted mean of the displacements over the disk, in the local frames (+u, +v, n).
  Vec3 mean_local() const;

  TextureSampler sampler;
  DiskPatch patch;
  MatrixX2d uv;
  MatrixX3d e1;         // per patch face: +u
  MatrixX3d e1_vertex;  // per patch vertex: the sum of its faces' +u (a tangent hint)
  std::unique_ptr<TriangleTree> tree;
  std::vector<std::array<int, 3>> perm;  // patch face corner k is base face corner perm[f][k]
  double mean_edge = 0;
};

//! Refine \p target in \p region (non-zero values) when its mean edge there exceeds \p ratio ×
//! \p required_edge; \return the warning line (empty when nothing was refined) and the count in \p added;
//! \p refined_region (if given) receives RefineResult::region (the region's values carried to new vertices:
//! the smaller of their edge's ends'), or \p region itself when nothing was refined.
std::string refine_for(Mesh& target, const std::vector<char>& region, double required_edge, double ratio,
                       size_t* added, const ProgressFn& progress = {}, std::vector<char>* refined_region = nullptr);

//! What refine_for() would do, without doing it: whether it refines, and the vertices it needs in the region
//! (about area / (edge² √3/4) at edges of 0.8 × \p required_edge, at least one per edge-length step).
struct RefineNeed {
  bool refine = false;
  double mean_edge = 0;      //!< mean edge in the region now
  double needed = 0;         //!< vertices the region needs (0 without refinement)
  size_t region_vertices = 0;  //!< vertices in the region now
};
RefineNeed refine_need(const Mesh& target, const std::vector<char>& region, double required_edge, double ratio);

}  // namespace geotex::detail
