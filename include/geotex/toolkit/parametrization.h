#pragma once
//! \file parametrization.h Parametrization of disk-topology meshes (thesis Sec. 5.4, Eq. 5.83–5.88):
//! discrete conformal (cotangent-harmonic) and discrete authalic maps with the boundary on a circle,
//! their combination, and the natural (free-boundary) conformal map, after Desbrun, Meyer and
//! Alliez, "Intrinsic parameterizations of surface meshes" (Eurographics 2002).
//!
//! Orientation. UVs are oriented like the mesh: a face whose vertices run counter-clockwise seen from
//! its normal side runs counter-clockwise in the (u, v) plane, so a valid map has every signed UV
//! area positive (see ParamQuality::flipped).

#include <filesystem>
#include <vector>

#include "geotex/core/options.h"
#include "geotex/core/mesh.h"

namespace geotex {

enum class ParamMethod {
  Conformal,        //!< discrete harmonic map, Eq. (5.84–5.88): weights cot α_ij + cot β_ij
  Authalic,         //!< discrete authalic map (DMA 2002): weights (cot γ_ij + cot δ_ij) / |x_i − x_j|²
  Combined,         //!< λ · conformal + (1 − λ) · authalic, λ = ParametrizationOptions::conformal_weight
  NaturalConformal  //!< free boundary: minimizes Dirichlet energy − UV area (DMA 2002 natural boundary)
};

//! "conformal", "authalic", "combined", "natural".
const EnumNames<ParamMethod>& param_method_names();

struct ParametrizationOptions {
  ParamMethod method = ParamMethod::Conformal;
  //! Combined: λ of Desbrun et al. (weight of the conformal energy; the authalic one gets 1 − λ).
  //! Authalic weights are made dimensionless by the mean squared edge length before mixing.
  double conformal_weight = 0.5;
  static const OptionTable<ParametrizationOptions>& table();
};

//! #V by 2 UV coordinates of a disk-topology mesh; boundary on the unit circle by arc length (except
//! NaturalConformal, normalised to the unit disk: centred on the boundary's centroid and scaled so the
//! farthest vertex is at radius 1). \throw InvalidInput if the mesh is not a disk (closed, several
//! boundary loops, several components, handles, isolated vertices); SolverError if a solve fails.
MatrixX2d parametrize(const Mesh& disk, const ParametrizationOptions& options = {});

//! Why \p mesh is not a disk, or an empty string if it is one (one component, one boundary loop,
//! Euler characteristic 1, no isolated vertices).
std::string disk_topology_problem(const Mesh& mesh);

//! Positions of the boundary loop on the unit circle, spaced by 3D arc length (Eq. 5.86's b_i).
//! \param loop vertex indices of the boundary loop in boundary_loops() order.
//! \return #loop by 2, oriented so that the interior lies to the left (counter-clockwise).
MatrixX2d boundary_on_circle(const Mesh& mesh, const std::vector<int>& loop);

//! Distortion of a parametrization.
struct ParamQuality {
  size_t flipped = 0;            //!< faces with a non-positive signed UV area
  double mean_angle_error_deg = 0;  //!< mean |angle in UV − angle in 3D| over all face corners
  double max_angle_error_deg = 0;
  //! area distortion: mean over faces (area-weighted) of |log((A_uv/ΣA_uv) / (A_3d/ΣA_3d))|
  double mean_log_area_ratio = 0;
};

//! Measure flips, angle and area distortion of \p uv (#V by 2) on \p mesh.
ParamQuality parametrization_quality(const Mesh& mesh, const MatrixX2d& uv);

//! Write the mesh as an OBJ with one `vt` per vertex (the UVs) and faces `f a/a b/b c/c`, atomically.
//! \throw IoError on failure, InvalidInput if uv has the wrong size.
void write_obj_with_uv(const Mesh& mesh, const MatrixX2d& uv, const std::filesystem::path& path);

}  // namespace geotex
