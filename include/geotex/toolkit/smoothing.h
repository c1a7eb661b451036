#pragma once
//! \file smoothing.h Laplacian smoothing (thesis Sec. 5.1.3): explicit (forward Euler, Eq. 5.12–5.13)
//! and implicit (backward Euler, Eq. 5.14) steps with umbrella or cotangent weights.

#include <vector>

#include "geotex/toolkit/laplace.h"
#include "geotex/core/progress.h"

namespace geotex {

struct SmoothingOptions {
  LaplacianType laplacian = LaplacianType::Cotangent;  //!< umbrella (5.8) or cotangent (5.11)
  bool implicit = true;  //!< backward Euler (5.14), unconditionally stable; else forward Euler (5.12)
  //! Step size λ. Umbrella: dimensionless (explicit steps are stable for λ ≤ 1). Cotangent: in units
  //! of the squared mean edge length h², so the same λ smooths any scale alike (λ h² is a time of
  //! mean-curvature flow, whose sphere radius obeys r² = r0² − 4t). Explicit cotangent steps are stable
  //! only for λ ≲ 0.05; implicit steps for any λ.
  double lambda = 1.0;
  int steps = 1;                        //!< number of steps
  MassType mass = MassType::Voronoi;    //!< cotangent only: mass matrix (Thesis = Eq. 5.11 verbatim)
  bool fix_boundary = true;             //!< keep boundary vertices where they are (open meshes)
  //! After each step, scale about the centroid to restore the enclosed volume (closed meshes) or the
  //! surface area (open ones), and translate the centroid back: smoothing without shrinking.
  bool rescale = false;
  //! Cotangent implicit steps: recompute the weights on the current surface each step (true, the
  //! flow of Eq. 5.14) or keep the first step's matrix and factor it once for all steps (false).
  bool update_weights = true;
  //! Stop before \ref steps once a step moves no vertex by more than this many mean edge lengths
  //! (0: always run every step). The system is factored once either way (umbrella, or frozen weights).
  double stop_tolerance = 0;
  ProgressFn progress;  //!< called after each step
  static const OptionTable<SmoothingOptions>& table();
};

//! Smooth a mesh. \return #V by 3 new positions (vertex order and connectivity unchanged).
//! \throw InvalidInput for an empty mesh, non-finite coordinates, bad options; SolverError on failure.
MatrixX3d smooth(const Mesh& mesh, const SmoothingOptions& options = {});

//! One implicit cotangent step (Eq. 5.14, weights of the input) from the input for each step size in
//! \p lambdas (in squared mean edge lengths of each connected part): the same as smooth() with steps = 1,
//! cotangent weights and no rescale for each λ, with the cotangent matrix, the mass and the symbolic
//! analysis computed once for all. \return one #V by 3 position matrix per λ.
//! \throw InvalidInput for an invalid mesh or a λ outside [0, 1e9]; SolverError on failure.
std::vector<MatrixX3d> implicit_cotan_steps(const Mesh& mesh, const std::vector<double>& lambdas,
                                            MassType mass = MassType::Voronoi, bool fix_boundary = true);

//! Restore volume (closed) or area (open) and centroid of \p X to those of \p reference, in place.
void rescale_like(const Mesh& reference, Mesh& mesh);

}  // namespace geotex
