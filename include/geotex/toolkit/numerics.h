#pragma once
//! \file numerics.h Unconstrained minimisation of smooth functions on R^n: L-BFGS and nonlinear
//! conjugate gradients with a backtracking (Armijo) line search (Nocedal & Wright, Numerical
//! Optimization, Alg. 7.4 and 5.4). Used by the MRF vertex process (thesis Sec. 6.3.5 suggests CG).
//!
//! (LBFGS++, packaged in Debian, was considered: its line searches enforce Wolfe conditions and would
//! change every result of the MRF denoiser; these are the textbook algorithms the denoiser was tuned with.)

#include <functional>

#include <Eigen/Core>

namespace geotex {

//! f(x), writing ∇f(x) into g (same size as x).
using ValueGradient = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& g)>;

struct DescentOptions {
  int iterations = 100;     //!< line searches at most
  double rel_tol = 0;       //!< stop when f fell by no more than this fraction of |f| in one iteration
  double first_step = 0.05; //!< first trial step along −g (in the units of x per unit gradient)
  int memory = 8;           //!< L-BFGS: pairs (s, y) kept
};

//! L-BFGS (two-loop recursion) from \p x, which receives the minimiser found. Restarts from steepest
//! descent when a line search fails; stops when it fails from steepest descent. \return f(x).
double lbfgs_minimize(const ValueGradient& f, Eigen::VectorXd& x, const DescentOptions& options = {});

//! Nonlinear conjugate gradients (Polak–Ribière+, restarted when d is not a descent direction) from
//! \p x, which receives the minimiser found. \return f(x).
double cg_minimize(const ValueGradient& f, Eigen::VectorXd& x, const DescentOptions& options = {});

//! Backtracking (Armijo, c = 1e-4) line search along \p d from \p x with value \p U and gradient \p g,
//! first trial step \p t (halved up to 40 times). On success x, U, g and t hold the accepted point.
//! \return false if d is not a descent direction or no step decreased f enough.
bool armijo_line_search(const ValueGradient& f, Eigen::VectorXd& x, double& U, Eigen::VectorXd& g,
                        const Eigen::VectorXd& d, double& t);

}  // namespace geotex
