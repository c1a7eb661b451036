#pragma once
//! \file direction_field.h A smooth unit tangent direction field on a mesh that follows a guide
//! direction where it can: the minimiser of
//!
//!   E(z) = Σ_ij w_ij |z_i − r_ij z_j|² + λ Σ_i A_i |z_i − g_i|²,
//!
//! z_i ∈ ℂ the field at vertex i in a tangent basis of its own, r_ij the discrete Levi-Civita transport
//! from j's tangent plane to i's (the angle of edge ij in i's basis minus that of ji in j's, plus π),
//! w_ij the cotangent weights (clamped at 0), A_i the vertex areas, g_i the tangent part of the guide
//! at i (short where the guide is nearly normal: there the smoothness term fills in), λ = 1/ℓ² with ℓ
//! the smoothing length. The direction is z_i/|z_i|. One sparse Hermitian solve. After Knöppel,
//! Crane, Pinkall and Schröder, "Globally optimal direction fields" (ACM TOG 2013), their energy with
//! an alignment term (their Sec. 6), for a 1-direction field.

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

//! How a tangent direction field is made from a guide direction.
enum class FieldMethod {
  Smooth,     //!< the smooth field above (default): follows the guide, smooth where it is nearly normal
  Projected,  //!< the tangent part of the guide at each vertex (jumps where the guide is along the normal)
};
//! "smooth", "projected".
const EnumNames<FieldMethod>& field_method_names();

struct DirectionFieldOptions {
  FieldMethod method = FieldMethod::Smooth;
  //! Smooth: the smoothing length ℓ as a share of √(surface area): over shorter distances the field
  //! is smooth, over longer ones it follows the guide.
  double smoothing = 0.05;
  static const OptionTable<DirectionFieldOptions>& table();
};

//! A unit tangent field on \p mesh following \p guide (#V by 3, or 1 by 3 for one direction
//! everywhere). \return #V by 3 unit tangent vectors (zero at isolated vertices); where the smooth
//! field vanishes (a singularity) or the guide's tangent part does (projected), the tangent part of
//! x, else y. \throw InvalidInput for a bad guide or options; SolverError if the solve fails.
MatrixX3d direction_field(const Mesh& mesh, const MatrixX3d& guide, const DirectionFieldOptions& options = {});

}  // namespace geotex
