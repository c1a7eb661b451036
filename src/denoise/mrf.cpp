// MRF denoising with explicit sharp-edge labelling (thesis ch. 6; optimizers of ch. 4.3).
//
// Data live in flat arrays in vertex / face / edge order (struct of arrays); per-element sweeps are
// OpenMP loops that gather (never scatter), so results do not depend on the thread count. Random
// choices draw from an Rng seeded by (seed, sweep, site): a seed gives the same run on any number of
// threads. Sites updated together in parallel (Metropolis, Gauss–Seidel ICM) share a colour of a
// greedy colouring in which no two same-coloured sites are MRF neighbours.

#include "geotex/denoise/mrf.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"
#include "mrf_internal.h"

namespace geotex {

namespace detail {

// ---------------------------------------------------------------------------------------------
// Topology

Topology::Topology(const Mesh& mesh) {
  nV = static_cast<int>(mesh.n_vertices());
  nF = static_cast<int>(mesh.n_faces());
  nE = static_cast<int>(mesh.n_edges());
  F.resize(3 * nF);
  fe.resize(3 * nF);
  for (int f = 0; f < nF; ++f) {
    auto h = mesh.halfedge_handle(mesh.face_handle(f));
    for (int m = 0; m < 3; ++m) {
      F[3 * f + m] = mesh.from_vertex_handle(h).idx();
      fe[3 * f + m] = mesh.edge_handle(h).idx();  // edge from corner m to corner m+1
      h = mesh.next_halfedge_handle(h);
    }
  }
  E.resize(2 * nE);
  ef.resize(2 * nE);
  for (int e = 0; e < nE; ++e) {
    const auto eh = mesh.edge_handle(e);
    for (int s = 0; s < 2; ++s) {
      const auto h = mesh.halfedge_handle(eh, s);
      ef[2 * e + s] = mesh.face_handle(h).is_valid() ? mesh.face_handle(h).idx() : -1;
    }
    const auto h0 = mesh.halfedge_handle(eh, 0);
    E[2 * e] = mesh.from_vertex_handle(h0).idx();
    E[2 * e + 1] = mesh.to_vertex_handle(h0).idx();
  }
  // Vertex → incident faces (with the corner), vertex → incident edges (CSR).
  vf_off.assign(nV + 1, 0);
  for (int c = 0; c < 3 * nF; ++c) ++vf_off[F[c] + 1];
  for (int v = 0; v < nV; ++v) vf_off[v + 1] += vf_off[v];
  vf.resize(3 * nF);
  {
    std::vector<int> fill(vf_off.begin(), vf_off.end() - 1);
    for (int c = 0; c < 3 * nF; ++c) vf[fill[F[c]]++] = c;  // corner id: 3 f + m
  }
  ve_off.assign(nV + 1, 0);
  for (int e = 0; e < nE; ++e) {
    ++ve_off[E[2 * e] + 1];
    ++ve_off[E[2 * e + 1] + 1];
  }
  for (int v = 0; v < nV; ++v) ve_off[v + 1] += ve_off[v];
  ve.resize(2 * nE);
  {
    std::vector<int> fill(ve_off.begin(), ve_off.end() - 1);
    for (int e = 0; e < nE; ++e) {
      ve[fill[E[2 * e]]++] = e;
      ve[fill[E[2 * e + 1]]++] = e;
    }
  }
}

namespace {
// Greedy colouring given each site's neighbour list (a callback filling `nb`).
template <class Neighbours>
std::vector<std::vector<int>> greedy_colouring(int n, Neighbours&& neighbours) {
  std::vector<int> colour(n, -1), stamp;
  std::vector<int> nb;
  int n_colours = 0;
  for (int s = 0; s < n; ++s) {
    nb.clear();
    neighbours(s, nb);
    if (static_cast<int>(stamp.size()) < n_colours + 1) stamp.resize(n_colours + 1, -1);
    for (int t : nb)
      if (t != s && colour[t] >= 0) stamp[colour[t]] = s;
    int c = 0;
    while (c < n_colours && stamp[c] == s) ++c;
    colour[s] = c;
    n_colours = std::max(n_colours, c + 1);
  }
  std::vector<std::vector<int>> classes(n_colours);
  for (int s = 0; s < n; ++s) classes[colour[s]].push_back(s);
  return classes;
}
}  // namespace

const std::vector<std::vector<int>>& Topology::vertex_colours() const {
  if (vertex_colours_.empty() && nV > 0) {
    // Conflict: b is a corner of a face that shares an edge with (or is) a face around a.
    vertex_colours_ = greedy_colouring(nV, [&](int a, std::vector<int>& nb) {
      for (int k = vf_off[a]; k < vf_off[a + 1]; ++k) {
        const int f = vf[k] / 3;
        for (int m = 0; m < 3; ++m) {
          const int e = fe[3 * f + m];
          for (int s = 0; s < 2; ++s) {
            const int g = ef[2 * e + s];
            if (g < 0) continue;
            for (int q = 0; q < 3; ++q) nb.push_back(F[3 * g + q]);
          }
        }
      }
    });
  }
  return vertex_colours_;
}

const std::vector<std::vector<int>>& Topology::edge_colours() const {
  if (edge_colours_.empty() && nE > 0) {
    edge_colours_ = greedy_colouring(nE, [&](int e, std::vector<int>& nb) {
      for (int s = 0; s < 2; ++s) {
        const int v = E[2 * e + s];
        for (int k = ve_off[v]; k < ve_off[v + 1]; ++k) nb.push_back(ve[k]);
      }
    });
  }
  return edge_colours_;
}

const std::vector<std::vector<int>>& Topology::face_colours() const {
  if (face_colours_.empty() && nF > 0) {
    face_colours_ = greedy_colouring(nF, [&](int f, std::vector<int>& nb) {
      for (int m = 0; m < 3; ++m) {
        const int e = fe[3 * f + m];
        for (int s = 0; s < 2; ++s)
          if (ef[2 * e + s] >= 0) nb.push_back(ef[2 * e + s]);
      }
    });
  }
  return face_colours_;
}

uint64_t site_seed(uint64_t seed, uint64_t sweep, uint64_t site) {
  return seed * 0x9E3779B97F4A7C15ull + (sweep + 1) * 0xD1B54A32D192ED03ull + (site + 1) * 0xABC98388FB8FAC03ull;
}

// ---------------------------------------------------------------------------------------------
// Face normals and the vertex-process energy U_V, Eq. (6.4), (6.13)

void compute_normals(const Topology& T, const double* x, double* n, double* inv_len) {
#pragma omp parallel for schedule(static) if (T.nF >= min_parallel)
  for (int f = 0; f < T.nF; ++f) {
    const double* a = x + 3 * T.F[3 * f];
    const double* b = x + 3 * T.F[3 * f + 1];
    const double* c = x + 3 * T.F[3 * f + 2];
    const Vec3 N = (Vec3(b[0], b[1], b[2]) - Vec3(a[0], a[1], a[2])).cross(Vec3(c[0], c[1], c[2]) - Vec3(a[0], a[1], a[2]));
    const double len = N.norm();
    const double inv = len > 1e-300 ? 1.0 / len : 0.0;
    for (int d = 0; d < 3; ++d) n[3 * f + d] = N[d] * inv;
    if (inv_len) inv_len[f] = inv;
  }
}

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

inline Vec3 vec(const double* p) { return {p[0], p[1], p[2]}; }

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
  constexpr int kMax = 64;
  int faces[kMax];
  Vec3 ln[kMax], lN[kMax];
  double linv[kMax];
  const int deg = std::min(T.vf_off[a + 1] - T.vf_off[a], kMax);
  for (int k = 0; k < deg; ++k) {
    const int corner = T.vf[T.vf_off[a] + k], f = corner / 3, m = corner % 3;
    faces[k] = f;
    const Vec3 q1 = vec(x + 3 * T.F[3 * f + (m + 1) % 3]), q2 = vec(x + 3 * T.F[3 * f + (m + 2) % 3]);
    lN[k] = (q1 - p).cross(q2 - p);
    const double len = lN[k].norm();
    linv[k] = len > 1e-300 ? 1.0 / len : 0.0;
    ln[k] = lN[k] * linv[k];
  }
  auto normal = [&](int f) -> Vec3 {
    for (int k = 0; k < deg; ++k)
      if (faces[k] == f) return ln[k];
    return vec(nrm + 3 * f);
  };
  auto first_face = [&](int e) { return T.ef[2 * e] >= 0 ? T.ef[2 * e] : T.ef[2 * e + 1]; };
  double U = alpha * (p - vec(x0 + 3 * a)).squaredNorm();
  if (grad) *grad = 2.0 * alpha * (p - vec(x0 + 3 * a));
  for (int k = 0; k < deg; ++k) {
    const int f = faces[k];
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
      const int m = T.vf[T.vf_off[a] + k] % 3;
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

// ---------------------------------------------------------------------------------------------
// Vertex-process sweeps

namespace {
using Vec = Eigen::VectorXd;

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

// Backtracking (Armijo) line search along d from x with value U and gradient g; t is the first trial.
bool line_search(const VertexProblem& P, Vec& x, double& U, Vec& g, const Vec& d, double& t) {
  const double slope = g.dot(d);
  if (!(slope < 0)) return false;
  Vec z(x.size()), gz(x.size());
  for (int bt = 0; bt < 40; ++bt) {
    z = x + t * d;
    const double Uz = P.value_grad(z.data(), gz.data());
    if (std::isfinite(Uz) && Uz <= U + 1e-4 * t * slope) {
      x.swap(z);
      g.swap(gz);
      U = Uz;
      return true;
    }
    t *= 0.5;
  }
  return false;
}

// L-BFGS (two-loop recursion, memory 8) on U_V. LBFGSpp is not a dependency of geotex; this is the
// textbook algorithm on flat arrays, with the OpenMP energy/gradient above.
double vertex_lbfgs(const VertexProblem& P, Vec& x, int iterations, double rel_tol) {
  const int m = 8;
  Vec g(x.size());
  double U = P.value_grad(x.data(), g.data());
  std::vector<Vec> S, Y;
  std::vector<double> rho;
  double t = 1.0;
  for (int it = 0; it < iterations; ++it) {
    Vec q = -g;
    std::vector<double> al(S.size());
    for (int k = static_cast<int>(S.size()) - 1; k >= 0; --k) {
      al[k] = rho[k] * S[k].dot(q);
      q -= al[k] * Y[k];
    }
    double gamma = 0.05;  // first step: a small move in mean edge lengths per unit gradient
    if (!S.empty()) gamma = S.back().dot(Y.back()) / Y.back().squaredNorm();
    q *= gamma;
    for (size_t k = 0; k < S.size(); ++k) {
      const double b = rho[k] * Y[k].dot(q);
      q += (al[k] - b) * S[k];
    }
    const Vec x_old = x, g_old = g;
    const double U_old = U;
    t = 1.0;
    if (!line_search(P, x, U, g, q, t)) {
      if (S.empty()) break;
      S.clear();
      Y.clear();
      rho.clear();
      continue;
    }
    Vec s = x - x_old, y = g - g_old;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      if (static_cast<int>(S.size()) == m) {
        S.erase(S.begin());
        Y.erase(Y.begin());
        rho.erase(rho.begin());
      }
      S.push_back(std::move(s));
      Y.push_back(std::move(y));
      rho.push_back(1.0 / sy);
    }
    if (U_old - U <= rel_tol * std::abs(U_old)) break;
  }
  return U;
}

// Nonlinear conjugate gradients (Polak–Ribière+, restarted when d is not a descent direction), as in
// the related Bayesian method the thesis cites ([34]).
double vertex_cg(const VertexProblem& P, Vec& x, int iterations, double rel_tol) {
  Vec g(x.size());
  double U = P.value_grad(x.data(), g.data());
  Vec d = -g;
  double t = 0.05;
  for (int it = 0; it < iterations; ++it) {
    if (g.dot(d) >= 0) d = -g;
    const Vec g_old = g;
    const double U_old = U;
    double t_try = std::min(4.0 * t, 1.0);
    if (!line_search(P, x, U, g, d, t_try)) {
      if (d == -g_old) break;
      d = -g;
      continue;
    }
    t = t_try;
    const double beta = std::max(0.0, g.dot(g - g_old) / g_old.squaredNorm());
    d = -g + beta * d;
    if (U_old - U <= rel_tol * std::abs(U_old)) break;
  }
  return U;
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Edge process, Eq. (6.9–6.11)

EdgeField::EdgeField(const Topology& topology, const EdgeProcessOptions& o) : T(topology), opt(o) {
  phi.resize(T.nE);
  u.resize(3 * T.nE);
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
    for (int k = T.ve_off[v]; k < T.ve_off[v + 1]; ++k) {
      const int e2 = T.ve[k];
      if (e2 == e || eps[e2] == 0) continue;
      support += cos_theta(e, e2, v) * eps[e2];
    }
  }
  return (phi0 - phi[e]) - opt.support_weight * support;
}

double EdgeField::energy(const double* eps) const {
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
  for (const auto& cls : T.edge_colours()) {
#pragma omp parallel for schedule(static) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int e = cls[k];
      if (fixed(e)) continue;
      Rng rng(site_seed(seed, sweep, static_cast<uint64_t>(e) + (1ull << 40)));
      const double proposal = rng.uniform();
      const double dU = (proposal - eps[e]) * field(e, eps);  // U_E is linear in ε_e
      if (dU <= 0 || (temperature > 0 && rng.uniform() < std::exp(-dU / temperature))) eps[e] = proposal;
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
  for (const auto& cls : T.edge_colours()) {
#pragma omp parallel for schedule(static) if (cls.size() >= size_t(min_parallel / 10))
    for (size_t k = 0; k < cls.size(); ++k) {
      const int e = cls[k];
      if (fixed(e)) continue;
      const double h = field(e, eps);
      eps[e] = h < 0 ? 1.0 : h > 0 ? 0.0 : eps[e];
    }
  }
  return energy(eps);
}

double EdgeField::sweep(double* eps, MrfOptimizer optimizer, double temperature, uint64_t seed, int sweep_index) const {
  if (optimizer == MrfOptimizer::Metropolis) return metropolis(eps, temperature, seed, sweep_index);
  if (optimizer == MrfOptimizer::Icm) return icm(eps);
  throw InvalidInput("the edge process is optimized by metropolis or icm, not " + to_string(optimizer));
}

void check_edge_options(const EdgeProcessOptions& o) {
  if (!std::isfinite(o.phi0_deg) || o.phi0_deg < 0 || o.phi0_deg > 180)
    throw InvalidInput("phi0 must be an angle in [0, 180] degrees");
  if (!std::isfinite(o.phi0_start_deg) || o.phi0_start_deg < 0 || o.phi0_start_deg > 180)
    throw InvalidInput("phi0 start must be an angle in [0, 180] degrees (0 = off)");
  if (!std::isfinite(o.support_weight) || o.support_weight < 0) throw InvalidInput("support weight must be >= 0");
  if (!(o.temperature >= 0) || !std::isfinite(o.temperature)) throw InvalidInput("edge temperature must be >= 0");
  if (!(o.cooling > 0 && o.cooling <= 1)) throw InvalidInput("edge cooling factor must be in (0, 1]");
  if (o.sweeps < 1) throw InvalidInput("edge sweeps must be >= 1");
  if (o.optimizer != MrfOptimizer::Metropolis && o.optimizer != MrfOptimizer::Icm)
    throw InvalidInput("the edge process is optimized by metropolis or icm");
}

double edge_step(EdgeField& field, const EdgeProcessOptions& o, int it, int iterations, bool last, double temperature,
                 uint64_t seed, int& sweep_counter, double* eps, bool& quenched) {
  field.opt.phi0_deg = annealed_phi0(o, it, iterations);
  const MrfOptimizer optimizer = last && o.quench ? MrfOptimizer::Icm : o.optimizer;
  quenched = quenched || optimizer == MrfOptimizer::Icm;
  double Ue = 0;
  for (int s = 0; s < o.sweeps; ++s) Ue = field.sweep(eps, optimizer, temperature, seed, sweep_counter++);
  return Ue;
}

double annealed_phi0(const EdgeProcessOptions& o, int it, int iterations) {
  if (!(o.phi0_start_deg > o.phi0_deg)) return o.phi0_deg;
  const double ramp = std::max(1.0, 0.5 * iterations);
  const double t = std::min(1.0, it / ramp);
  return o.phi0_start_deg + t * (o.phi0_deg - o.phi0_start_deg);
}

std::vector<double> flat(const MatrixX3d& X, double scale) {
  std::vector<double> x(3 * X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (int d = 0; d < 3; ++d) x[3 * i + d] = X(i, d) / scale;
  return x;
}

MatrixX3d unflat(const double* x, int n, double scale) {
  MatrixX3d X(n, 3);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) X(i, d) = x[3 * i + d] * scale;
  return X;
}

}  // namespace detail

using namespace detail;

// ---------------------------------------------------------------------------------------------
// Clique potentials

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

double edge_energy(const Mesh& mesh, const MatrixX3d& X, const Eigen::VectorXd& labels,
                   const EdgeProcessOptions& options) {
  const Topology T(mesh);
  if (X.rows() != T.nV || labels.size() != T.nE) throw InvalidInput("edge_energy: sizes do not match the mesh");
  const std::vector<double> x = flat(X, 1.0);
  std::vector<double> n(3 * T.nF);
  compute_normals(T, x.data(), n.data(), nullptr);
  EdgeField field(T, options);
  field.update(x.data(), n.data());
  return field.energy(labels.data());
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
  switch (optimizer) {
    case MrfOptimizer::Metropolis: U = vertex_metropolis(P, x, temperature, step, seed, sweep_index, nullptr); break;
    case MrfOptimizer::Icm: U = vertex_icm(P, x, 5); break;
    case MrfOptimizer::Cg: U = vertex_cg(P, x, 1, 0); break;
    case MrfOptimizer::Lbfgs: U = vertex_lbfgs(P, x, 1, 0); break;
  }
  X = unflat(x.data(), T.nV, 1.0);
  return U;
}

double edge_process_sweep(const Mesh& mesh, const MatrixX3d& X, Eigen::VectorXd& labels,
                          const EdgeProcessOptions& options, double temperature, uint64_t seed, int sweep_index) {
  check_edge_options(options);
  const Topology T(mesh);
  if (X.rows() != T.nV || labels.size() != T.nE) throw InvalidInput("edge_process_sweep: sizes do not match the mesh");
  const std::vector<double> x = flat(X, 1.0);
  std::vector<double> n(3 * T.nF);
  compute_normals(T, x.data(), n.data(), nullptr);
  EdgeField field(T, options);
  field.update(x.data(), n.data());
  return field.sweep(labels.data(), options.optimizer, temperature, seed, sweep_index);
}

// ---------------------------------------------------------------------------------------------
// The coupled model, Sec. 6.3.4–6.3.5

MrfResult mrf_denoise(const Mesh& mesh, const MrfOptions& o) {
  require_valid(mesh, "input mesh");
  check_edge_options(o.edges);
  if (!(o.alpha >= 0) || !std::isfinite(o.alpha)) throw InvalidInput("alpha must be >= 0");
  if (!(o.temperature >= 0) || !std::isfinite(o.temperature)) throw InvalidInput("vertex temperature must be >= 0");
  if (!(o.cooling > 0 && o.cooling <= 1)) throw InvalidInput("vertex cooling factor must be in (0, 1]");
  if (!(o.step > 0) || !std::isfinite(o.step)) throw InvalidInput("Metropolis step must be > 0");
  if (o.iterations < 0 || o.vertex_sweeps < 0 || o.final_sweeps < 0) throw InvalidInput("iterations and sweeps must be >= 0");
  const auto t0 = std::chrono::steady_clock::now();
  const Topology T(mesh);
  const double h = mean_edge_length(mesh);
  if (!(h > 0)) throw InvalidInput("input mesh has zero mean edge length");
  const std::vector<double> x0 = flat(positions(mesh), h);
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(x0.data(), x0.size());
  std::vector<double> n(3 * T.nF), eps(T.nE, 0.0), w(T.nE, 1.0), prev(T.nE);
  EdgeField field(T, o.edges);
  compute_normals(T, x.data(), n.data(), nullptr);
  field.update(x.data(), n.data());
  field.opt.phi0_deg = annealed_phi0(o.edges, 0, o.iterations);
  if (o.initial_labels_from_angles) field.initial_labels(eps.data());
  const VertexProblem P(T, x0.data(), w.data(), o.alpha, o.potential);

  int sweeps = o.vertex_sweeps;
  if (sweeps == 0)
    sweeps = o.optimizer == MrfOptimizer::Icm ? 2 : 5;
  MrfResult r;
  double Tv = o.temperature, Te = o.edges.temperature, step = o.step, U_prev = P.value(x.data());
  int sweep_counter = 0;
  bool quenched = false, quench_now = false;
  for (int it = 0; it < o.iterations; ++it) {
    // Edge process for the current geometry (Eq. 6.12) ...
    compute_normals(T, x.data(), n.data(), nullptr);
    field.update(x.data(), n.data());
    prev = eps;
    const bool last = it + 1 == o.iterations || quench_now;
    const double Ue =
        edge_step(field, o.edges, it, o.iterations, last, Te, o.seed, sweep_counter, eps.data(), quenched);
    for (int e = 0; e < T.nE; ++e) w[e] = 1.0 - eps[e];
    // ... then the vertex process for the current labels (Eq. 6.15).
    double Uv = 0;
    switch (o.optimizer) {
      case MrfOptimizer::Metropolis:
        for (int s = 0; s < sweeps; ++s) {
          double acc = 0;
          Uv = vertex_metropolis(P, x, Tv, step, o.seed, sweep_counter++, &acc);
          // Keep the acceptance rate near ¼ by adapting the proposal size.
          step *= acc < 0.15 ? 0.7 : acc > 0.35 ? 1.3 : 1.0;
          step = std::clamp(step, 1e-4, 1.0);
        }
        break;
      case MrfOptimizer::Icm:
        for (int s = 0; s < sweeps; ++s) Uv = vertex_icm(P, x, 5);
        break;
      case MrfOptimizer::Cg: Uv = vertex_cg(P, x, sweeps, 0.1 * o.tolerance); break;
      case MrfOptimizer::Lbfgs: Uv = vertex_lbfgs(P, x, sweeps, 0.1 * o.tolerance); break;
    }
    Tv *= o.cooling;
    Te *= o.edges.cooling;
    const double changed = record_iteration(
        r, eps, prev, Uv, Ue, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    r.iterations = it + 1;
    report(o.progress, double(it + 1) / o.iterations, "mrf");
    const bool stable = changed < 1e-3 && std::abs(U_prev - Uv) <= o.tolerance * std::abs(U_prev);
    U_prev = Uv;
    if (stable && !quenched) {
      quench_now = true;  // one more iteration with the edge process at T = 0
    } else if (stable) {
      r.converged = true;
      break;
    }
  }
  if (o.final_sweeps > 0) {
    double Uv = 0;
    switch (o.optimizer) {
      case MrfOptimizer::Metropolis:
        for (int s = 0; s < o.final_sweeps; ++s) Uv = vertex_metropolis(P, x, 0.0, step, o.seed, sweep_counter++, nullptr);
        break;
      case MrfOptimizer::Icm:
        for (int s = 0; s < o.final_sweeps; ++s) Uv = vertex_icm(P, x, 5);
        break;
      case MrfOptimizer::Cg: Uv = vertex_cg(P, x, o.final_sweeps, 0.1 * o.tolerance); break;
      case MrfOptimizer::Lbfgs: Uv = vertex_lbfgs(P, x, o.final_sweeps, 0.1 * o.tolerance); break;
    }
    // Reported as part of the last outer iteration.
    if (!r.vertex_energy.empty()) {
      r.vertex_energy.back() = Uv;
      r.seconds.back() = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
  }
  if (o.final_phi0_deg > 0) {
    // Final labelling on the denoised geometry (MrfOptions::final_phi0_deg): ICM on Eq. (6.12).
    compute_normals(T, x.data(), n.data(), nullptr);
    field.update(x.data(), n.data());
    field.opt.phi0_deg = o.final_phi0_deg;
    field.initial_labels(eps.data());
    for (int s = 0; s < 50; ++s) {
      prev = eps;
      field.icm(eps.data());
      if (prev == eps) break;
    }
  }
  r.positions = unflat(x.data(), T.nV, h);
  r.edge_labels = Eigen::Map<Eigen::VectorXd>(eps.data(), eps.size());
  return r;
}

}  // namespace geotex

namespace geotex::detail {

double record_iteration(MrfResult& r, const std::vector<double>& eps, const std::vector<double>& prev,
                        double vertex_energy, double edge_energy, double seconds) {
  double changed = 0;
  int labelled = 0;
  for (size_t e = 0; e < eps.size(); ++e) {
    changed = std::max(changed, std::abs(eps[e] - prev[e]));
    labelled += eps[e] > 0.5;
  }
  r.vertex_energy.push_back(vertex_energy);
  r.edge_energy.push_back(edge_energy);
  r.labelled.push_back(labelled);
  r.seconds.push_back(seconds);
  return changed;
}

}  // namespace geotex::detail
