#pragma once
// Internals of the MRF denoisers (thesis ch. 6), shared by
//   mrf.cpp           the alternation of the edge process with a site process (Sec. 6.3.4–6.3.5), and
//                     the two entry points mrf_denoise() and mrf_normal_denoise();
//   mrf_topology.cpp  connectivity as flat arrays, colour classes, face normals;
//   mrf_vertex.cpp    the vertex process (Eq. 6.4, 6.13) and its optimizers;
//   mrf_edge.cpp      the edge process (Eq. 6.9–6.11);
//   mrf_normal.cpp    the face-normal process (Sec. 6.5) and the vertex fit.
// Not installed.
//
// Data live in flat arrays in vertex / face / edge order (struct of arrays), positions in mean edge
// lengths; per-element sweeps are OpenMP loops that gather (never scatter), so results do not depend
// on the thread count. Random choices draw from an Rng seeded by (seed, sweep, site).

#include <chrono>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "geotex/denoise/mrf.h"

namespace geotex::detail {

//! Loops shorter than this run on one thread (loops over colour classes or heavy sites: a tenth of it):
//! below it, OpenMP's fork/join costs more than the work, and far more when the cores are shared
//! with other processes. Tests lower it to check that results do not depend on the thread count.
inline int min_parallel = 50000;

//! Vertices with more edges than this keep sums over their edges instead of visiting all of them for
//! each (edge colouring, edge support): per-vertex work stays linear in the valence.
constexpr int kHeavyValence = 32;

inline Vec3 vec(const double* p) { return {p[0], p[1], p[2]}; }
inline void put(double* p, const Vec3& v) { p[0] = v[0], p[1] = v[1], p[2] = v[2]; }

// ---------------------------------------------------------------------------------------------
// Topology (mrf_topology.cpp)

//! Mesh connectivity as flat arrays.
struct Topology {
  explicit Topology(const Mesh& mesh);
  int nV = 0, nF = 0, nE = 0;
  std::vector<int> F;             //!< 3 nF corners
  std::vector<int> fe;            //!< 3 nF: edge from corner m to corner m+1
  std::vector<int> E;             //!< 2 nE: from, to of the edge's halfedge 0
  std::vector<int> ef;            //!< 2 nE: face of halfedge 0 (holds from → to), of halfedge 1; −1 on a boundary
  std::vector<int> vf_off, vf;    //!< vertex → incident corners (3 f + m), CSR
  std::vector<int> vf_pos;        //!< 3 nF: position of corner c in its vertex's list: vf[vf_off[F[c]] + vf_pos[c]] == c
  std::vector<int> ve_off, ve;    //!< vertex → incident edges, CSR
  //! Colour classes: sites of one class are not MRF neighbours (built on first use).
  const std::vector<std::vector<int>>& vertex_colours() const;
  const std::vector<std::vector<int>>& edge_colours() const;
  const std::vector<std::vector<int>>& face_colours() const;

 private:
  mutable std::vector<std::vector<int>> vertex_colours_, edge_colours_, face_colours_;
};

uint64_t site_seed(uint64_t seed, uint64_t sweep, uint64_t site);
//! Unit normals n (3 per face) of positions x; \p inv_len (optional) receives 1/|N_f| (0 if degenerate).
void compute_normals(const Topology& T, const double* x, double* n, double* inv_len);
//! Positions as a flat array divided by \p scale, and back.
std::vector<double> flat(const MatrixX3d& X, double scale);
MatrixX3d unflat(const double* x, int n, double scale);

// ---------------------------------------------------------------------------------------------
// The site processes the edge process alternates with (mrf_vertex.cpp, mrf_normal.cpp)

//! The edge labels and the smoothness weights they give, shared by the driver and a site process.
struct LabelState {
  std::vector<double> eps;  //!< ε per edge
  std::vector<double> w;    //!< 1 − ε per edge (Eq. 6.13)
  int sweeps = 0;           //!< sweeps so far: with the seed and the site, the seed of each random choice
  explicit LabelState(int nE) : eps(nE, 0.0), w(nE, 1.0) {}
  void update_weights() {
    for (size_t e = 0; e < eps.size(); ++e) w[e] = 1.0 - eps[e];
  }
};

//! A process whose smoothness the edge labels switch off: the vertex process (Eq. 6.15) or the
//! face-normal process (Sec. 6.5). It reads the weights LabelState::w.
class SiteProcess {
 public:
  virtual ~SiteProcess() = default;
  //! Flat positions (3 per vertex, mean edge lengths): the edge directions of Eq. (6.10).
  virtual const double* positions() const = 0;
  //! Face normals (3 per face) the dihedral angles φ_e of Eq. (6.9) are measured on.
  virtual const double* normals() = 0;
  //! The process' energy for the current configuration and weights.
  virtual double energy() = 0;
  //! \p sweeps sweeps (or line searches) at \p temperature; Metropolis adapts its step when \p adapt.
  //! \return the energy.
  virtual double run(int sweeps, double temperature, bool adapt, int& sweep_counter) = 0;
};

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

//! One sweep (Metropolis, ICM) or \p sweeps line searches (CG, L-BFGS) of the vertex process.
double vertex_sweeps(const VertexProblem& P, Eigen::VectorXd& x, MrfOptimizer optimizer, int sweeps, double temperature,
                     double& step, bool adapt, uint64_t seed, int& sweep_counter, double rel_tol);

//! The vertex process of mrf_denoise(): positions x (mean edge lengths) from the data x0.
class VertexProcess final : public SiteProcess {
 public:
  VertexProcess(const Topology& T, const std::vector<double>& x0, const LabelState& labels, const MrfOptions& o);
  const double* positions() const override { return x_.data(); }
  const double* normals() override;
  double energy() override { return P_.value(x_.data()); }
  double run(int sweeps, double temperature, bool adapt, int& sweep_counter) override;

 private:
  const Topology& T_;
  const MrfOptions& o_;
  VertexProblem P_;
  Eigen::VectorXd x_;
  std::vector<double> n_;
  double step_;
};

//! The face-normal process of mrf_normal_denoise(): normals n from the data n0 of the current positions x.
class NormalProcess final : public SiteProcess {
 public:
  NormalProcess(const Topology& T, std::vector<double> x, const LabelState& labels, const MrfNormalOptions& o);
  //! A round: the data normals n0 from the current positions, and n = n0.
  void begin_round();
  //! Fit the positions to the normals n (Sun et al. 2007, Eq. 8).
  void fit_positions(int iterations);
  const double* positions() const override { return x_.data(); }
  const double* normals() override { return n_.data(); }
  double energy() override;
  double run(int sweeps, double temperature, bool adapt, int& sweep_counter) override;

 private:
  const Topology& T_;
  const LabelState& labels_;
  const MrfNormalOptions& o_;
  std::vector<double> x_, n0_, n_;
  double step_;
};

// ---------------------------------------------------------------------------------------------
// The edge process (mrf_edge.cpp)

//! φ0 of outer iteration `it` under EdgeProcessOptions::phi0_start_deg.
double annealed_phi0(const EdgeProcessOptions& o, int it, int iterations);

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
  //! The sums S_v = Σ_{e at v} (±u_e) ε_e (edges directed out of v) at the vertices of high valence, for \p eps.
  void gather(const double* eps) const;
  //! ε_e changed by \p delta: update the sums at its ends (edges of one colour share no vertex).
  void changed(int e, double delta) const;

  const Topology& T;
  EdgeProcessOptions opt;
  std::vector<double> phi, u;
  std::vector<int> heavy;                 //!< vertex → its slot in heavy_sum, −1 below kHeavyValence
  mutable std::vector<double> heavy_sum;  //!< 3 per slot: S_v (Eq. 6.10's support in O(1) per edge)
};

//! One alternation's edge step (Sec. 6.3.5) in outer iteration \p it of \p iterations: the (annealed)
//! threshold φ0 of \p o, then o.sweeps sweeps at \p temperature, or ICM (T = 0) when \p last and
//! o.quench; sets \p quenched once ICM ran. \return U_E.
double edge_step(EdgeField& field, const EdgeProcessOptions& o, int it, int iterations, bool last, double temperature,
                 uint64_t seed, int& sweep_counter, double* eps, bool& quenched);

}  // namespace geotex::detail
