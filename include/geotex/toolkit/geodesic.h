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

//! The heat-method distance from one source solved on a neighbourhood of it only, so that a caller asking
//! for many sources' distances within a radius (the atlas' disks) pays for each neighbourhood, not for the
//! whole mesh: the vertices within a bound of the source along edges (Dijkstra; a path along edges is never
//! shorter than the geodesic, so they hold the geodesic ball of that radius) and the faces between them,
//! as a mesh of its own, on which HeatGeodesics is factored and solved. The heat time is the whole mesh's
//! (time_factor × its mean edge²). Boundaries of the neighbourhood get the natural (Neumann) condition of
//! the Poisson step (C φ = ∇·X in its weak form, whose sources sum to 0 on any mesh): φ is then the
//! least-squares potential of the normalised heat gradient X over the neighbourhood, and X there is the
//! whole mesh's up to the heat's decay across the bound (one backward-Euler step decays as e^(−d/√t)), so
//! well inside the bound the distance is the whole mesh's within a small tolerance (geodesic_test).
class LocalHeatGeodesics {
 public:
  //! \p mesh must outlive this object (it is read again on every call); \p mean_edge sets the heat time
  //! (0: \p mesh's own mean edge). \throw InvalidInput for an empty mesh or non-finite coordinates.
  explicit LocalHeatGeodesics(const Mesh& mesh, const HeatGeodesicOptions& options = {}, double mean_edge = 0);

  //! A neighbourhood and the distances on it.
  struct Ball {
    Mesh mesh;                  //!< the neighbourhood's faces (a vertex with none is kept, isolated)
    std::vector<int> vertices;  //!< neighbourhood vertex → mesh vertex (the source first)
    Eigen::VectorXd distance;   //!< heat distance per neighbourhood vertex (+∞: an isolated one)
    Eigen::VectorXd path;       //!< distance along edges per neighbourhood vertex (≤ the bound)
  };
  //! The neighbourhood within \p bound (model units) of \p source along edges and the heat distance on it.
  //! \throw InvalidInput for a source out of range or a bound that is not positive.
  Ball distance(int source, double bound);
  //! The vertex of \p source's component farthest from it along edges (an extremity).
  int farthest(int source);

 private:
  //! Dijkstra from \p source up to \p bound: the vertices reached, nearest first, with their distances.
  std::vector<std::pair<int, double>> reach(int source, double bound);

  const Mesh& mesh_;
  HeatGeodesicOptions options_;
  double mean_edge_ = 0;
  std::vector<double> path_;  // scratch: distance along edges (+∞ where not reached), reset after each call
  std::vector<int> local_;    // scratch: mesh vertex → neighbourhood vertex (−1), reset after each call
  std::vector<int> face_seen_;  // scratch: the last call that took the face
  int calls_ = 0;
};

//! One-shot: HeatGeodesics(mesh, options).distance(sources).
Eigen::VectorXd heat_geodesic_distance(const Mesh& mesh, const std::vector<int>& sources,
                                       const HeatGeodesicOptions& options = {});

}  // namespace geotex
