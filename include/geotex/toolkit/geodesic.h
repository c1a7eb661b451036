#pragma once
//! \file geodesic.h Geodesic distance by the heat method (Crane, Weischedel and Wardetzky, "Geodesics in
//! heat", ACM TOG 2013) on the cotangent Laplacian of laplace.h: diffuse heat from the sources for a
//! short time t, normalise its gradient, and recover the distance whose gradient that field is.
//!
//!  1. (M − t C) u = δ_sources                      (one backward-Euler heat step, Eq. 5.14's form)
//!  2. X_f = −∇u / ‖∇u‖ per face                       (∇u = (1/2A_f) Σ_i u_i n_f × e_i)
//!  3. C φ = ∇·X, ∇·X at i = ½ Σ_f [cot θ₁ (e₁·X_f) + cot θ₂ (e₂·X_f)]
//!  4. φ shifted so that the sources are at 0.
//! Both systems are factored once per mesh (HeatGeodesics), so each further set of sources costs two
//! back-substitutions. Boundaries get the natural (Neumann) condition.

#include <memory>
#include <vector>

#include "geotex/core/mesh.h"
#include "geotex/core/options.h"

namespace geotex {

struct HeatGeodesicOptions {
  //! Heat time t = time_factor × h², h the mean edge length (Crane et al. use 1: shorter is closer to
  //! the exact distance on good meshes, longer smoother on noisy ones).
  double time_factor = 1.0;
  static const OptionTable<HeatGeodesicOptions>& table();
};

//! Prefactored heat-method distance on one mesh.
class HeatGeodesics {
 public:
  //! \throw InvalidInput for an empty mesh or non-finite coordinates; SolverError if a factorization fails.
  explicit HeatGeodesics(const Mesh& mesh, const HeatGeodesicOptions& options = {});
  ~HeatGeodesics();
  HeatGeodesics(HeatGeodesics&&) noexcept;
  HeatGeodesics& operator=(HeatGeodesics&&) noexcept;

  //! Distance from the nearest of \p sources (vertex indices) to every vertex. \return #V distances;
  //! +∞ on components no source reaches. \throw InvalidInput for no source or one out of range.
  Eigen::VectorXd distance(const std::vector<int>& sources) const;
  Eigen::VectorXd distance(int source) const { return distance(std::vector<int>{source}); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! One-shot: HeatGeodesics(mesh, options).distance(sources).
Eigen::VectorXd heat_geodesic_distance(const Mesh& mesh, const std::vector<int>& sources,
                                       const HeatGeodesicOptions& options = {});

}  // namespace geotex
