// Generic minimisers (toolkit/numerics.h): known minima of smooth functions.

#include <cmath>

#include <gtest/gtest.h>

#include "geotex/toolkit/numerics.h"

using namespace geotex;
using Vec = Eigen::VectorXd;

namespace {

// Rosenbrock's function in n dimensions: minimum 0 at (1, …, 1), a curved narrow valley.
double rosenbrock(const Vec& x, Vec& g) {
  double f = 0;
  g.setZero(x.size());
  for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
    const double a = x[i + 1] - x[i] * x[i], b = 1 - x[i];
    f += 100 * a * a + b * b;
    g[i] += -400 * x[i] * a - 2 * b;
    g[i + 1] += 200 * a;
  }
  return f;
}

// An ill-conditioned quadratic ½ xᵀ D x − bᵀx, D = diag(1 … 1000): minimum at D⁻¹ b.
double quadratic(const Vec& x, Vec& g) {
  const Vec d = Vec::LinSpaced(x.size(), 1, 1000), b = Vec::Ones(x.size());
  g = d.cwiseProduct(x) - b;
  return 0.5 * x.dot(d.cwiseProduct(x)) - b.dot(x);
}

}  // namespace

TEST(Numerics, LbfgsAndCgFindTheMinimumOfRosenbrock) {
  for (const bool lbfgs : {true, false}) {
    Vec x = Vec::Constant(6, -1.2);
    DescentOptions o;
    o.iterations = lbfgs ? 500 : 20000;
    const double f = lbfgs ? lbfgs_minimize(rosenbrock, x, o) : cg_minimize(rosenbrock, x, o);
    EXPECT_LT(f, 1e-8) << (lbfgs ? "lbfgs" : "cg");
    EXPECT_LT((x - Vec::Ones(6)).norm(), 1e-3) << (lbfgs ? "lbfgs" : "cg");
  }
}

TEST(Numerics, IllConditionedQuadraticAndMonotoneDescent) {
  const Vec d = Vec::LinSpaced(50, 1, 1000);
  const Vec expected = d.cwiseInverse();
  Vec x = Vec::Zero(50);
  DescentOptions o;
  o.iterations = 400;
  lbfgs_minimize(quadratic, x, o);
  EXPECT_LT((x - expected).norm(), 1e-6 * expected.norm() + 1e-8);
  // Each line search lowers f (Armijo): values along the way never increase.
  double last = 0;
  const ValueGradient recorded = [&](const Vec& z, Vec& g) { return quadratic(z, g); };
  Vec y = Vec::Zero(50);
  for (int k = 1; k <= 20; ++k) {
    Vec z = y;
    o.iterations = k;
    const double f = cg_minimize(recorded, z, o);
    EXPECT_LE(f, last + 1e-12);
    last = f;
  }
}

TEST(Numerics, LineSearchRefusesAnAscentDirection) {
  Vec x = Vec::Zero(3), g(3);
  double U = quadratic(x, g);
  double t = 1;
  EXPECT_FALSE(armijo_line_search(quadratic, x, U, g, g, t));  // +g is uphill
  EXPECT_TRUE(armijo_line_search(quadratic, x, U, g, Vec(-g), t));
  EXPECT_LT(U, 0.0);
}
