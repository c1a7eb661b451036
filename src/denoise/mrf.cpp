// MRF denoising with explicit sharp-edge labelling (thesis ch. 6; optimizers of ch. 4.3): the
// alternation of the edge process with a site process (Sec. 6.3.4–6.3.5), and its two uses,
//   mrf_denoise()         vertices are the sites, positions the labels (Sec. 6.3);
//   mrf_normal_denoise()  faces are the sites, unit normals the labels, then the vertices are fitted
//                         to the normals (Sec. 6.5).
// The processes themselves: mrf_vertex.cpp, mrf_normal.cpp, mrf_edge.cpp (internals: mrf_internal.h).

#include "geotex/denoise/mrf.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/progress.h"
#include "mrf_internal.h"

namespace geotex {

using namespace detail;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// How one alternation runs: the site process' sweeps and temperature, the edge process, the stopping rule.
struct Schedule {
  int iterations = 0;
  int sweeps = 1;             // site-process sweeps (or line searches) per outer iteration
  double temperature = 0;     // site-process start temperature (Metropolis)
  double cooling = 1;         // its factor per outer iteration
  double tolerance = 0;       // stop when labels are stable and the energy fell by less than this fraction
  const EdgeProcessOptions* edges = nullptr;
  uint64_t seed = 1;
  ProgressFn progress;
  const char* name = "";
  double progress_from = 0, progress_to = 1;
};

// Start labels ε_e = [φ_e > φ0] on the current geometry (Fig. 6.3: "initially labelled based only on the
// sharpness of the dihedral angle").
void initial_labels(SiteProcess& P, EdgeField& field, const Schedule& s, LabelState& L) {
  field.update(P.positions(), P.normals());
  field.opt.phi0_deg = annealed_phi0(*s.edges, 0, s.iterations);
  field.initial_labels(L.eps.data());
}

// After an outer iteration: append the energies, the labelled-edge count and the elapsed time to r,
// and return the largest label change since prev.
double record_iteration(MrfResult& r, const std::vector<double>& eps, const std::vector<double>& prev,
                        double site_energy, double edge_energy, double seconds) {
  double changed = 0;
  int labelled = 0;
  for (size_t e = 0; e < eps.size(); ++e) {
    changed = std::max(changed, std::abs(eps[e] - prev[e]));
    labelled += eps[e] > 0.5;
  }
  r.vertex_energy.push_back(site_energy);
  r.edge_energy.push_back(edge_energy);
  r.labelled.push_back(labelled);
  r.seconds.push_back(seconds);
  return changed;
}

// The coupled model (Sec. 6.3.4–6.3.5): in each outer iteration, the edge process for the current
// geometry (Eq. 6.12), then the site process for the current labels (Eq. 6.15), each at its own
// temperature, both cooled. Once labels are stable and the site energy no longer falls, one more
// iteration runs the edge process at T = 0 (the quench), and the alternation stops.
void alternate(SiteProcess& P, EdgeField& field, const Schedule& s, LabelState& L, MrfResult& r, Clock::time_point t0) {
  L.update_weights();
  double T_site = s.temperature, T_edge = s.edges->temperature, U_prev = P.energy();
  bool quenched = false, quench_now = false;
  std::vector<double> prev;
  for (int it = 0; it < s.iterations; ++it) {
    field.update(P.positions(), P.normals());
    prev = L.eps;
    const bool last = it + 1 == s.iterations || quench_now;
    const double Ue = edge_step(field, *s.edges, it, s.iterations, last, T_edge, s.seed, L.sweeps, L.eps.data(), quenched);
    L.update_weights();
    const double U = P.run(s.sweeps, T_site, true, L.sweeps);
    T_site *= s.cooling;
    T_edge *= s.edges->cooling;
    const double changed = record_iteration(r, L.eps, prev, U, Ue, seconds_since(t0));
    ++r.iterations;
    report(s.progress, s.progress_from + (s.progress_to - s.progress_from) * double(it + 1) / s.iterations, s.name);
    const bool stable = changed < 1e-3 && std::abs(U_prev - U) <= s.tolerance * std::abs(U_prev);
    U_prev = U;
    if (stable && !quenched) {
      quench_now = true;
    } else if (stable) {
      r.converged = true;
      break;
    }
  }
}

// Final labelling (MrfOptions::final_phi0_deg): ICM on Eq. (6.12) from ε = [φ > φ0] on the final geometry.
void relabel(SiteProcess& P, EdgeField& field, double phi0_deg, LabelState& L) {
  field.update(P.positions(), P.normals());
  field.opt.phi0_deg = phi0_deg;
  field.initial_labels(L.eps.data());
  std::vector<double> prev;
  for (int s = 0; s < 50; ++s) {
    check_interrupt();
    prev = L.eps;
    field.icm(L.eps.data());
    if (prev == L.eps) break;
  }
}

double unit_length(const Mesh& mesh) {
  const double h = mean_edge_length(mesh);
  if (!(h > 0)) throw InvalidInput("input mesh has zero mean edge length");
  return h;
}

}  // namespace

MrfResult mrf_denoise(const Mesh& mesh, const MrfOptions& o) {
  check_options(o);
  require_valid(mesh, "input mesh");
  const auto t0 = Clock::now();
  const Topology T(mesh);
  const double h = unit_length(mesh);
  const std::vector<double> x0 = flat(positions(mesh), h);
  LabelState L(T.nE);
  VertexProcess P(T, x0, L, o);
  EdgeField field(T, o.edges);

  Schedule s;
  s.iterations = o.iterations;
  s.sweeps = o.vertex_sweeps > 0 ? o.vertex_sweeps : o.optimizer == MrfOptimizer::Icm ? 2 : 5;
  s.temperature = o.temperature;
  s.cooling = o.cooling;
  s.tolerance = o.tolerance;
  s.edges = &o.edges;
  s.seed = o.seed;
  s.progress = o.progress;
  s.name = "mrf";
  if (o.initial_labels_from_angles) initial_labels(P, field, s, L);
  MrfResult r;
  alternate(P, field, s, L, r, t0);
  if (o.final_sweeps > 0) {
    // The minimum of U_V for the final labels (Eq. 6.15), reported as part of the last outer iteration.
    const double U = P.run(o.final_sweeps, 0.0, false, L.sweeps);
    if (!r.vertex_energy.empty()) {
      r.vertex_energy.back() = U;
      r.seconds.back() = seconds_since(t0);
    }
  }
  if (o.final_phi0_deg > 0) relabel(P, field, o.final_phi0_deg, L);
  r.positions = unflat(P.positions(), T.nV, h);
  // Coordinates near the double range (1e200) overflow the unit length: refuse, never return NaN (issue 14).
  if (!r.positions.allFinite()) throw InvalidInput("denoise: non-finite result (coordinates too large?)");
  r.edge_labels = Eigen::Map<const Eigen::VectorXd>(L.eps.data(), T.nE);
  return r;
}

Eigen::VectorXd label_sharp_edges(const Mesh& mesh, const MatrixX3d& X, const EdgeProcessOptions& options) {
  check_options(options);
  require_valid(mesh, "input mesh");
  const Topology T(mesh);
  if (X.rows() != T.nV) throw InvalidInput("label_sharp_edges: positions do not match the mesh");
  const double h = unit_length(mesh);
  LabelState L(T.nE);
  MrfNormalOptions o;  // a site process that only holds the geometry: positions and their face normals
  NormalProcess P(T, flat(X, h), L, o);
  P.begin_round();
  EdgeField field(T, options);
  relabel(P, field, options.phi0_deg, L);
  return Eigen::Map<const Eigen::VectorXd>(L.eps.data(), T.nE);
}

MrfResult mrf_normal_denoise(const Mesh& mesh, const MrfNormalOptions& o) {
  check_options(o);  // the normal process's optimizer is icm or metropolis (its table's choice)
  require_valid(mesh, "input mesh");
  const auto t0 = Clock::now();
  const Topology T(mesh);
  const double h = unit_length(mesh);
  LabelState L(T.nE);
  NormalProcess P(T, flat(positions(mesh), h), L, o);
  EdgeField field(T, o.edges);

  Schedule s;
  s.iterations = o.iterations;
  s.sweeps = o.normal_sweeps;
  s.temperature = o.temperature;
  s.cooling = o.cooling;
  s.tolerance = o.tolerance;
  s.edges = &o.edges;
  s.seed = o.seed;
  s.progress = o.progress;
  s.name = "mrf-normal";
  MrfResult r;
  for (int round = 0; round < o.rounds; ++round) {
    // Each round: the normal field of the current positions, the alternation, the vertex fit.
    P.begin_round();
    if (round == 0 && o.initial_labels_from_angles) initial_labels(P, field, s, L);
    s.progress_from = double(round) / o.rounds;
    s.progress_to = double(round + 1) / o.rounds;
    alternate(P, field, s, L, r, t0);
    P.fit_positions(o.vertex_iterations);
  }
  r.positions = unflat(P.positions(), T.nV, h);
  // Coordinates near the double range (1e200) overflow the unit length: refuse, never return NaN (issue 14).
  if (!r.positions.allFinite()) throw InvalidInput("denoise: non-finite result (coordinates too large?)");
  r.edge_labels = Eigen::Map<const Eigen::VectorXd>(L.eps.data(), T.nE);
  return r;
}

}  // namespace geotex
