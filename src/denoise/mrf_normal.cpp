// The face-normal variant of the MRF denoiser (thesis Sec. 6.5): faces are the sites, unit normals
// the labels, the edge process of Sec. 6.3.3 switches the smoothness off across ridges; the vertex
// positions are then fitted to the normal field with the update of Sun et al. 2007 (the thesis' [127],
// which uses Taubin's [141] least-squares formulation).

#include <algorithm>
#include <chrono>
#include <cmath>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/denoise/mrf.h"
#include "geotex/denoise/normal_fit.h"
#include "geotex/core/random.h"
#include "mrf_internal.h"

namespace geotex {

using namespace detail;

namespace {

inline Vec3 vec(const double* p) { return {p[0], p[1], p[2]}; }
inline void put(double* p, const Vec3& v) { p[0] = v[0], p[1] = v[1], p[2] = v[2]; }

// U_N = α Σ_f ‖n_f − n_f⁰‖² + Σ_e (1 − ε_e) ρ(‖n_f − n_g‖).
struct NormalProblem {
  const Topology& T;
  const double* n0;
  const double* w;
  double alpha;
  SmoothnessPotential rho;

  double pair(const Vec3& a, const Vec3& b) const {
    const double y2 = (a - b).squaredNorm();
    return rho == SmoothnessPotential::Quadratic ? y2 : std::sqrt(y2);
  }
  double value(const double* n) const {
    double U = 0;
#pragma omp parallel for schedule(static) reduction(+ : U) if (T.nE >= min_parallel)
    for (int e = 0; e < T.nE; ++e) {
      const int f0 = T.ef[2 * e], f1 = T.ef[2 * e + 1];
      if (f0 >= 0 && f1 >= 0 && w[e] != 0) U += w[e] * pair(vec(n + 3 * f0), vec(n + 3 * f1));
    }
    double L = 0;
#pragma omp parallel for schedule(static) reduction(+ : L) if (T.nF >= min_parallel)
    for (int f = 0; f < T.nF; ++f) L += (vec(n + 3 * f) - vec(n0 + 3 * f)).squaredNorm();
    return U + alpha * L;
  }
  // Terms of U_N that involve n_f, with n_f = m.
  double local(int f, const Vec3& m, const double* n) const {
    double U = alpha * (m - vec(n0 + 3 * f)).squaredNorm();
    for (int k = 0; k < 3; ++k) {
      const int e = T.fe[3 * f + k];
      const int g = T.ef[2 * e] == f ? T.ef[2 * e + 1] : T.ef[2 * e];
      if (g >= 0 && w[e] != 0) U += w[e] * pair(m, vec(n + 3 * g));
    }
    return U;
  }
  // Conditional mode of site f: the unit vector maximizing m · (α n_f⁰ + Σ ω_g n_g), exact for the
  // quadratic potential; for the square-root one, one reweighted step (ω = w / 2‖n_f − n_g‖).
  Vec3 mode(int f, const double* n) const {
    Vec3 s = alpha * vec(n0 + 3 * f);
    const Vec3 nf = vec(n + 3 * f);
    for (int k = 0; k < 3; ++k) {
      const int e = T.fe[3 * f + k];
      const int g = T.ef[2 * e] == f ? T.ef[2 * e + 1] : T.ef[2 * e];
      if (g < 0 || w[e] == 0) continue;
      const Vec3 ng = vec(n + 3 * g);
      double omega = w[e];
      if (rho == SmoothnessPotential::SquareRoot) omega /= 2.0 * std::max((nf - ng).norm(), 1e-3);
      s += omega * ng;
    }
    const double len = s.norm();
    return len > 1e-300 ? Vec3(s / len) : nf;
  }
};

// ICM with every face updated from the previous configuration (Sec. 4.3.1); if that raises U_N,
// a sweep over colour classes (neighbouring faces never share a class) replaces it.
double normal_icm(const NormalProblem& P, std::vector<double>& n) {
  const double U0 = P.value(n.data());
  std::vector<double> next(n.size());
#pragma omp parallel for schedule(static) if (P.T.nF >= min_parallel)
  for (int f = 0; f < P.T.nF; ++f) put(&next[3 * f], P.mode(f, n.data()));
  const double U = P.value(next.data());
  if (U <= U0) {
    n.swap(next);
    return U;
  }
  for (const auto& cls : P.T.face_colours()) {
#pragma omp parallel for schedule(static) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int f = cls[k];
      const Vec3 m = P.mode(f, n.data());
      if (P.local(f, m, n.data()) <= P.local(f, vec(&n[3 * f]), n.data())) put(&n[3 * f], m);
    }
  }
  return P.value(n.data());
}

double normal_metropolis(const NormalProblem& P, std::vector<double>& n, double T, double step, uint64_t seed,
                         int sweep, double* acceptance) {
  long accepted = 0;
  for (const auto& cls : P.T.face_colours()) {
#pragma omp parallel for schedule(static) reduction(+ : accepted) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int f = cls[k];
      Rng rng(site_seed(seed, sweep, static_cast<uint64_t>(f) + (2ull << 40)));
      const Vec3 old = vec(&n[3 * f]);
      Vec3 m = old + step * Vec3(rng.normal(), rng.normal(), rng.normal());
      if (m.norm() < 1e-12) continue;
      m.normalize();
      const double dU = P.local(f, m, n.data()) - P.local(f, old, n.data());
      if (dU <= 0 || (T > 0 && rng.uniform() < std::exp(-dU / T))) {
        put(&n[3 * f], m);
        ++accepted;
      }
    }
  }
  if (acceptance) *acceptance = P.T.nF ? double(accepted) / P.T.nF : 0.0;
  return P.value(n.data());
}

// Sun et al. 2007, Eq. (8), on the flat (x, y, z interleaved) arrays of the solver (normal_fit.h).
void fit_vertices(const Topology& T, std::vector<double>& x, const std::vector<double>& n, int iterations) {
  using RowMajor3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMajor3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  const MatrixX3d X = Eigen::Map<const RowMajor3d>(x.data(), T.nV, 3);
  const MatrixX3d N = Eigen::Map<const RowMajor3d>(n.data(), T.nF, 3);
  const MatrixX3i F = Eigen::Map<const RowMajor3i>(T.F.data(), T.nF, 3);
  Eigen::Map<RowMajor3d>(x.data(), T.nV, 3) = fit_vertices_to_normals(F, X, N, iterations);
}

}  // namespace

MrfResult mrf_normal_denoise(const Mesh& mesh, const MrfNormalOptions& o) {
  require_valid(mesh, "input mesh");
  check_edge_options(o.edges);
  if (!(o.alpha >= 0) || !std::isfinite(o.alpha)) throw InvalidInput("alpha must be >= 0");
  if (o.optimizer != MrfOptimizer::Icm && o.optimizer != MrfOptimizer::Metropolis)
    throw InvalidInput("the normal process is optimized by icm or metropolis");
  if (!(o.temperature >= 0) || !std::isfinite(o.temperature)) throw InvalidInput("normal temperature must be >= 0");
  if (!(o.cooling > 0 && o.cooling <= 1)) throw InvalidInput("cooling factor must be in (0, 1]");
  if (!(o.step > 0) || !std::isfinite(o.step)) throw InvalidInput("Metropolis step must be > 0");
  if (o.iterations < 0 || o.normal_sweeps < 1 || o.vertex_iterations < 0 || o.rounds < 1)
    throw InvalidInput("iterations must be >= 0, sweeps and rounds >= 1");
  const auto t0 = std::chrono::steady_clock::now();
  const Topology T(mesh);
  const double h = mean_edge_length(mesh);
  if (!(h > 0)) throw InvalidInput("input mesh has zero mean edge length");
  std::vector<double> x = flat(positions(mesh), h);
  std::vector<double> n0(3 * T.nF), n(3 * T.nF), eps(T.nE, 0.0), w(T.nE, 1.0), prev;
  EdgeField field(T, o.edges);
  MrfResult r;
  int sweep_counter = 0, total = 0;
  double step = o.step;
  for (int round = 0; round < o.rounds; ++round) {
    compute_normals(T, x.data(), n0.data(), nullptr);
    n = n0;
    if (round == 0 && o.initial_labels_from_angles) {
      field.update(x.data(), n.data());
      field.opt.phi0_deg = annealed_phi0(o.edges, 0, o.iterations);
      field.initial_labels(eps.data());
    }
    const NormalProblem P{T, n0.data(), w.data(), o.alpha, o.potential};
    double Tn = o.temperature, Te = o.edges.temperature, U_prev = 0;
    bool quenched = false, quench_now = false;
    for (int it = 0; it < o.iterations; ++it) {
      // Edge process on the current normal field (angles between the filtered normals) ...
      field.update(x.data(), n.data());
      prev = eps;
      const bool last = it + 1 == o.iterations || quench_now;
      const double Ue =
          edge_step(field, o.edges, it, o.iterations, last, Te, o.seed, sweep_counter, eps.data(), quenched);
      for (int e = 0; e < T.nE; ++e) w[e] = 1.0 - eps[e];
      // ... then the normal process for the current labels.
      double Un = 0;
      for (int s = 0; s < o.normal_sweeps; ++s) {
        if (o.optimizer == MrfOptimizer::Icm) {
          Un = normal_icm(P, n);
        } else {
          double acc = 0;
          Un = normal_metropolis(P, n, Tn, step, o.seed, sweep_counter++, &acc);
          step *= acc < 0.15 ? 0.7 : acc > 0.35 ? 1.3 : 1.0;
          step = std::clamp(step, 1e-4, 1.0);
        }
      }
      Tn *= o.cooling;
      Te *= o.edges.cooling;
      const double changed = record_iteration(
          r, eps, prev, Un, Ue, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      r.iterations = ++total;
      report(o.progress, double(round * o.iterations + it + 1) / (o.rounds * o.iterations), "mrf-normal");
      const bool stable = it > 0 && changed < 1e-3 && std::abs(U_prev - Un) <= o.tolerance * std::abs(U_prev);
      U_prev = Un;
      if (stable && !quenched) {
        quench_now = true;
      } else if (stable) {
        r.converged = true;
        break;
      }
    }
    fit_vertices(T, x, n, o.vertex_iterations);
  }
  r.positions = unflat(x.data(), T.nV, h);
  r.edge_labels = Eigen::Map<Eigen::VectorXd>(eps.data(), eps.size());
  return r;
}

}  // namespace geotex
