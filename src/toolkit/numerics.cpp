// Unconstrained minimisers of smooth functions (numerics.h).

#include "geotex/toolkit/numerics.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geotex/core/progress.h"

namespace geotex {

using Vec = Eigen::VectorXd;

bool armijo_line_search(const ValueGradient& f, Vec& x, double& U, Vec& g, const Vec& d, double& t) {
  const double slope = g.dot(d);
  if (!(slope < 0)) return false;
  Vec z(x.size()), gz(x.size());
  for (int bt = 0; bt < 40; ++bt) {
    z = x + t * d;
    const double Uz = f(z, gz);
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

double lbfgs_minimize(const ValueGradient& f, Vec& x, const DescentOptions& o) {
  Vec g(x.size());
  double U = f(x, g);
  std::vector<Vec> S, Y;
  std::vector<double> rho;
  double t = 1.0;
  for (int it = 0; it < o.iterations; ++it) {
    check_interrupt();
    // Two-loop recursion: q = −H g.
    Vec q = -g;
    std::vector<double> al(S.size());
    for (int k = static_cast<int>(S.size()) - 1; k >= 0; --k) {
      al[k] = rho[k] * S[k].dot(q);
      q -= al[k] * Y[k];
    }
    double gamma = o.first_step;  // no curvature pairs yet: a small step per unit gradient
    if (!S.empty()) gamma = S.back().dot(Y.back()) / Y.back().squaredNorm();
    q *= gamma;
    for (size_t k = 0; k < S.size(); ++k) {
      const double b = rho[k] * Y[k].dot(q);
      q += (al[k] - b) * S[k];
    }
    const Vec x_old = x, g_old = g;
    const double U_old = U;
    t = 1.0;
    if (!armijo_line_search(f, x, U, g, q, t)) {
      if (S.empty()) break;
      S.clear();
      Y.clear();
      rho.clear();
      continue;
    }
    Vec s = x - x_old, y = g - g_old;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {  // keep H positive definite
      if (static_cast<int>(S.size()) == o.memory) {
        S.erase(S.begin());
        Y.erase(Y.begin());
        rho.erase(rho.begin());
      }
      S.push_back(std::move(s));
      Y.push_back(std::move(y));
      rho.push_back(1.0 / sy);
    }
    if (U_old - U <= o.rel_tol * std::abs(U_old)) break;
  }
  return U;
}

double cg_minimize(const ValueGradient& f, Vec& x, const DescentOptions& o) {
  Vec g(x.size());
  double U = f(x, g);
  Vec d = -g;
  double t = o.first_step;
  for (int it = 0; it < o.iterations; ++it) {
    check_interrupt();
    if (g.dot(d) >= 0) d = -g;
    const Vec g_old = g;
    const double U_old = U;
    double t_try = std::min(4.0 * t, 1.0);
    if (!armijo_line_search(f, x, U, g, d, t_try)) {
      if (d == -g_old) break;
      d = -g;
      continue;
    }
    t = t_try;
    const double beta = std::max(0.0, g.dot(g - g_old) / g_old.squaredNorm());  // Polak–Ribière+
    d = -g + beta * d;
    if (U_old - U <= o.rel_tol * std::abs(U_old)) break;
  }
  return U;
}

}  // namespace geotex
