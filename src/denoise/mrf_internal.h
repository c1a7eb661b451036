#pragma once
// Internals shared by mrf.cpp (vertex process, edge process) and mrf_normal.cpp (face-normal
// variant). Not installed.

#include <cstdint>
#include <vector>

#include "geotex/denoise/mrf.h"

namespace geotex::detail {

//! Loops shorter than this run on one thread (loops over colour classes or heavy sites: a tenth of it):
//! below it, OpenMP's fork/join costs more than the work, and far more when the cores are shared
//! with other processes. Tests lower it to check that results do not depend on the thread count.
inline int min_parallel = 50000;

//! Mesh connectivity as flat arrays.
struct Topology {
  explicit Topology(const Mesh& mesh);
  int nV = 0, nF = 0, nE = 0;
  std::vector<int> F;             //!< 3 nF corners
  std::vector<int> fe;            //!< 3 nF: edge from corner m to corner m+1
  std::vector<int> E;             //!< 2 nE: from, to of the edge's halfedge 0
  std::vector<int> ef;            //!< 2 nE: face of halfedge 0 (holds from → to), of halfedge 1; −1 on a boundary
  std::vector<int> vf_off, vf;    //!< vertex → incident corners (3 f + m), CSR
  std::vector<int> ve_off, ve;    //!< vertex → incident edges, CSR
  //! Colour classes: sites of one class are not MRF neighbours (built on first use).
  const std::vector<std::vector<int>>& vertex_colours() const;
  const std::vector<std::vector<int>>& edge_colours() const;
  const std::vector<std::vector<int>>& face_colours() const;

 private:
  mutable std::vector<std::vector<int>> vertex_colours_, edge_colours_, face_colours_;
};

uint64_t site_seed(uint64_t seed, uint64_t sweep, uint64_t site);
void compute_normals(const Topology& T, const double* x, double* n, double* inv_len);
std::vector<double> flat(const MatrixX3d& X, double scale);
MatrixX3d unflat(const double* x, int n, double scale);
void check_edge_options(const EdgeProcessOptions& o);
//! φ0 of outer iteration `it` under EdgeProcessOptions::phi0_start_deg.
double annealed_phi0(const EdgeProcessOptions& o, int it, int iterations);

//! U_V of Eq. (6.4) + (6.13) on flat positions (3 per vertex).
struct VertexProblem {
  VertexProblem(const Topology& T, const double* x0, const double* w, double alpha, SmoothnessPotential rho);
  double value(const double* x) const;                  //!< recomputes the normals
  double value_from_normals(const double* x) const;     //!< uses the normals of the last value()/value_grad()
  double value_grad(const double* x, double* g) const;
  //! The terms that change with x_a, with x_a = p; others from x, their normals from nrm.
  double local(int a, const Vec3& p, const double* x, const double* nrm, Vec3* grad) const;
  Vec3 local_minimize(int a, const double* x, const double* nrm, int steps) const;
  void update_normals_at(int a, const double* x, double* nrm) const;

  const Topology& T;
  const double* x0;
  const double* w;  //!< 1 − ε per edge
  double alpha;
  SmoothnessPotential rho;
  mutable std::vector<double> n, inv, dn, cg;
};

//! The edge process for a fixed geometry: dihedral angles and edge directions, Eq. (6.9–6.11).
struct EdgeField {
  EdgeField(const Topology& T, const EdgeProcessOptions& o);
  //! Angles from the face normals n (3 per face) and directions from x.
  void update(const double* x, const double* n);
  bool fixed(int e) const;  //!< boundary edges keep ε = 0
  double cos_theta(int e, int e2, int v) const;
  //! ∂U_E/∂ε_e = (φ0 − φ_e) − w Σ cos θ ε_e' (U_E is linear in each ε_e).
  double field(int e, const double* eps) const;
  double energy(const double* eps) const;
  void initial_labels(double* eps) const;
  double metropolis(double* eps, double temperature, uint64_t seed, int sweep) const;
  double icm(double* eps) const;
  double sweep(double* eps, MrfOptimizer optimizer, double temperature, uint64_t seed, int sweep_index) const;

  const Topology& T;
  EdgeProcessOptions opt;
  std::vector<double> phi, u;
};

//! One alternation's edge step (Sec. 6.3.5) in outer iteration \p it of \p iterations: the (annealed)
//! threshold φ0 of \p o, then o.sweeps sweeps at \p temperature, or ICM (T = 0) when \p last and
//! o.quench; sets \p quenched once ICM ran. \return U_E.
double edge_step(EdgeField& field, const EdgeProcessOptions& o, int it, int iterations, bool last, double temperature,
                 uint64_t seed, int& sweep_counter, double* eps, bool& quenched);

//! After an outer iteration: append the energies, the labelled-edge count and the elapsed time to
//! \p r, and return the largest label change since \p prev.
double record_iteration(MrfResult& r, const std::vector<double>& eps, const std::vector<double>& prev,
                        double vertex_energy, double edge_energy, double seconds);

}  // namespace geotex::detail
