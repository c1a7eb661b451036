#pragma once
//! \file transfer.h Texture transfer between surfaces (thesis Sec. 8.3.3), in three layers:
//!  - sampling: read a texture anywhere on its base as a displacement in a local frame
//!    (TextureSampler), and apply per-vertex displacements given in local frames to a target
//!    (texture_from_local());
//!  - disks: geodesic disks (heat-method distance) mapped conformally to the unit disk with the centre
//!    at 0 and an anchor direction along +u (DiskMap);
//!  - transfer of one disk (transfer_texture()) and covering a whole surface with overlapping disks
//!    (cover_with_texture()).
//!
//! The rules a transfer follows, stated once:
//!  - position: a target point at unit-disk coordinate z takes the source's texture at the same z;
//!  - orientation: the source's anchor direction (TransferOptions::source_direction, projected onto the
//!    tangent plane at the source centre) goes to the target's (target_direction), never by vertex order;
//!  - heights: in units of the patch radius (HeightRule::PatchRadius: h_target = h_source × R_target /
//!    R_source, so texture elements keep their proportions), times height_scale; the lean (the angle
//!    from the normal) is kept, its direction turned with the local frame (conformal maps keep angles);
//!  - rim: heights fade to 0 at the patch boundary over the outer `falloff` part of the radius
//!    (smoothstep in the unit-disk radius |z|), so no cliff is left;
//!  - resolution: where the target is coarser than the source patch (scaled to it), the target patch is
//!    refined first (refine.h), and TransferResult::warnings says so.

#include <string>
#include <vector>

#include "geotex/texture/texture.h"
#include "geotex/toolkit/geodesic.h"

namespace geotex {

// ---------------------------------------------------------------------------------------------
// Sampling

//! Reads a texture anywhere on its base as displacement vectors: the per-vertex displacements are
//! decoded once (Eq. 8.8) and interpolated linearly in each face (the textured surface is the
//! piecewise-linear surface through the displaced vertices).
class TextureSampler {
 public:
  //! \throw InvalidInput if the texture does not match the base.
  TextureSampler(const Mesh& base, const Texture& texture, const TextureOptions& options = {});

  //! The displacement at barycentric coordinates \p bary of \p face (corners in faces(base) order),
  //! in the local frame (e1, e2, n): n the interpolated vertex normal, e1 the tangent part of \p e1_hint,
  //! e2 = n × e1. Its z is the signed height, atan2(‖(x, y)‖, |z|) the lean (Eq. 8.5, 8.8).
  Vec3 sample(int face, const Vec3& bary, const Vec3& e1_hint) const;
  //! The same at a vertex, in the frame (e1, e2, n_i).
  Vec3 sample_vertex(int vertex, const Vec3& e1_hint) const;

  const Mesh& base() const { return base_; }
  const MatrixX3d& displacements() const { return D_; }  //!< #V by 3, in world coordinates
  const MatrixX3d& normals() const { return N_; }        //!< #V by 3 base vertex normals

 private:
  Mesh base_;
  MatrixX3i F_;
  MatrixX3d D_, N_;
};

//! A tangent frame: e1 = the tangent part of \p e1_hint at normal \p n, normalised; e2 = n × e1
//! (another tangent when e1_hint is along n). \return the 3 × 3 matrix [e1 e2 n].
Eigen::Matrix3d local_frame(const Vec3& n, const Vec3& e1_hint);

//! Apply a texture given per vertex of \p codec's base as displacements \p local (#V by 3) in the
//! frames (e1_i, e2_i, n_i), e1_i the tangent part of \p e1 (#V by 3, one hint per vertex): the
//! texture whose displacements are x e1 + y e2 + z n (Eq. 8.4–8.7).
Texture texture_from_local(TextureCodec& codec, const MatrixX3d& local, const MatrixX3d& e1);

// ---------------------------------------------------------------------------------------------
// Geodesic disks

//! A disk-shaped piece of a mesh and where it came from.
struct DiskPatch {
  Mesh mesh;
  std::vector<int> vertices;  //!< patch vertex → original vertex
  std::vector<int> faces;     //!< patch face → original face
  int center = -1;            //!< the centre as a patch vertex
  Eigen::VectorXd distance;   //!< geodesic distance of each patch vertex from the centre
};

//! The faces whose three corners lie within \p distance ≤ \p radius (a geodesic distance from \p center,
//! #V values, e.g. from HeatGeodesics) and that are connected across edges to the centre's, with the
//! holes they enclose filled when every vertex of a hole lies within the radius plus twice the hole's
//! longest edge (a distance that wobbles by a fraction of an edge leaves pin-holes), as a disk patch.
//! \throw InvalidInput if the centre is out of range or the result is not a disk (one boundary loop,
//! Euler characteristic 1).
DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius, const Eigen::VectorXd& distance);
//! The same with the heat-method distance from \p center (toolkit/geodesic.h).
DiskPatch extract_disk_patch(const Mesh& mesh, int center, double radius);

//! The vertex of \p mesh nearest to \p point (a patch centre given by a point rather than a vertex id).
//! \throw InvalidInput for a mesh without vertices or a non-finite point.
int nearest_vertex(const Mesh& mesh, const Vec3& point);

//! A disk patch on the unit disk: the discrete conformal map with the boundary on the circle (Eq. 5.85),
//! moved by the Möbius transformation z ↦ (z − a)/(1 − ā z) that takes the centre to 0 (conformal, the
//! circle stays the circle), and turned so that the anchor direction at the centre points along +u.
struct DiskMap {
  MatrixX2d uv;  //!< #patch vertices by 2, in the closed unit disk; the centre at (0, 0)
  //! #patch faces by 3 (per face): the 3D image of the uv direction +u in the face's plane, unit
  //! (the local frames' e1; e2 = n × e1 is then +v, the map being conformal).
  MatrixX3d e1;
};

//! \param anchor any 3D direction; its tangent part at the centre points along +u (when it is along the
//! normal, the tangent part of x, else of y, is used). \throw InvalidInput, SolverError (parametrize()).
DiskMap disk_map(const DiskPatch& patch, const Vec3& anchor);

// ---------------------------------------------------------------------------------------------
// Damage

//! What a texture did to its base: faces folded over (folded_faces(), measures.h) and faces crossed by
//! an edge of a non-adjacent face (self_intersecting_faces(), core/self_intersections.h) on the textured
//! surface, against the bare base's own (the same connectivity).
struct TextureDamage {
  size_t folded = 0, base_folded = 0;
  size_t self_intersecting = 0, base_self_intersecting = 0;
  size_t excess_folded() const { return folded > base_folded ? folded - base_folded : 0; }
  size_t excess_self_intersecting() const {
    return self_intersecting > base_self_intersecting ? self_intersecting - base_self_intersecting : 0;
  }
};
//! The damage of \p textured (#V by 3 positions over \p base's faces) against \p base.
TextureDamage texture_damage(const Mesh& base, const MatrixX3d& textured);
//! A warning line when the excess folded or self-intersecting faces exceed \p threshold, else empty.
std::string damage_warning(const TextureDamage& damage, size_t threshold);

// ---------------------------------------------------------------------------------------------
// Transfer of one disk

//! How heights are carried from the source to the target.
enum class HeightRule {
  PatchRadius,  //!< h_target = h_source × target_radius / source_radius (texture keeps its proportions)
  Absolute,     //!< model units, as in the thesis (a large source on a small target blows it apart)
};
//! "patch-radius", "absolute" (also "thesis").
const EnumNames<HeightRule>& height_rule_names();

struct TransferOptions {
  int source_center = 0;       //!< source base vertex at the patch centre
  double source_radius = 0;    //!< geodesic radius of the source patch (model units of the source)
  int target_center = 0;       //!< target base vertex at the patch centre
  double target_radius = 0;    //!< geodesic radius of the target patch (model units of the target)
  //! Anchor directions: the tangent part of source_direction at the source centre maps to the tangent
  //! part of target_direction at the target centre (a second point q gives the direction q − centre).
  Vec3 source_direction = Vec3::UnitX();
  Vec3 target_direction = Vec3::UnitX();
  double rotation_deg = 0;     //!< then turn the source by this angle about its centre (counter-clockwise)
  HeightRule height_rule = HeightRule::PatchRadius;
  double height_scale = 1.0;   //!< multiply the heights by this, on top of the height rule
  //! Width of the rim falloff, as a share of the radius: heights fade to 0 at the boundary by a
  //! smoothstep over |z| ∈ [1 − falloff, 1] (0: no falloff, a cliff at the rim), and the lean by its
  //! square (a feature cut by the rim fades shorter and more upright, so its overhangs cannot fold).
  //! The step the falloff adds between neighbours is at most 1.5 × edge / (falloff × radius) of the
  //! texture's height (smoothstep's steepest slope).
  double falloff = 0.4;
  //! Refine the target patch when its mean edge there exceeds refine_ratio × the source patch's mean
  //! edge scaled to the target (so that no detail is lost): every edge longer than 0.8 × the scaled
  //! source edge is split (longest first), leaving a mean of about 0.6 of it. 0: never refine.
  double refine_ratio = 1.0;
  //! Warn when the textured target has more than this many folded or self-intersecting faces beyond
  //! the bare target's own (TransferResult::damage).
  int damage_warning = 0;
  HeatGeodesicOptions geodesic;  //!< geodesic distance on both surfaces
  TextureOptions texture;        //!< decoding the source, encoding the target
  ProgressFn progress;           //!< called after each stage (source disk, target disk, map, encoding)
  //! Table; preset "thesis": absolute heights, no falloff, no refinement, the one-form encoding.
  static const OptionTable<TransferOptions>& table();
};

struct TransferResult {
  //! The target base actually used: the input target, refined in the patch when it was coarser (its
  //! first vertices are the input's, in order; new vertices follow). Apply the texture to this mesh.
  Mesh target;
  Texture texture;             //!< on \ref target (zero outside the patch)
  DiskPatch source_patch, target_patch;
  int source_center = -1, target_center = -1;  //!< the patches' centres (source base, target vertices)
  MatrixX2d source_uv, target_uv;  //!< the patches' unit-disk coordinates (DiskMap::uv; the rotation applied)
  size_t target_vertices = 0;  //!< target vertices that received a height (the target patch's)
  size_t added_vertices = 0;   //!< vertices the refinement added to the target
  double height_factor = 1;    //!< what the source heights were multiplied by (rule × height_scale)
  Eigen::VectorXd falloff;     //!< #V of \ref target: the rim weight (1 inside, 0 at the rim and outside)
  TextureDamage damage;        //!< of the textured target against \ref target's own
  std::vector<std::string> warnings;  //!< one line each (the target was refined, damage, …)
};

//! Transfer the texture of a geodesic disk of \p source_base to a geodesic disk of \p target_base
//! (Sec. 8.3.3) by the rules in the file comment. \throw InvalidInput for a bad centre or radius, or
//! a patch that is not a disk.
TransferResult transfer_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                                const TransferOptions& options);

// ---------------------------------------------------------------------------------------------
// Whole-surface transfer: an atlas of overlapping disks

//! How overlapping disks share a vertex.
enum class AtlasOverlap {
  Cut,    //!< each vertex takes one disk's displacement, the borders minimum cuts of the overlaps (feathered)
  Blend,  //!< the disks' displacements averaged with weights (ghosts: unrelated features mixed)
};
//! "cut", "blend".
const EnumNames<AtlasOverlap>& atlas_overlap_names();

struct AtlasOptions {
  int source_center = 0;        //!< source base vertex at the centre of the texture patch
  double source_radius = 0;     //!< geodesic radius of the source patch
  Vec3 source_direction = Vec3::UnitX();  //!< the source's anchor direction (see TransferOptions)
  //! Geodesic radius of each target disk (0: the source radius: texture elements keep their size).
  double target_radius = 0;
  //! Orientation field on the target: each disk's anchor is the tangent part of this direction at its
  //! centre (where it is along the normal, that of the second axis); a texture with a grain keeps it.
  Vec3 target_direction = Vec3::UnitX();
  //! Disk centres are placed (farthest-point sampling, geodesic) until every vertex lies within
  //! spacing × target_radius of one; smaller is more overlap.
  double spacing = 0.6;
  //! overlap = blend: disk k weighs b_k = (1 − |z_k|²)² at a vertex with disk coordinate z_k (1 at its centre,
  //! 0 at its rim), and the disks covering a vertex are averaged with weights b_k^p / Σ_j b_j^p. The
  //! disk whose centre is nearest dominates; between two neighbours the blend is about 1.7/p of the
  //! radius wide (large p: nearly a cut, steeper at the borders; at 8 the 99th percentile of |Δh|/edge
  //! across borders was 12 % above that inside disks on a bump texture, at 4 equal to it). The blend
  //! keeps the texture's contrast: Σ w̃_k M_k + Σ w̃_k (D_k − M_k) / √(Σ w̃_k²), M_k the source's mean
  //! displacement (a plain average of two unrelated pieces of texture has 1/√2 of their contrast).
  double blend_power = 4.0;
  //! Overlaps: cut (the default) pastes the disks in the order they are placed, each along a minimum cut
  //! of its overlap with those before (Kwatra et al. 2003, as synthesis does: the border runs where the
  //! two displacements agree, so a feature is copied whole from one disk). A disk's rim slices the
  //! source's features, so a cut also pays for pasting (or keeping) relief beyond |z| = spacing, by a
  //! smoothstep up to the rim: each vertex goes to a disk that has it whole. A disk inside the area
  //! already covered takes only what it improves (nothing forces its centre in: a lone vertex would be a
  //! needle). blend averages them (above), which mixes unrelated parts of the source: ghosted features,
  //! and spikes that cross.
  AtlasOverlap overlap = AtlasOverlap::Cut;
  int feather = 1;  //!< overlap = cut: rings on either side of a cut over which the two are mixed
  //! Shrink the displacements smoothly around every face the texture folds or makes cross another face
  //! (beyond the bare target's own) until none does: a spike that still crosses a neighbour is lowered
  //! as a whole (Gaussian dips of radius unfold_radius × target_radius about the damaged faces on the
  //! bare target, at most 40 rounds). Counted in AtlasResult::unfolded_vertices.
  bool unfold = true;
  double unfold_radius = 0.1;  //!< the dips' radius, as a share of target_radius
  HeightRule height_rule = HeightRule::PatchRadius;
  double height_scale = 1.0;
  double refine_ratio = 1.0;    //!< refine the target where coarser than this × the scaled source (0: never)
  int damage_warning = 0;       //!< warn above this many excess folded or self-intersecting faces (AtlasResult::damage)
  HeatGeodesicOptions geodesic;
  TextureOptions texture;
  ProgressFn progress;  //!< called after each disk with the share of the target covered ("disks"), then per unfolding round
  static const OptionTable<AtlasOptions>& table();
};

struct AtlasResult {
  Mesh target;                     //!< the target base used (refined where it was coarser)
  Texture texture;                 //!< on \ref target
  int source_center = -1;          //!< the source disk's centre (a source base vertex)
  std::vector<int> centers;        //!< disk centres (vertices of \ref target)
  //! #V: the largest disk weight b_k = (1 − |z_k|²)² at each vertex (0: no disk covers it; with
  //! spacing s, every vertex is within about s of a centre, so b ≳ (1 − s²)²)
  Eigen::VectorXd coverage;
  Eigen::VectorXi owner;           //!< #V: the disk with the largest weight there (−1: none)
  size_t added_vertices = 0;
  double height_factor = 1;
  //! Vertices whose displacement AtlasOptions::unfold shrank by over 1 %, and its rounds (0: nothing folded).
  size_t unfolded_vertices = 0;
  int unfold_rounds = 0;
  TextureDamage damage;            //!< of the textured target against \ref target's own
  std::vector<std::string> warnings;
};

//! Cover the whole of \p target_base with copies of one source disk (an atlas of geodesic disks, cut or
//! blended where they overlap): a step towards texture synthesis. \throw InvalidInput for bad options.
AtlasResult cover_with_texture(const Mesh& source_base, const Texture& source, const Mesh& target_base,
                               const AtlasOptions& options);

}  // namespace geotex
