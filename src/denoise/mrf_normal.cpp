// The face-normal process of the MRF denoiser (thesis Sec. 6.5): faces are the sites, unit normals the
// labels, and U_N(n) = α_n Σ_f ‖n_f − n_f⁰‖² + Σ_e (1 − ε_e) ρ(‖n_f − n_g‖) is lowered by ICM (closed-form
// site updates) or Metropolis sampling; the vertex positions are then fitted to the normal field with the
// update of Sun et al. 2007 (the thesis' [127], which uses Taubin's [141] least-squares formulation).

#include <algorithm>
#include <cmath>

#include "geotex/core/progress.h"
#include "geotex/core/random.h"
#include "geotex/denoise/normal_fit.h"
#include "mrf_internal.h"

namespace geotex::detail {

namespace {

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

}  // namespace

NormalProcess::NormalProcess(const Topology& T, std::vector<double> x, const LabelState& labels, const MrfNormalOptions& o)
    : T_(T), labels_(labels), o_(o), x_(std::move(x)), n0_(3 * T.nF), n_(3 * T.nF), step_(o.step) {}

void NormalProcess::begin_round() {
  compute_normals(T_, x_.data(), n0_.data(), nullptr);
  n_ = n0_;
}

double NormalProcess::energy() {
  const NormalProblem P{T_, n0_.data(), labels_.w.data(), o_.alpha, o_.potential};
  return P.value(n_.data());
}

double NormalProcess::run(int sweeps, double temperature, bool adapt, int& sweep_counter) {
  const NormalProblem P{T_, n0_.data(), labels_.w.data(), o_.alpha, o_.potential};
  double U = 0;
  for (int s = 0; s < sweeps; ++s) {
    check_interrupt();
    if (o_.optimizer == MrfOptimizer::Icm) {
      U = normal_icm(P, n_);
    } else {
      double acceptance = 0;
      U = normal_metropolis(P, n_, temperature, step_, o_.seed, sweep_counter++, &acceptance);
      if (adapt) {
        step_ *= acceptance < 0.15 ? 0.7 : acceptance > 0.35 ? 1.3 : 1.0;
        step_ = std::clamp(step_, 1e-4, 1.0);
      }
    }
  }
  return U;
}

void NormalProcess::fit_positions(int iterations) {
  // Sun et al. 2007, Eq. (8), on the flat (x, y, z interleaved) arrays (normal_fit.h).
  using RowMajor3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  using RowMajor3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
  const MatrixX3d X = Eigen::Map<const RowMajor3d>(x_.data(), T_.nV, 3);
  const MatrixX3d N = Eigen::Map<const RowMajor3d>(n_.data(), T_.nF, 3);
  const MatrixX3i F = Eigen::Map<const RowMajor3i>(T_.F.data(), T_.nF, 3);
  Eigen::Map<RowMajor3d>(x_.data(), T_.nV, 3) = fit_vertices_to_normals(F, X, N, iterations);
}

}  // namespace geotex::detail
