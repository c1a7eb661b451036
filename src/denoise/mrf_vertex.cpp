// The vertex process of the MRF denoiser (thesis Sec. 6.3.1–6.3.2, 6.3.4): vertices are the sites,
// positions the labels, and U_V(X) = α Σ_i ‖x_i⁰ − x_i‖² + Σ_e (1 − ε_e) ρ(‖n_f − n_g‖) (Eq. 6.4, 6.13)
// is lowered by Metropolis sampling, ICM (Sec. 4.3) or, on the whole of U_V, CG and L-BFGS (numerics.h).
// Sites updated together in parallel (Metropolis, Gauss–Seidel ICM) share a colour of a greedy
// colouring in which no two same-coloured sites are MRF neighbours (Fig. 6.1, right).

#include <algorithm>
#include <cmath>
#include <vector>

#include "geotex/core/error.h"
#include "geotex/core/progress.h"
#include "geotex/core/random.h"
#include "geotex/toolkit/numerics.h"
#include "mrf_internal.h"

namespace geotex {
namespace detail {

using Vec = Eigen::VectorXd;

VertexProcess::VertexProcess(const Topology& T, const std::vector<double>& x0, const LabelState& labels,
                             const MrfOptions& o)
    : T_(T),
      o_(o),
      P_(T, x0.data(), labels.w.data(), o.alpha, o.potential),
      x_(Eigen::Map<const Vec>(x0.data(), static_cast<Eigen::Index>(x0.size()))),
      n_(3 * T.nF),
      step_(o.step) {}

const double* VertexProcess::normals() {
  compute_normals(T_, x_.data(), n_.data(), nullptr);
  return n_.data();
}

double VertexProcess::run(int sweeps, double temperature, bool adapt, int& sweep_counter) {
  return vertex_sweeps(P_, x_, o_.optimizer, sweeps, temperature, step_, adapt, o_.seed, sweep_counter, 0.1 * o_.tolerance);
}

namespace {

double vertex_metropolis(const VertexProblem& P, Vec& x, double T, double step, uint64_t seed, int sweep,
                         double* acceptance) {
  const Topology& top = P.T;
  Vec nrm(3 * top.nF);
  compute_normals(top, x.data(), nrm.data(), nullptr);
  long accepted = 0;
  for (const auto& cls : top.vertex_colours()) {
#pragma omp parallel for schedule(static) reduction(+ : accepted) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int a = cls[k];
      if (top.vf_off[a + 1] == top.vf_off[a]) continue;
      Rng rng(site_seed(seed, sweep, a));
      const Vec3 old = vec(&x[3 * a]);
      const Vec3 q = old + step * Vec3(rng.normal(), rng.normal(), rng.normal());
      const double dU = P.local(a, q, x.data(), nrm.data(), nullptr) - P.local(a, old, x.data(), nrm.data(), nullptr);
      // Metropolis criterion, Eq. (4.11): always accept a decrease; an increase with probability e^(−ΔU/T).
      const bool accept = dU <= 0 || (T > 0 && rng.uniform() < std::exp(-dU / T));
      if (accept) {
        for (int d = 0; d < 3; ++d) x[3 * a + d] = q[d];
        P.update_normals_at(a, x.data(), nrm.data());
        ++accepted;
      }
    }
  }
  if (acceptance) *acceptance = top.nV ? double(accepted) / top.nV : 0.0;
  return P.value(x.data());
}

// ICM, Sec. 4.3.1: every site takes its conditional mode given the previous configuration (Jacobi).
// A Jacobi step can raise the energy; it is then damped, and as a last resort replaced by a sweep over
// colour classes (sites of one colour share no energy term, so that sweep never raises the energy).
double vertex_icm(const VertexProblem& P, Vec& x, int local_steps) {
  const Topology& top = P.T;
  Vec nrm(3 * top.nF);
  compute_normals(top, x.data(), nrm.data(), nullptr);
  const double U0 = P.value_from_normals(x.data());
  Vec y = x;
#pragma omp parallel for schedule(dynamic, 256) if (top.nV >= min_parallel / 10)
  for (int a = 0; a < top.nV; ++a) {
    if (top.vf_off[a + 1] == top.vf_off[a]) continue;
    const Vec3 p = P.local_minimize(a, x.data(), nrm.data(), local_steps);
    for (int d = 0; d < 3; ++d) y[3 * a + d] = p[d];
  }
  double theta = 1.0;
  for (int damp = 0; damp < 4; ++damp, theta *= 0.5) {
    const Vec z = x + theta * (y - x);
    const double U = P.value(z.data());
    if (U <= U0) {
      x = z;
      return U;
    }
  }
  for (const auto& cls : top.vertex_colours()) {
#pragma omp parallel for schedule(dynamic, 256) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int a = cls[k];
      if (top.vf_off[a + 1] == top.vf_off[a]) continue;
      const Vec3 p = P.local_minimize(a, x.data(), nrm.data(), local_steps);
      for (int d = 0; d < 3; ++d) x[3 * a + d] = p[d];
      P.update_normals_at(a, x.data(), nrm.data());
    }
  }
  return P.value(x.data());
}

double vertex_lbfgs(const VertexProblem& P, Vec& x, int iterations, double rel_tol) {
  DescentOptions d;
  d.iterations = iterations;
  d.rel_tol = rel_tol;
  return lbfgs_minimize([&P](const Vec& z, Vec& g) { return P.value_grad(z.data(), g.data()); }, x, d);
}

// Nonlinear conjugate gradients, as in the related Bayesian method the thesis cites ([34]).
double vertex_cg(const VertexProblem& P, Vec& x, int iterations, double rel_tol) {
  DescentOptions d;
  d.iterations = iterations;
  d.rel_tol = rel_tol;
  return cg_minimize([&P](const Vec& z, Vec& g) { return P.value_grad(z.data(), g.data()); }, x, d);
}

}  // namespace

double vertex_sweeps(const VertexProblem& P, Vec& x, MrfOptimizer optimizer, int sweeps, double temperature,
                     double& step, bool adapt, uint64_t seed, int& sweep_counter, double rel_tol) {
  double U = 0;
  switch (optimizer) {
    case MrfOptimizer::Metropolis:
      for (int s = 0; s < sweeps; ++s) {
        check_interrupt();
        double acceptance = 0;
        U = vertex_metropolis(P, x, temperature, step, seed, sweep_counter++, &acceptance);
        if (adapt) {  // keep the acceptance rate near ¼ by adapting the proposal size
          step *= acceptance < 0.15 ? 0.7 : acceptance > 0.35 ? 1.3 : 1.0;
          step = std::clamp(step, 1e-4, 1.0);
        }
      }
      break;
    case MrfOptimizer::Icm:
      for (int s = 0; s < sweeps; ++s) {
        check_interrupt();
        U = vertex_icm(P, x, 5);
      }
      break;
    case MrfOptimizer::Cg: U = vertex_cg(P, x, sweeps, rel_tol); break;
    case MrfOptimizer::Lbfgs: U = vertex_lbfgs(P, x, sweeps, rel_tol); break;
  }
  return U;
}

// ---------------------------------------------------------------------------------------------
// The energy U_V, Eq. (6.4), (6.13)

// ρ(y) with y = ‖d‖ and ∂ρ/∂d.
inline double rho_value(SmoothnessPotential rho, const Vec3& d, Vec3* dd) {
  const double y2 = d.squaredNorm();
  if (rho == SmoothnessPotential::Quadratic) {
    if (dd) *dd = 2.0 * d;
    return y2;
  }
  const double y = std::sqrt(y2);
  if (dd) *dd = y > 1e-12 ? Vec3(d / y) : Vec3::Zero();
  return y;
}

VertexProblem::VertexProblem(const Topology& topology, const double* data, const double* edge_weights, double a,
                             SmoothnessPotential r)
    : T(topology), x0(data), w(edge_weights), alpha(a), rho(r) {
  n.resize(3 * T.nF);
  inv.resize(T.nF);
  dn.resize(3 * T.nE);
  cg.resize(9 * T.nF);
}

double VertexProblem::value(const double* x) const {
  compute_normals(T, x, n.data(), inv.data());
  return value_from_normals(x);
}

double VertexProblem::value_from_normals(const double* x) const {
  double U = 0;
#pragma omp parallel for schedule(static) reduction(+ : U) if (T.nE >= min_parallel)
  for (int e = 0; e < T.nE; ++e) {
    const int f0 = T.ef[2 * e], f1 = T.ef[2 * e + 1];
    if (f0 < 0 || f1 < 0 || w[e] == 0) continue;
    U += w[e] * rho_value(rho, vec(&n[3 * f0]) - vec(&n[3 * f1]), nullptr);
  }
  double L = 0;
#pragma omp parallel for schedule(static) reduction(+ : L) if (3 * T.nV >= min_parallel)
  for (int i = 0; i < 3 * T.nV; ++i) L += (x[i] - x0[i]) * (x[i] - x0[i]);
  return U + alpha * L;
}

double VertexProblem::value_grad(const double* x, double* g) const {
  compute_normals(T, x, n.data(), inv.data());
  double U = 0;
#pragma omp parallel for schedule(static) reduction(+ : U) if (T.nE >= min_parallel)
  for (int e = 0; e < T.nE; ++e) {
    const int f0 = T.ef[2 * e], f1 = T.ef[2 * e + 1];
    Vec3 d = Vec3::Zero();
    if (f0 >= 0 && f1 >= 0 && w[e] != 0) {
      Vec3 dd;
      U += w[e] * rho_value(rho, vec(&n[3 * f0]) - vec(&n[3 * f1]), &dd);
      d = w[e] * dd;  // ∂U/∂n_f0; ∂U/∂n_f1 = −d
    }
    for (int k = 0; k < 3; ++k) dn[3 * e + k] = d[k];
  }
  // Per face: c = ∂U/∂n, projected and divided by |N| (∂n/∂N), then ∂U/∂p_m = (p_{m+1} − p_{m+2}) × c'.
#pragma omp parallel for schedule(static) if (T.nF >= min_parallel)
  for (int f = 0; f < T.nF; ++f) {
    Vec3 c = Vec3::Zero();
    for (int m = 0; m < 3; ++m) {
      const int e = T.fe[3 * f + m];
      const double s = T.ef[2 * e] == f ? 1.0 : -1.0;
      c += s * vec(&dn[3 * e]);
    }
    const Vec3 nf = vec(&n[3 * f]);
    const Vec3 cp = (c - nf * nf.dot(c)) * inv[f];
    const Vec3 p[3] = {vec(x + 3 * T.F[3 * f]), vec(x + 3 * T.F[3 * f + 1]), vec(x + 3 * T.F[3 * f + 2])};
    for (int m = 0; m < 3; ++m) {
      const Vec3 gm = (p[(m + 1) % 3] - p[(m + 2) % 3]).cross(cp);
      for (int k = 0; k < 3; ++k) cg[9 * f + 3 * m + k] = gm[k];
    }
  }
  double L = 0;
#pragma omp parallel for schedule(static) reduction(+ : L) if (T.nV >= min_parallel)
  for (int v = 0; v < T.nV; ++v) {
    Vec3 gv = Vec3::Zero();
    for (int k = T.vf_off[v]; k < T.vf_off[v + 1]; ++k) gv += vec(&cg[3 * T.vf[k]]);
    const Vec3 r = vec(x + 3 * v) - vec(x0 + 3 * v);
    L += r.squaredNorm();
    gv += 2.0 * alpha * r;
    for (int k = 0; k < 3; ++k) g[3 * v + k] = gv[k];
  }
  return U + alpha * L;
}

// Energy terms that change with x_a, evaluated with x_a = p (others from x, their normals from `n`).
double VertexProblem::local(int a, const Vec3& p, const double* x, const double* nrm, Vec3* grad) const {
  // The normals of the faces around a with x_a = p: on the stack, or in a per-thread buffer at high valence.
  constexpr int kStack = 32;
  Vec3 ln_stack[kStack], lN_stack[kStack];
  double linv_stack[kStack];
  thread_local std::vector<Vec3> ln_heap, lN_heap;
  thread_local std::vector<double> linv_heap;
  const int deg = T.vf_off[a + 1] - T.vf_off[a];
  Vec3 *ln = ln_stack, *lN = lN_stack;
  double* linv = linv_stack;
  if (deg > kStack) {
    ln_heap.resize(deg);
    lN_heap.resize(deg);
    linv_heap.resize(deg);
    ln = ln_heap.data(), lN = lN_heap.data(), linv = linv_heap.data();
  }
  const int* faces_corner = T.vf.data() + T.vf_off[a];
  for (int k = 0; k < deg; ++k) {
    const int corner = faces_corner[k], f = corner / 3, m = corner % 3;
    const Vec3 q1 = vec(x + 3 * T.F[3 * f + (m + 1) % 3]), q2 = vec(x + 3 * T.F[3 * f + (m + 2) % 3]);
    lN[k] = (q1 - p).cross(q2 - p);
    const double len = lN[k].norm();
    linv[k] = len > 1e-300 ? 1.0 / len : 0.0;
    ln[k] = lN[k] * linv[k];
  }
  auto normal = [&](int f) -> Vec3 {  // a face around a is found by its corner at a, in O(1)
    for (int m = 0; m < 3; ++m)
      if (T.F[3 * f + m] == a) return ln[T.vf_pos[3 * f + m]];
    return vec(nrm + 3 * f);
  };
  auto first_face = [&](int e) { return T.ef[2 * e] >= 0 ? T.ef[2 * e] : T.ef[2 * e + 1]; };
  double U = alpha * (p - vec(x0 + 3 * a)).squaredNorm();
  if (grad) *grad = 2.0 * alpha * (p - vec(x0 + 3 * a));
  for (int k = 0; k < deg; ++k) {
    const int f = faces_corner[k] / 3;
    Vec3 c = Vec3::Zero();
    for (int m = 0; m < 3; ++m) {
      const int e = T.fe[3 * f + m];
      const int f0 = T.ef[2 * e], f1 = T.ef[2 * e + 1];
      if (f0 < 0 || f1 < 0 || w[e] == 0) continue;
      const bool spoke = T.E[2 * e] == a || T.E[2 * e + 1] == a;
      const bool count = !spoke || f == first_face(e);  // a spoke lies on two faces around a: count once
      Vec3 dd;
      const double val = w[e] * rho_value(rho, normal(f0) - normal(f1), grad ? &dd : nullptr);
      if (count) U += val;
      if (grad) c += (f0 == f ? 1.0 : -1.0) * w[e] * dd;
    }
    if (grad) {
      const int m = faces_corner[k] % 3;
      const Vec3 cp = (c - ln[k] * ln[k].dot(c)) * linv[k];
      const Vec3 q1 = vec(x + 3 * T.F[3 * f + (m + 1) % 3]), q2 = vec(x + 3 * T.F[3 * f + (m + 2) % 3]);
      *grad += (q1 - q2).cross(cp);
    }
  }
  return U;
}

void VertexProblem::update_normals_at(int a, const double* x, double* nrm) const {
  for (int k = T.vf_off[a]; k < T.vf_off[a + 1]; ++k) {
    const int f = T.vf[k] / 3;
    const Vec3 A = vec(x + 3 * T.F[3 * f]), B = vec(x + 3 * T.F[3 * f + 1]), C = vec(x + 3 * T.F[3 * f + 2]);
    const Vec3 N = (B - A).cross(C - A);
    const double len = N.norm();
    const Vec3 u = len > 1e-300 ? Vec3(N / len) : Vec3::Zero();
    for (int d = 0; d < 3; ++d) nrm[3 * f + d] = u[d];
  }
}

// Minimize the local energy of site a from p by backtracking gradient steps (never increases it).
Vec3 VertexProblem::local_minimize(int a, const double* x, const double* nrm, int steps) const {
  Vec3 p = vec(x + 3 * a), g;
  double U = local(a, p, x, nrm, &g);
  double t = 0.05;
  for (int it = 0; it < steps; ++it) {
    const double g2 = g.squaredNorm();
    if (g2 < 1e-24) break;
    bool moved = false;
    for (int bt = 0; bt < 30; ++bt) {
      const Vec3 q = p - t * g;
      Vec3 gq;
      const double Uq = local(a, q, x, nrm, &gq);
      if (Uq <= U - 1e-4 * t * g2) {
        p = q;
        U = Uq;
        g = gq;
        moved = true;
        t *= 2.0;
        break;
      }
      t *= 0.5;
    }
    if (!moved) break;
  }
  return p;
}

}  // namespace detail

using namespace detail;

// ---------------------------------------------------------------------------------------------
double clique_smoothness(const Vec3& xi, const Vec3& xj, const Vec3& xk, const Vec3& xl, SmoothnessPotential rho,
                         double label, Eigen::Matrix<double, 4, 3>* grad) {
  const Vec3 N1 = (xj - xi).cross(xk - xi), N2 = (xl - xj).cross(xk - xj);  // faces f_ijk, f_jlk
  const double l1 = N1.norm(), l2 = N2.norm();
  if (l1 == 0 || l2 == 0) throw InvalidInput("clique_smoothness: degenerate face");
  const Vec3 n1 = N1 / l1, n2 = N2 / l2;
  const double w = 1.0 - label;  // Eq. (6.13)
  Vec3 dd;
  const double U = w * rho_value(rho, n1 - n2, &dd);
  if (grad) {
    const Vec3 c1 = w * dd, c2 = -c1;
    const Vec3 p1 = (c1 - n1 * n1.dot(c1)) / l1, p2 = (c2 - n2 * n2.dot(c2)) / l2;
    grad->row(0) = (xj - xk).cross(p1).transpose();
    grad->row(1) = ((xk - xi).cross(p1) + (xl - xk).cross(p2)).transpose();
    grad->row(2) = ((xi - xj).cross(p1) + (xj - xl).cross(p2)).transpose();
    grad->row(3) = (xk - xj).cross(p2).transpose();
  }
  return U;
}

double likelihood_potential(const Vec3& x0, const Vec3& x, double alpha, Vec3* grad) {
  if (grad) *grad = 2.0 * alpha * (x - x0);
  return alpha * (x0 - x).squaredNorm();  // Eq. (6.4)
}

double vertex_energy(const Mesh& mesh, const MatrixX3d& X, const MatrixX3d& X0, const Eigen::VectorXd& labels,
                     double alpha, SmoothnessPotential rho) {
  const Topology T(mesh);
  if (X.rows() != T.nV || X0.rows() != T.nV || labels.size() != T.nE)
    throw InvalidInput("vertex_energy: sizes do not match the mesh");
  const std::vector<double> x = flat(X, 1.0), x0 = flat(X0, 1.0);
  std::vector<double> w(T.nE);
  for (int e = 0; e < T.nE; ++e) w[e] = 1.0 - labels[e];
  const VertexProblem P(T, x0.data(), w.data(), alpha, rho);
  return P.value(x.data());
}


double vertex_process_sweep(const Mesh& mesh, MatrixX3d& X, const MatrixX3d& X0, const Eigen::VectorXd& labels,
                            double alpha, SmoothnessPotential rho, MrfOptimizer optimizer, double temperature,
                            double step, uint64_t seed, int sweep_index) {
  const Topology T(mesh);
  if (X.rows() != T.nV || X0.rows() != T.nV || labels.size() != T.nE)
    throw InvalidInput("vertex_process_sweep: sizes do not match the mesh");
  const std::vector<double> x0 = flat(X0, 1.0);
  std::vector<double> w(T.nE);
  for (int e = 0; e < T.nE; ++e) w[e] = 1.0 - labels[e];
  const VertexProblem P(T, x0.data(), w.data(), alpha, rho);
  std::vector<double> xs = flat(X, 1.0);
  Eigen::VectorXd x = Eigen::Map<Eigen::VectorXd>(xs.data(), xs.size());
  double U = 0;
  int counter = sweep_index;
  U = vertex_sweeps(P, x, optimizer, 1, temperature, step, false, seed, counter, 0);
  X = unflat(x.data(), T.nV, 1.0);
  return U;
}


}  // namespace geotex
