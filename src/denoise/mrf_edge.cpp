// The edge process of the MRF denoiser (thesis Sec. 6.3.3): every edge carries a label ε ∈ [0, 1], how
// likely it lies on a ridge, and for a fixed geometry the labels lower
//   U_E(ε) = Σ_e (φ0 − φ_e) ε_e − w Σ_{pairs (e_ij, e_jk)} cos θ_ijk ε_ij ε_jk      Eq. (6.9–6.11),
// by Metropolis sampling with annealing (Sec. 6.3.5) or ICM. U_E is linear in each ε_e, so a site's
// conditional mode is 0 or 1 and a Metropolis step needs only the local field ∂U_E/∂ε_e.

#include <algorithm>
#include <cmath>

#include "geotex/core/error.h"
#include "geotex/core/progress.h"
#include "geotex/core/random.h"
#include "mrf_internal.h"

namespace geotex {
namespace detail {

double edge_step(EdgeField& field, const EdgeProcessOptions& o, int it, int iterations, bool last, double temperature,
                 uint64_t seed, int& sweep_counter, double* eps, bool& quenched) {
  field.opt.phi0_deg = annealed_phi0(o, it, iterations);
  const MrfOptimizer optimizer = last && o.quench ? MrfOptimizer::Icm : o.optimizer;
  quenched = quenched || optimizer == MrfOptimizer::Icm;
  double Ue = 0;
  for (int s = 0; s < o.sweeps; ++s) {
    check_interrupt();
    Ue = field.sweep(eps, optimizer, temperature, seed, sweep_counter++);
  }
  return Ue;
}

double annealed_phi0(const EdgeProcessOptions& o, int it, int iterations) {
  if (!(o.phi0_start_deg > o.phi0_deg)) return o.phi0_deg;
  const double ramp = std::max(1.0, 0.5 * iterations);
  const double t = std::min(1.0, it / ramp);
  return o.phi0_start_deg + t * (o.phi0_deg - o.phi0_start_deg);
}

EdgeField::EdgeField(const Topology& topology, const EdgeProcessOptions& o) : T(topology), opt(o) {
  phi.resize(T.nE);
  u.resize(3 * T.nE);
  heavy.assign(T.nV, -1);
  int slots = 0;
  for (int v = 0; v < T.nV; ++v)
    if (T.ve_off[v + 1] - T.ve_off[v] > kHeavyValence) heavy[v] = slots++;
  heavy_sum.assign(3 * slots, 0.0);
}

void EdgeField::gather(const double* eps) const {
  for (int v = 0; v < T.nV; ++v) {
    if (heavy[v] < 0) continue;
    Vec3 S = Vec3::Zero();
    for (int k = T.ve_off[v]; k < T.ve_off[v + 1]; ++k) {
      const int e = T.ve[k];
      if (eps[e] != 0) S += (T.E[2 * e] == v ? 1.0 : -1.0) * eps[e] * vec(&u[3 * e]);
    }
    put(&heavy_sum[3 * heavy[v]], S);
  }
}

void EdgeField::changed(int e, double delta) const {
  for (int s = 0; s < 2; ++s) {
    const int v = T.E[2 * e + s];
    if (heavy[v] < 0) continue;
    double* S = &heavy_sum[3 * heavy[v]];
    const double sign = s == 0 ? delta : -delta;  // e is directed out of its first vertex
    for (int d = 0; d < 3; ++d) S[d] += sign * u[3 * e + d];
  }
}

void EdgeField::update(const double* x, const double* n) {
#pragma omp parallel for schedule(static) if (T.nE >= min_parallel)
  for (int e = 0; e < T.nE; ++e) {
    const Vec3 a = vec(x + 3 * T.E[2 * e]), b = vec(x + 3 * T.E[2 * e + 1]);
    const Vec3 t = b - a;
    const double len = t.norm();
    const Vec3 ut = len > 0 ? Vec3(t / len) : Vec3::Zero();
    for (int d = 0; d < 3; ++d) u[3 * e + d] = ut[d];
    const int f0 = T.ef[2 * e], f1 = T.ef[2 * e + 1];
    if (f0 < 0 || f1 < 0) {
      phi[e] = 0;
      continue;
    }
    const Vec3 n0 = vec(n + 3 * f0), n1 = vec(n + 3 * f1);
    const Vec3 c = n0.cross(n1);
    const double angle = std::atan2(c.norm(), n0.dot(n1));
    // Face 0 holds the edge directed a → b; the fold is convex when (n0 × n1) points along a → b.
    const double signed_angle = c.dot(t) >= 0 ? angle : -angle;
    phi[e] = opt.ridges == RidgeSign::All ? angle : opt.ridges == RidgeSign::Convex ? signed_angle : -signed_angle;
  }
}

bool EdgeField::fixed(int e) const { return T.ef[2 * e] < 0 || T.ef[2 * e + 1] < 0; }

// cos θ between edge e directed into v and edge e2 directed out of v (Eq. 6.10's θ_ijk).
double EdgeField::cos_theta(int e, int e2, int v) const {
  const double s1 = T.E[2 * e + 1] == v ? 1.0 : -1.0;   // e's direction into v
  const double s2 = T.E[2 * e2] == v ? 1.0 : -1.0;      // e2's direction out of v
  return s1 * s2 * (u[3 * e] * u[3 * e2] + u[3 * e + 1] * u[3 * e2 + 1] + u[3 * e + 2] * u[3 * e2 + 2]);
}

double EdgeField::field(int e, const double* eps) const {
  const double phi0 = opt.phi0_deg * M_PI / 180.0;
  double support = 0;
  for (int s = 0; s < 2; ++s) {
    const int v = T.E[2 * e + s];
    if (heavy[v] >= 0) {
      // Σ_{e' ≠ e} cos θ ε_e' = s1 u_e·S_v + |u_e|² ε_e, with s1 = +1 when e is directed into v (cos_theta()).
      const Vec3 ue = vec(&u[3 * e]);
      support += (s == 1 ? 1.0 : -1.0) * ue.dot(vec(&heavy_sum[3 * heavy[v]])) + ue.squaredNorm() * eps[e];
      continue;
    }
    for (int k = T.ve_off[v]; k < T.ve_off[v + 1]; ++k) {
      const int e2 = T.ve[k];
      if (e2 == e || eps[e2] == 0) continue;
      support += cos_theta(e, e2, v) * eps[e2];
    }
  }
  return (phi0 - phi[e]) - opt.support_weight * support;
}

double EdgeField::energy(const double* eps) const {
  gather(eps);
  const double phi0 = opt.phi0_deg * M_PI / 180.0;
  double U = 0;
#pragma omp parallel for schedule(static) reduction(+ : U) if (T.nE >= min_parallel)
  for (int e = 0; e < T.nE; ++e) {
    if (eps[e] == 0) continue;
    // ε_e (φ0 − φ_e) + ½ ε_e × (pair terms of e): each pair is seen from both of its edges.
    const double h = field(e, eps);
    const double pairs = h - (phi0 - phi[e]);
    U += eps[e] * ((phi0 - phi[e]) + 0.5 * pairs);
  }
  return U;
}

void EdgeField::initial_labels(double* eps) const {
  const double phi0 = opt.phi0_deg * M_PI / 180.0;
  for (int e = 0; e < T.nE; ++e) eps[e] = !fixed(e) && phi[e] > phi0 ? 1.0 : 0.0;
}

double EdgeField::metropolis(double* eps, double temperature, uint64_t seed, int sweep) const {
  gather(eps);
  for (const auto& cls : T.edge_colours()) {
#pragma omp parallel for schedule(static) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int e = cls[k];
      if (fixed(e)) continue;
      Rng rng(site_seed(seed, sweep, static_cast<uint64_t>(e) + (1ull << 40)));
      const double proposal = rng.uniform();
      const double dU = (proposal - eps[e]) * field(e, eps);  // U_E is linear in ε_e
      if (dU <= 0 || (temperature > 0 && rng.uniform() < std::exp(-dU / temperature))) {
        changed(e, proposal - eps[e]);
        eps[e] = proposal;
      }
    }
  }
  return energy(eps);
}

double EdgeField::icm(double* eps) const {
  const double U0 = energy(eps);
  std::vector<double> next(eps, eps + T.nE);
#pragma omp parallel for schedule(static) if (T.nE >= min_parallel)
  for (int e = 0; e < T.nE; ++e) {
    if (fixed(e)) continue;
    const double h = field(e, eps);
    next[e] = h < 0 ? 1.0 : h > 0 ? 0.0 : eps[e];  // the conditional mode of a linear energy on [0, 1]
  }
  const double U = energy(next.data());
  if (U <= U0) {
    std::copy(next.begin(), next.end(), eps);
    return U;
  }
  gather(eps);
  for (const auto& cls : T.edge_colours()) {
#pragma omp parallel for schedule(static) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int e = cls[k];
      if (fixed(e)) continue;
      const double h = field(e, eps);
      const double mode = h < 0 ? 1.0 : h > 0 ? 0.0 : eps[e];
      changed(e, mode - eps[e]);
      eps[e] = mode;
    }
  }
  return energy(eps);
}

double EdgeField::sweep(double* eps, MrfOptimizer optimizer, double temperature, uint64_t seed, int sweep_index) const {
  if (optimizer == MrfOptimizer::Metropolis) return metropolis(eps, temperature, seed, sweep_index);
  if (optimizer == MrfOptimizer::Icm) return icm(eps);
  throw InvalidInput("the edge process is optimized by metropolis or icm, not " + to_string(optimizer));
}

}  // namespace detail

using namespace detail;

double edge_sharpness_potential(double phi, double phi0, double label, double* grad) {
  if (grad) *grad = phi0 - phi;
  return (phi0 - phi) * label;  // Eq. (6.9)
}

double edge_support_potential(const Vec3& xi, const Vec3& xj, const Vec3& xk, double label_ij, double label_jk,
                              double weight, Eigen::Vector2d* grad) {
  const Vec3 a = xj - xi, b = xk - xj;
  const double c = a.dot(b) / (a.norm() * b.norm());  // cos θ_ijk
  if (grad) *grad = Eigen::Vector2d(-weight * c * label_jk, -weight * c * label_ij);
  return -weight * c * label_ij * label_jk;  // Eq. (6.10), weighted as in (6.11)
}


double edge_energy(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& labels,
                   const EdgeProcessOptions& options) {
  check_options(options);
  const Topology T(mesh);
  if (X.rows() != T.nV || labels.size() != T.nE) throw InvalidInput("edge_energy: sizes do not match the mesh");
  const std::vector<double> x = flat(X, 1.0);
  std::vector<double> n(3 * T.nF);
  compute_normals(T, x.data(), n.data(), nullptr);
  EdgeField field(T, options);
  field.update(x.data(), n.data());
  return field.energy(labels.data());
}


double edge_process_sweep(const Mesh& mesh, const MatrixX3d& X, Eigen::VectorXd& labels,
                          const EdgeProcessOptions& options, double temperature, uint64_t seed, int sweep_index) {
  check_options(options);
  const Topology T(mesh);
  if (X.rows() != T.nV || labels.size() != T.nE) throw InvalidInput("edge_process_sweep: sizes do not match the mesh");
  const std::vector<double> x = flat(X, 1.0);
  std::vector<double> n(3 * T.nF);
  compute_normals(T, x.data(), n.data(), nullptr);
  EdgeField field(T, options);
  field.update(x.data(), n.data());
  return field.sweep(labels.data(), options.optimizer, temperature, seed, sweep_index);
}


}  // namespace geotex
