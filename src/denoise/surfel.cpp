// Surfel energy and its ICM optimisation (thesis Sec. 7.4.1–7.4.3).

#include "geotex/denoise/surfel.h"

#include <algorithm>
#include <cmath>
#include <span>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/progress.h"

namespace geotex {

namespace {

// One neighbour of a site in the (n, ρ) form of the site energy, with a = n·x − ρ (ρ is the signed
// distance from the data point to the surfel plane):
//   d(s_j, s_i) = n·u + ρ           with u = c_j − x_i                      (Eq. 7.10, c_j fixed)
//   d(s_i, s_j) = e − ρ (n·n_j)     with e = n_j·x_i − a_j, c_i = x_i − ρ n  (Eq. 7.6, 7.10)
struct SiteTerm {
  Vec3 nj;
  Vec3 u;
  double e;
  double w;  // w_j / W (Eq. 7.14–7.15)
};

double term_energy(const std::vector<SiteTerm>& terms, double alpha, double beta, const Vec3& n, double rho) {
  double E = alpha * rho * rho;  // Eq. (7.8)
  for (const SiteTerm& t : terms) {
    const double dji = n.dot(t.u) + rho;
    const double dij = t.e - rho * n.dot(t.nj);
    E += t.w * (beta * (n - t.nj).squaredNorm() + dij * dij + dji * dji);  // Eq. (7.14)
  }
  return E;
}

// Exact minimiser of nᵀAn − 2bᵀn on the unit sphere (the trust-region subproblem on its boundary):
// n = (A − λI)⁻¹ b with A − λI positive semidefinite; λ = d_min − μ solves the secular equation
// ‖n(μ)‖ = 1. \p prefer picks the sign of the null-space component in the hard case.
Vec3 sphere_quadratic_min(const Eigen::Matrix3d& A, const Vec3& b, const Vec3& prefer) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(A);
  const Vec3 d = es.eigenvalues();  // ascending
  const Eigen::Matrix3d& Q = es.eigenvectors();
  const Vec3 bt = Q.transpose() * b;
  const double bnorm = b.norm();
  const double scale = std::max({std::abs(d[0]), std::abs(d[2]), bnorm, 1e-300});
  const Vec3 delta = d.array() - d[0];
  if (std::abs(bt[0]) <= 1e-12 * scale) {
    // Possible hard case: at μ = 0 the other components alone may have norm ≤ 1.
    double norm2 = 0;
    Vec3 y = Vec3::Zero();
    bool finite = true;
    for (int k = 1; k < 3; ++k) {
      if (delta[k] <= 1e-14 * scale) {
        if (std::abs(bt[k]) > 1e-12 * scale) finite = false;
        continue;
      }
      y[k] = bt[k] / delta[k];
      norm2 += y[k] * y[k];
    }
    if (finite && norm2 <= 1.0) {
      y[0] = std::sqrt(std::max(0.0, 1.0 - norm2));
      Vec3 n = Q * y;
      const Vec3 n2 = Q * Vec3(-y[0], y[1], y[2]);
      if (n2.dot(prefer) > n.dot(prefer)) n = n2;
      return n.normalized();
    }
  }
  // g(μ) = Σ bt_k² / (δ_k + μ)², decreasing on μ > 0, g(‖b‖) ≤ 1. Newton on h = g^(-1/2) − 1
  // (nearly linear in μ), safeguarded by bisection.
  double lo = 0, hi = std::max(bnorm, 1e-300), mu = hi;
  for (int it = 0; it < 100; ++it) {
    double g = 0, dg = 0;
    for (int k = 0; k < 3; ++k) {
      const double q = 1.0 / (delta[k] + mu);
      g += bt[k] * bt[k] * q * q;
      dg -= 2.0 * bt[k] * bt[k] * q * q * q;
    }
    const double s = 1.0 / std::sqrt(g);
    const double h = s - 1.0;
    if (h < 0) lo = mu; else hi = mu;
    if (std::abs(h) < 1e-15 || hi - lo <= 1e-16 * hi) break;
    const double dh = -0.5 * s * s * s * dg;
    double next = mu - h / dh;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    mu = next;
  }
  Vec3 y;
  for (int k = 0; k < 3; ++k) y[k] = bt[k] / (delta[k] + mu);
  const Vec3 n = Q * y;
  return n.norm() > 0 ? Vec3(n.normalized()) : prefer;
}

// The same minimiser, found first by majorisation–minimisation: with c ≥ λ_max(A) (A is positive
// semidefinite, so its trace will do), f(n) = nᵀAn − 2bᵀn is majorised at m by a function whose minimum on
// the sphere is n = normalize((cI − A) m + b), and f never increases along these steps. Each step is a
// 3 by 3 product; with the parallelism weight β dominating b, the steps contract by about ‖A‖ / ‖b‖ and
// reach the minimiser in a few steps. The eigen-decomposition above stays the fallback when they do not.
Vec3 sphere_quadratic_min_fast(const Eigen::Matrix3d& A, const Vec3& b, const Vec3& start) {
  const double c = A.trace();
  const double bnorm = b.norm();
  if (bnorm > 4.0 * c && start.norm() > 0) {
    Vec3 n = start.normalized();
    for (int it = 0; it < 30; ++it) {
      const Vec3 next = (c * n - A * n + b).normalized();
      const double change = (next - n).squaredNorm();
      n = next;
      if (change <= 1e-26) return n;
    }
  }
  return sphere_quadratic_min(A, b, start);
}

// Block-coordinate descent on (ρ, n), each block minimised exactly; returns the final energy.
double minimize_terms(const std::vector<SiteTerm>& terms, double alpha, double beta, Vec3& n, double& rho,
                      int sweeps, double tolerance, bool energy = true) {
  if (terms.empty()) {  // only the likelihood: the plane through the data point
    rho = 0;
    return 0;
  }
  for (int s = 0; s < sweeps; ++s) {
    // ∂E/∂ρ = 0: ρ = Σ w (e (n·n_j) − n·u) / (α + Σ w (1 + (n·n_j)²)).
    double num = 0, den = alpha;
    for (const SiteTerm& t : terms) {
      const double c = n.dot(t.nj);
      num += t.w * (t.e * c - n.dot(t.u));
      den += t.w * (1.0 + c * c);
    }
    rho = num / den;
    // For fixed ρ: E = nᵀAn − 2bᵀn + const on ‖n‖ = 1, with
    //   A = Σ w (βI + u uᵀ + ρ² n_j n_jᵀ),  b = Σ w (β n_j − ρ u + ρ e n_j).
    // (The βI part of A is constant on the sphere and left out: it would only cluster the eigenvalues.)
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Vec3 b = Vec3::Zero();
    for (const SiteTerm& t : terms) {
      A.noalias() += t.w * (t.u * t.u.transpose() + rho * rho * t.nj * t.nj.transpose());
      b += t.w * ((beta + rho * t.e) * t.nj - rho * t.u);
    }
    const Vec3 next = sphere_quadratic_min_fast(A, b, n);
    const double change = (next - n).squaredNorm();
    n = next;
    if (change <= tolerance) {
      // ρ once more for the final n (cheap, and keeps the pair exactly block-optimal in ρ).
      double num2 = 0, den2 = alpha;
      for (const SiteTerm& t : terms) {
        const double c = n.dot(t.nj);
        num2 += t.w * (t.e * c - n.dot(t.u));
        den2 += t.w * (1.0 + c * c);
      }
      rho = num2 / den2;
      break;
    }
  }
  return energy ? term_energy(terms, alpha, beta, n, rho) : 0.0;
}

void build_terms(const Vec3& x, const std::vector<Vec3>& xj, const std::vector<Surfel>& sj,
                 const std::vector<double>& w, std::vector<SiteTerm>& terms) {
  terms.clear();
  double W = 0;
  for (double v : w) W += v;
  if (!(W > 0)) return;
  for (size_t k = 0; k < sj.size(); ++k) {
    const Vec3& nj = sj[k].n;
    const Vec3 cj = xj[k] - (nj.dot(xj[k]) - sj[k].a) * nj;  // Eq. (7.6)
    terms.push_back({nj, cj - x, nj.dot(x) - sj[k].a, w[k] / W});
  }
}

void check_site(const SurfelSite& site) {
  if (site.neighbor_x.size() != site.neighbors.size() || site.weights.size() != site.neighbors.size())
    throw InvalidInput("surfel site: neighbour positions, surfels and weights differ in number");
}

}  // namespace

double threshold_chord(double degrees) { return 2.0 * std::sin(0.5 * degrees * M_PI / 180.0); }

double surfel_weight(const Vec3& ni, const Vec3& nj, double t_chord) {
  const double q = (ni - nj).norm() / t_chord;  // Eq. (7.13)
  return 1.0 / (1.0 + q * q);                   // Eq. (7.12)
}

Surfels surfels_from_normals(const MatrixX3d& X, const MatrixX3d& N) {
  if (X.rows() != N.rows()) throw InvalidInput(fmt::format("{} points but {} normals", X.rows(), N.rows()));
  Surfels S;
  S.normals.resize(X.rows(), 3);
  S.offsets.resize(X.rows());
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    Vec3 n = N.row(i).transpose();
    const double len = n.norm();
    n = len > 0 && std::isfinite(len) ? Vec3(n / len) : Vec3::UnitZ();
    S.normals.row(i) = n.transpose();
    S.offsets[i] = n.dot(X.row(i).transpose());  // Eq. (7.7)
  }
  return S;
}

Surfels initial_surfels(const Mesh& mesh) {
  require_valid(mesh, "surfel input");
  return surfels_from_normals(positions(mesh), vertex_normals(mesh, NormalWeighting::Area));
}

MatrixX3d surfel_centers(const MatrixX3d& X, const Surfels& S) {
  if (X.rows() != S.size()) throw InvalidInput(fmt::format("{} points but {} surfels", X.rows(), S.size()));
  MatrixX3d C(X.rows(), 3);
#pragma omp parallel for schedule(static) if (X.rows() > 4096)
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const Vec3 x = X.row(i).transpose(), n = S.normals.row(i).transpose();
    C.row(i) = (x - (n.dot(x) - S.offsets[i]) * n).transpose();  // Eq. (7.6)
  }
  return C;
}

SurfelPairTerms surfel_pair_terms(const Vec3& xi, const Surfel& si, const Vec3& xj, const Surfel& sj) {
  SurfelPairTerms out;
  const Vec3& ni = si.n;
  const Vec3& nj = sj.n;
  // Parallelism ‖n_i − n_j‖² (Eq. 7.9).
  out.parallelism = (ni - nj).squaredNorm();
  out.grad_parallelism.head<3>() = 2.0 * (ni - nj);
  // d(s_i, s_j) = n_j·c_i − a_j with c_i = x_i − r n_i, r = n_i·x_i − a_i (Eq. 7.6, 7.10);
  // ∂d/∂n_i = −(n_i·n_j) x_i − r n_j, ∂d/∂a_i = n_i·n_j.
  const double r = ni.dot(xi) - si.a;
  const Vec3 ci = xi - r * ni;
  const double dij = nj.dot(ci) - sj.a;
  out.overlap_ij = dij * dij;
  out.grad_overlap_ij.head<3>() = 2.0 * dij * (-ni.dot(nj) * xi - r * nj);
  out.grad_overlap_ij[3] = 2.0 * dij * ni.dot(nj);
  // d(s_j, s_i) = n_i·c_j − a_i (c_j belongs to s_j): ∂d/∂n_i = c_j, ∂d/∂a_i = −1.
  const Vec3 cj = xj - (nj.dot(xj) - sj.a) * nj;
  const double dji = ni.dot(cj) - si.a;
  out.overlap_ji = dji * dji;
  out.grad_overlap_ji.head<3>() = 2.0 * dji * cj;
  out.grad_overlap_ji[3] = -2.0 * dji;
  return out;
}

double surfel_likelihood(const Vec3& xi, const Surfel& si, Eigen::Vector4d* gradient) {
  const double r = si.n.dot(xi) - si.a;  // Eq. (7.8)
  if (gradient) {
    gradient->head<3>() = 2.0 * r * xi;
    (*gradient)[3] = -2.0 * r;
  }
  return r * r;
}

double surfel_site_energy(const SurfelSite& site, const Surfel& s) {
  check_site(site);
  double W = 0, E = 0;
  for (size_t k = 0; k < site.neighbors.size(); ++k) {
    const SurfelPairTerms p = surfel_pair_terms(site.x, s, site.neighbor_x[k], site.neighbors[k]);
    E += site.weights[k] * (site.beta * p.parallelism + p.overlap_ij + p.overlap_ji);  // Eq. (7.14)
    W += site.weights[k];                                                              // Eq. (7.15)
  }
  return (W > 0 ? E / W : 0.0) + site.alpha * surfel_likelihood(site.x, s);  // Eq. (7.16)
}

Surfel minimize_surfel_site(const SurfelSite& site, const Surfel& start, int sweeps, double tolerance) {
  check_site(site);
  std::vector<SiteTerm> terms;
  build_terms(site.x, site.neighbor_x, site.neighbors, site.weights, terms);
  Vec3 n = start.n.norm() > 0 ? Vec3(start.n.normalized()) : Vec3::UnitZ();
  double rho = n.dot(site.x) - start.a;
  minimize_terms(terms, site.alpha, site.beta, n, rho, sweeps, tolerance);
  return {n, n.dot(site.x) - rho};
}

namespace {

// Working copy of a configuration in struct-of-arrays form, in unit lengths.
struct Config {
  std::vector<Vec3> n, c;
  std::vector<double> a;
};

void update_centers(const std::vector<Vec3>& X, Config& s) {
  const Eigen::Index P = static_cast<Eigen::Index>(X.size());
#pragma omp parallel for schedule(static) if (P > 4096)
  for (Eigen::Index i = 0; i < P; ++i) s.c[i] = X[i] - (s.n[i].dot(X[i]) - s.a[i]) * s.n[i];  // Eq. (7.6)
}

// The site terms of surfel i in configuration s at threshold t (chord).
// The weights are those of a surfel with normal \p m (Eq. 7.12–7.13), or, with \p guide, those of
// the guidance normals of i and j; squared with \p irls.
void site_terms(const std::vector<Vec3>& X, const Neighborhoods& N, const Config& s, Eigen::Index i, double t_chord,
                const Vec3& m, std::vector<SiteTerm>& terms, const std::vector<Vec3>* guide = nullptr, bool irls = false) {
  terms.clear();
  const Vec3& x = X[i];
  double W = 0;
  for (int k = N.offsets[i]; k < N.offsets[i + 1]; ++k) {
    const int j = N.indices[k];
    double w = guide ? surfel_weight((*guide)[i], (*guide)[j], t_chord) : surfel_weight(m, s.n[j], t_chord);
    if (irls) w *= w;  // SurfelOptions::irls_weights
    W += w;
    terms.push_back({s.n[j], s.c[j] - x, s.n[j].dot(x) - s.a[j], w});
  }
  for (SiteTerm& t : terms) t.w /= W;  // Eq. (7.15)
}

double total_energy(const std::vector<Vec3>& X, const Neighborhoods& N, const Config& s, double alpha, double beta,
                    double t_chord, const std::vector<Vec3>* guide = nullptr, bool irls = false) {
  const Eigen::Index P = static_cast<Eigen::Index>(X.size());
  double E = 0;
  const std::atomic<bool>* stop = InterruptScope::current();
#pragma omp parallel reduction(+ : E) if (P > 4096)
  {
    std::vector<SiteTerm> terms;
#pragma omp for schedule(static)
    for (Eigen::Index i = 0; i < P; ++i) {
      if (interrupt_requested(stop)) continue;
      site_terms(X, N, s, i, t_chord, s.n[i], terms, guide, irls);
      const double rho = s.n[i].dot(X[i]) - s.a[i];
      E += term_energy(terms, alpha, beta, s.n[i], rho);
    }
  }
  check_interrupt();
  return E;
}

// Guidance normals (after Zhang et al. 2015, guided mesh normal filtering): every surfel takes the mean
// normal of the most consistent patch (a surfel and its neighbours) among the patches it belongs to,
// so a surfel beside a sharp edge is guided by a patch on its own side.
void guidance_normals(const Neighborhoods& N, const std::vector<Vec3>& n, std::vector<Vec3>& mean,
                      std::vector<double>& spread, std::vector<Vec3>& g) {
  const Eigen::Index P = static_cast<Eigen::Index>(n.size());
  mean.resize(P);
  spread.resize(P);
  g.resize(P);
#pragma omp parallel for schedule(static) if (P > 4096)
  for (Eigen::Index p = 0; p < P; ++p) {
    Vec3 m = n[p];
    for (int k = N.offsets[p]; k < N.offsets[p + 1]; ++k) m += n[N.indices[k]];
    m = m.norm() > 0 ? Vec3(m.normalized()) : n[p];
    double s = (n[p] - m).squaredNorm();
    for (int k = N.offsets[p]; k < N.offsets[p + 1]; ++k) s = std::max(s, (n[N.indices[k]] - m).squaredNorm());
    mean[p] = m;
    spread[p] = s;
  }
#pragma omp parallel for schedule(static) if (P > 4096)
  for (Eigen::Index i = 0; i < P; ++i) {
    Eigen::Index best = i;
    for (int k = N.offsets[i]; k < N.offsets[i + 1]; ++k)
      if (spread[N.indices[k]] < spread[best]) best = N.indices[k];
    g[i] = mean[best];
  }
}

void check_inputs(const MatrixX3d& X, const Neighborhoods& N, const Surfels& S) {
  if (X.rows() == 0) throw InvalidInput("surfels: no data points");
  if (S.size() != X.rows() || S.normals.rows() != X.rows())
    throw InvalidInput(fmt::format("surfels: {} points but {} surfels", X.rows(), S.size()));
  if (N.size() != X.rows() || static_cast<size_t>(N.offsets.back()) != N.indices.size())
    throw InvalidInput(fmt::format("surfels: {} points but {} neighbourhoods", X.rows(), N.size()));
  for (int j : N.indices)
    if (j < 0 || j >= X.rows()) throw InvalidInput("surfels: neighbour index out of range");
  if (!X.allFinite() || !S.normals.allFinite() || !S.offsets.allFinite())
    throw InvalidInput("surfels: non-finite point or surfel");
}

struct Normalized {
  std::vector<Vec3> X;
  Config s;
  Vec3 origin;
  double unit;
};

double mean_neighbor_distance(const MatrixX3d& X, const Neighborhoods& N) {
  double sum = 0;
  size_t count = 0;
  for (Eigen::Index i = 0; i < N.size(); ++i)
    for (int k = N.offsets[i]; k < N.offsets[i + 1]; ++k) {
      sum += (X.row(i) - X.row(N.indices[k])).norm();
      ++count;
    }
  return count ? sum / count : 0.0;
}

// Move to the unit length of Sec. 7.4.3.4, centred at the centroid (keeps offsets small).
Normalized normalize(const MatrixX3d& X, const Surfels& S, const Vec3& origin, double unit) {
  Normalized out;
  out.origin = origin;
  out.unit = unit;
  const Eigen::Index P = X.rows();
  out.X.resize(P);
  out.s.n.resize(P);
  out.s.a.resize(P);
  out.s.c.resize(P);
  for (Eigen::Index i = 0; i < P; ++i) {
    out.X[i] = (X.row(i).transpose() - origin) / unit;
    Vec3 n = S.normals.row(i).transpose();
    const double len = n.norm();
    n = len > 0 ? Vec3(n / len) : Vec3::UnitZ();
    out.s.n[i] = n;
    out.s.a[i] = (S.offsets[i] / (len > 0 ? len : 1.0) - n.dot(origin)) / unit;
  }
  return out;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Cluster moves (not in the thesis). ICM changes one surfel at a time, so a chain of parallel surfels
// can sit in a state that no single surfel can leave and the chain as a whole can: on a noiseless cube
// the surfels along an edge stay at the bisector of its faces, a zero-width chamfer, though turning the
// whole chain to either face lowers the energy. Each move takes a cluster (surfels joined through
// neighbours with the same normal), tries the normal of every larger cluster just outside it within 60°,
// with each plane through its data point, and keeps the one that lowers Σ U_k over the cluster and its
// neighbours the most.
// Returns the number of moves made.
int cluster_moves(const std::vector<Vec3>& X, const Neighborhoods& N, Config& s, double alpha, double beta,
                  double chord, int passes) {
  const Eigen::Index P = static_cast<Eigen::Index>(X.size());
  constexpr double same = 1e-9;  // "the same normal": exactly parallel (noiseless data)
  int moves = 0;
  std::vector<int> parent(P), mark(P, -1);
  for (int pass = 0; pass < passes; ++pass) {
    check_interrupt();
    for (Eigen::Index i = 0; i < P; ++i) parent[i] = static_cast<int>(i);
    for (Eigen::Index i = 0; i < P; ++i)
      for (int q = N.offsets[i]; q < N.offsets[i + 1]; ++q)
        if ((s.n[i] - s.n[N.indices[q]]).norm() < same) parent[find_root(parent, static_cast<int>(i))] = find_root(parent, N.indices[q]);
    // Clusters as compressed rows: the members of root r are order[start[r] .. start[r + 1]).
    std::vector<int> root(P), start(P + 1, 0), order(P);
    for (Eigen::Index i = 0; i < P; ++i) ++start[(root[i] = find_root(parent, static_cast<int>(i))) + 1];
    for (Eigen::Index r = 0; r < P; ++r) start[r + 1] += start[r];
    {
      std::vector<int> fill(start.begin(), start.end() - 1);
      for (Eigen::Index i = 0; i < P; ++i) order[fill[root[i]]++] = static_cast<int>(i);
    }
    auto members = [&](int r) { return std::span<const int>(order.data() + start[r], start[r + 1] - start[r]); };
    int made = 0, stamp = 0;
    std::vector<int> affected;
    std::vector<SiteTerm> terms;
    std::vector<Vec3> candidates, old_n;
    std::vector<double> old_a;
    for (int r = 0; r < P; ++r) {
      const std::span<const int> M = members(r);
      if (M.empty()) continue;
      ++stamp;
      affected.assign(M.begin(), M.end());
      for (int i : M) mark[i] = stamp;
      candidates.clear();
      for (int i : M)
        for (int q = N.offsets[i]; q < N.offsets[i + 1]; ++q) {
          const int j = N.indices[q];
          if (mark[j] == stamp) continue;
          mark[j] = stamp;
          affected.push_back(j);
          // A candidate turns the cluster by less than 60° (a plane across the surface, normal along a chain
          // of edge points, can have less overlap energy than the chamfer it would replace).
          bool seen = (s.n[j] - s.n[i]).norm() < same || s.n[j].dot(s.n[i]) < 0.5 ||
                      members(root[j]).size() <= M.size();
          for (const Vec3& m : candidates) seen = seen || (m - s.n[j]).norm() < same;
          if (!seen) candidates.push_back(s.n[j]);
        }
      if (candidates.empty()) continue;
      auto energy = [&] {  // Σ U_k (Eq. 7.16), the weights from the configuration itself (Eq. 7.13)
        double E = 0;
        for (int k : affected) {
          site_terms(X, N, s, k, chord, s.n[k], terms);
          E += term_energy(terms, alpha, beta, s.n[k], s.n[k].dot(X[k]) - s.a[k]);
        }
        return E;
      };
      const double before = energy();
      old_n.clear();
      old_a.clear();
      for (int i : M) {
        old_n.push_back(s.n[i]);
        old_a.push_back(s.a[i]);
      }
      auto assign = [&](const Vec3& m) {
        for (int i : M) {
          s.n[i] = m;
          s.a[i] = m.dot(X[i]);
          s.c[i] = X[i];
        }
      };
      auto restore = [&] {
        for (size_t k = 0; k < M.size(); ++k) {
          s.n[M[k]] = old_n[k];
          s.a[M[k]] = old_a[k];
          s.c[M[k]] = X[M[k]] - (old_n[k].dot(X[M[k]]) - old_a[k]) * old_n[k];
        }
      };
      double best = before - 1e-12 * std::max(1.0, std::abs(before));
      int best_k = -1;
      for (size_t k = 0; k < candidates.size(); ++k) {
        assign(candidates[k]);
        const double e = energy();
        if (e < best) {
          best = e;
          best_k = static_cast<int>(k);
        }
        restore();
      }
      if (best_k >= 0) {
        assign(candidates[best_k]);
        ++made;
      }
    }
    moves += made;
    if (made == 0) break;
  }
  return moves;
}

double resolve_unit(const MatrixX3d& X, const Neighborhoods& N, double unit) {
  if (unit < 0 || !std::isfinite(unit)) throw InvalidInput("surfels: the unit length must be positive");
  if (unit == 0) unit = mean_neighbor_distance(X, N);
  if (!(unit > 0)) throw InvalidInput("surfels: cannot determine a unit length (no neighbours, or coincident points)");
  return unit;
}

}  // namespace

double median_neighbor_angle_deg(const Surfels& S, const Neighborhoods& N) {
  if (N.size() != S.size()) throw InvalidInput(fmt::format("surfels: {} surfels but {} neighbourhoods", S.size(), N.size()));
  std::vector<double> angle;
  angle.reserve(N.indices.size() / 2 + 1);
  for (Eigen::Index i = 0; i < N.size(); ++i)
    for (int k = N.offsets[i]; k < N.offsets[i + 1]; ++k) {
      const int j = N.indices[k];
      if (j <= i) continue;
      const Vec3 a = S.normals.row(i).transpose(), b = S.normals.row(j).transpose();
      angle.push_back(std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI);
    }
  if (angle.empty()) throw InvalidInput("surfels: no neighbour pairs");
  std::nth_element(angle.begin(), angle.begin() + angle.size() / 2, angle.end());
  return angle[angle.size() / 2];
}

double automatic_t_start_deg(const Surfels& initial, const Neighborhoods& N, double t_end_deg) {
  // 0.85 × the median angle: 18.2° on Block0.4 (σ = 0.4), 15.0° on Fandisk0.3 (σ = 0.3) (bench/surfel.md).
  constexpr double kThresholdFactor = 0.85, kHighest = 60.0;
  return std::clamp(kThresholdFactor * median_neighbor_angle_deg(initial, N), t_end_deg, std::max(t_end_deg, kHighest));
}

SurfelOptions tuned_surfel_options(const Surfels& initial, const Neighborhoods& N, SurfelOptions o) {
  const SurfelDenoiseOptions d;  // the surfel pipeline's defaults are the tuned settings
  o.irls_weights = d.weights == SurfelWeights::Irls;
  o.cluster_moves = d.cluster_moves;
  o.iterations = d.iterations;
  o.t_start_deg = automatic_t_start_deg(initial, N, o.t_end_deg);
  return o;
}

namespace {

// Compare the minimisers found with the weights of each distinct neighbouring orientation
// (and the current surfel) on the site energy with the weights of the candidate itself,
// Eq. (7.13): ICM keeps the label of least energy. This escapes the symmetric saddles
// of noiseless data (a surfel on a cube edge exactly between its two faces).
void best_candidate(const std::vector<Vec3>& X, const Neighborhoods& N, const Config& s, Eigen::Index i, double chord,
                    const SurfelOptions& o, std::vector<SiteTerm>& terms, std::vector<Vec3>& starts, Vec3& n,
                    double& rho) {
  const Vec3& x = X[i];
  auto true_energy = [&](const Vec3& cn, double crho) {
    site_terms(X, N, s, i, chord, cn, terms, nullptr, o.irls_weights);
    return term_energy(terms, o.alpha, o.beta, cn, crho);
  };
  double best = true_energy(n, rho);
  const double keep = true_energy(s.n[i], s.n[i].dot(x) - s.a[i]);
  if (keep < best) {
    best = keep;
    n = s.n[i];
    rho = n.dot(x) - s.a[i];
  }
  starts.clear();
  starts.push_back(s.n[i]);
  const double distinct = 0.5 * chord;
  // At most kMaxStarts orientations (a one-ring rarely has more): linear cost at any valence.
  constexpr size_t kMaxStarts = 16;
  for (int k = N.offsets[i]; k < N.offsets[i + 1] && starts.size() < kMaxStarts; ++k) {
    const Vec3& m = s.n[N.indices[k]];
    bool seen = false;
    for (const Vec3& q : starts) seen = seen || (q - m).norm() < distinct;
    if (seen) continue;
    starts.push_back(m);
    site_terms(X, N, s, i, chord, m, terms, nullptr, o.irls_weights);
    Vec3 cn = m;
    double crho = rho;
    minimize_terms(terms, o.alpha, o.beta, cn, crho, o.local_sweeps, 1e-14);
    const double e = true_energy(cn, crho);
    if (e < best) {
      best = e;
      n = cn;
      rho = crho;
    }
  }
}

}  // namespace

SurfelResult optimize_surfels(const MatrixX3d& X, const Neighborhoods& N, const Surfels& initial,
                              const SurfelOptions& o) {
  check_inputs(X, N, initial);
  if (!(o.alpha >= 0) || !(o.beta >= 0)) throw InvalidInput("surfels: alpha and beta must be non-negative");
  if (!(o.t_start_deg > 0) || !(o.t_end_deg > 0) || o.t_start_deg > 180 || o.t_end_deg > 180)
    throw InvalidInput("surfels: angle thresholds must lie in (0, 180] degrees");
  if (o.iterations < 0 || o.iterations_per_threshold < 1 || o.local_sweeps < 1)
    throw InvalidInput("surfels: iteration counts must be positive");

  SurfelResult result;
  result.unit_length = resolve_unit(X, N, o.unit_length);
  Normalized w = normalize(X, initial, X.colwise().mean().transpose(), result.unit_length);
  const Eigen::Index P = X.rows();
  Config next = w.s;
  update_centers(w.X, w.s);
  std::vector<Vec3> patch_mean, guide;
  std::vector<double> patch_spread;
  const std::vector<Vec3>* G = o.guided ? &guide : nullptr;
  if (o.guided) guidance_normals(N, w.s.n, patch_mean, patch_spread, guide);
  if (o.record_energy)
    result.initial_energy = total_energy(w.X, N, w.s, o.alpha, o.beta, threshold_chord(o.t_start_deg), G);

  if (o.cluster_moves) {
    result.cluster_moves += cluster_moves(w.X, N, w.s, o.alpha, o.beta, threshold_chord(o.t_start_deg), 20);
    update_centers(w.X, w.s);
  }
  const int K = o.iterations;
  const int total = K * o.iterations_per_threshold;
  int done = 0;
  for (int k = 0; k < K; ++k) {
    // Exponential decrease from t_start to t_end (Sec. 7.4.3.4).
    const double t = K > 1 ? o.t_start_deg * std::pow(o.t_end_deg / o.t_start_deg, double(k) / (K - 1)) : o.t_start_deg;
    const double chord = threshold_chord(t);
    for (int inner = 0; inner < o.iterations_per_threshold; ++inner) {
      // ICM with two configurations: every site reads the previous one (Sec. 7.4.3.5), so the
      // sweep is order-independent and parallel.
      if (o.guided) guidance_normals(N, w.s.n, patch_mean, patch_spread, guide);
      // A sweep over 2.6 M surfels takes seconds: Ctrl-C skips the rest of it (checked after the region).
      const std::atomic<bool>* stop = InterruptScope::current();
#pragma omp parallel if (P > 4096)
      {
        std::vector<SiteTerm> terms;
        std::vector<Vec3> starts;
#pragma omp for schedule(static)
        for (Eigen::Index i = 0; i < P; ++i) {
          if (interrupt_requested(stop)) continue;
          const Vec3& x = w.X[i];
          // The lagged-weight minimiser from the current surfel (the thesis' scheme).
          site_terms(w.X, N, w.s, i, chord, w.s.n[i], terms, G, o.irls_weights);
          Vec3 n = w.s.n[i];
          double rho = n.dot(x) - w.s.a[i];
          minimize_terms(terms, o.alpha, o.beta, n, rho, o.local_sweeps, 1e-14, false);
          if (o.candidates && !o.guided) best_candidate(w.X, N, w.s, i, chord, o, terms, starts, n, rho);
          next.n[i] = n;
          next.a[i] = n.dot(x) - rho;
        }
      }
      check_interrupt();
      std::swap(w.s.n, next.n);
      std::swap(w.s.a, next.a);
      update_centers(w.X, w.s);
      result.thresholds_deg.push_back(t);
      if (o.record_energy) {
        if (o.guided) guidance_normals(N, w.s.n, patch_mean, patch_spread, guide);
        result.energy.push_back(total_energy(w.X, N, w.s, o.alpha, o.beta, chord, G));
      }
      report(o.progress, double(++done) / std::max(total, 1), "surfel ICM");
    }
  }

  if (o.cluster_moves && K > 0) {
    const double chord = threshold_chord(o.t_end_deg);
    result.cluster_moves += cluster_moves(w.X, N, w.s, o.alpha, o.beta, chord, 20);
    update_centers(w.X, w.s);
  }

  result.surfels.normals.resize(P, 3);
  result.surfels.offsets.resize(P);
  for (Eigen::Index i = 0; i < P; ++i) {
    result.surfels.normals.row(i) = w.s.n[i].transpose();
    result.surfels.offsets[i] = w.s.a[i] * w.unit + w.s.n[i].dot(w.origin);
  }
  return result;
}

}  // namespace geotex
