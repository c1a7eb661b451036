#pragma once
//! \file measures.h How well a texture survived a deformation or a transfer: protrusion length and
//! lean, folded faces, height statistics, height steps. Used by the tests, the demo and the benchmarks.

#include <vector>

#include "geotex/core/mesh.h"
#include "geotex/texture/transfer.h"

namespace geotex {

//! A protrusion (a tentacle, a spike) measured at its foot vertex v: tip = the textured position of v,
//! foot = the base position of v (for the generated shapes the footprint's centre becomes the tip).
struct Protrusion {
  double length = 0;           //!< ‖tip − foot‖
  double lean_deg = 0;         //!< angle between tip − foot and the base's vertex normal n at the foot
  Vec3 direction = Vec3::Zero();  //!< unit tangential part of tip − foot (zero when it points along n)
  Vec3 normal = Vec3::Zero();     //!< n: the base's angle-weighted vertex normal at the foot
};

//! Measure the protrusions at vertices \p feet of \p textured (#V by 3) over \p base (same connectivity).
std::vector<Protrusion> measure_protrusions(const Mesh& base, const MatrixX3d& textured, const std::vector<int>& feet);

//! The tangent vector \p v at a point with unit normal \p n0 turned by the rotation part R of the polar
//! decomposition J_t = R S of the tangent Jacobian J_t: T(n0) → T(n1) of a map with 3 × 3 Jacobian \p J
//! (J projected onto the tangent plane at \p n1): where a vector displacement stored in a frame carried
//! by the surface goes, stretch removed. The reference for a lean's direction after a deformation.
Vec3 polar_rotated(const Eigen::Matrix3d& J, const Vec3& n0, const Vec3& n1, const Vec3& v);

//! Faces folded over: the face's normal points against the (unnormalised) sum of its edge-neighbours'
//! normals. Crumpled texture folds; a smooth surface, however bent, does not. \return the count.
size_t folded_faces(const Mesh& mesh);

//! Statistics of a height field over a region (height_stats_linear(), height_stats_disk()).
struct HeightStats {
  double mean_abs = 0;  //!< area-weighted mean |h|
  double rms = 0;       //!< area-weighted root mean square of h
  double max_abs = 0;   //!< largest |h|
  double area = 0;      //!< area counted
};
//! Statistics of the piecewise-linear height field \p h (#V), integrated over the faces whose corners are
//! all in \p mask (|h| by a 16-point rule, h² exactly): what resampling at any density converges to.
//! Vertex statistics of a rough texture exceed these (linear interpolation between a peak and a trough
//! is lower than both), so compare a resampled texture with its source this way.
HeightStats height_stats_linear(const Mesh& base, const Eigen::VectorXd& h, const std::vector<char>& mask);

//! Statistics of the piecewise-linear heights \p h (one per vertex of \p disk) over the part of the
//! unit disk \p uv (#V by 2, e.g. TransferResult::target_uv) within radius \p radius, weighted by uv area:
//! two disks of a transfer sample the same function of z, so these agree up to resampling, whatever
//! area distortion the two conformal maps have (height_stats_linear() on the surfaces includes it).
HeightStats height_stats_disk(const Mesh& disk, const MatrixX2d& uv, const Eigen::VectorXd& h, double radius);

//! What a disk transfer kept (TransferResult against its source), by the measures the tests state.
struct TransferQuality {
  //! Relative change of the disk statistics (height_stats_disk) within |z| ≤ 1 − falloff, target
  //! against the source's heights times TransferResult::height_factor: what the transfer itself kept.
  double mean_change = 0, rms_change = 0, max_change = 0;
  //! The same on the surfaces (height_stats_linear over the vertices with |z| ≤ 1 − falloff): includes
  //! how differently the two conformal maps distort area.
  double surface_mean_change = 0, surface_rms_change = 0;
  double lean_change_deg = 0;  //!< |h|-weighted mean lean there, target − source (degrees)
  size_t folded = 0;           //!< folded faces of the textured target (folded_faces())
  size_t source_folded = 0;    //!< folded faces of the textured source
  //! Largest height step the rim falloff adds between neighbours, max |Δw| × |h̃| (h̃ the heights
  //! before the falloff), over the largest |h̃|.
  double falloff_step = 0;
  double rim_cliff = 0;  //!< largest |h| on the target patch's boundary over the largest |h̃|
};
//! \param options the options the transfer ran with (the falloff and texture options are read; the
//! transfer is run once more without the falloff, on the already refined target, for h̃).
TransferQuality transfer_quality(const Mesh& source_base, const Texture& source, const TransferResult& result,
                                 const TransferOptions& options);

//! Seams of an atlas: height slopes |Δh| / edge length across the borders between disks (edges whose
//! ends have different AtlasResult::owner) and within disks.
struct SeamQuality {
  double across99 = 0, across_max = 0;  //!< 99th percentile and maximum across borders
  double within99 = 0, within_max = 0;  //!< the same within disks
};
SeamQuality atlas_seams(const AtlasResult& result);

}  // namespace geotex
