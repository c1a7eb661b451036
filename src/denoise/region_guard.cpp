// A coarse model's change held to what its noise explains, per region (region_guard.h). On a coarse model the
// smooth reading's targets round the facets' dihedral angles, which are shape: even given the true noise level
// the default ended above its noisy input (the cow at σ 0.05: 6.4-6.6° against 4.7-4.8°; bench/denoise.md,
// issue 24, thirteenth to fifteenth sessions).

#include "region_guard.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "geotex/denoise/reading_model.h"

namespace geotex::detail {

namespace {
// Beyond about a radian the small-angle reading of ν² means nothing: a corner's noise can turn a sliver over.
constexpr double kMaxNormalNoise = 1.0;
// A floor for the weights 1 / ν_f (no noise: every change is beyond it, whatever the weights).
constexpr double kMinNormalNoise = 1e-24;

// The unit normal of face f over positions X, and its doubled area.
Vec3 guard_face_normal(const MatrixX3i& F, const MatrixX3d& X, Eigen::Index f, double* doubled_area = nullptr) {
  const Vec3 a = X.row(F(f, 0)), b = X.row(F(f, 1)), c = X.row(F(f, 2));
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (doubled_area) *doubled_area = len;
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}
}  // namespace

Eigen::VectorXd face_normal_noise(const MatrixX3i& F, const MatrixX3d& X, double s) {
  Eigen::VectorXd nu2(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    double a2 = 0;
    guard_face_normal(F, X, f, &a2);
    double sum = 0;
    for (int i = 0; i < 3; ++i) sum += (X.row(F(f, (i + 1) % 3)) - X.row(F(f, (i + 2) % 3))).squaredNorm();
    nu2[f] = a2 > 0 ? std::min(kMaxNormalNoise, s * s * sum / (a2 * a2)) : kMaxNormalNoise;
  }
  return nu2;
}

Eigen::VectorXd region_guard_share(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X, const MatrixX3d& P,
                                   double s) {
  const Eigen::VectorXd nu2 = face_normal_noise(F, X, s);
  Eigen::VectorXd noise = Eigen::VectorXd::Zero(X.rows()), change = Eigen::VectorXd::Zero(X.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    // Each face's terms weighted by 1 / ν_f: the error read is each face's angle, E|θ_f| ≈ √(E θ_f²), whose
    // derivative in t weighs E θ_f² by 1 / (2 ν_f) near the face's own scale. Unweighted, a sliver's large ν²
    // (a thin face's corner height is small) excused a turn of its well-shaped neighbours (the beetle).
    const double w = 1 / std::sqrt(std::max(nu2[f], kMinNormalNoise));
    const double d2 = (guard_face_normal(F, P, f) - guard_face_normal(F, X, f)).squaredNorm();
    for (int k = 0; k < 3; ++k) noise[F(f, k)] += w * nu2[f], change[F(f, k)] += w * d2;
  }
  // Over the vertex's faces and its neighbours' (each face counted once per corner in the closed one-ring).
  noise = ring_sum(N, noise, 1);
  change = ring_sum(N, change, 1);
  Eigen::VectorXd t = Eigen::VectorXd::Ones(X.rows());
  for (Eigen::Index v = 0; v < t.size(); ++v)
    if (change[v] > noise[v]) t[v] = noise[v] / change[v];
  return t;
}

void hold_change_to_noise(const Neighborhoods& N, const MatrixX3i& F, const MatrixX3d& X, double sigma_abs,
                          AutoDenoiseResult& r) {
  if (!(r.noise.noise_share < 1) || !(sigma_abs > 0)) return;
  const Eigen::VectorXd t = region_guard_share(N, F, X, r.positions, sigma_abs / std::sqrt(3.0));
  r.positions = X + t.asDiagonal() * (r.positions - X);
  const double held = (1 - t.array()).mean();
  if (held > 0.005)
    r.choices.push_back(fmt::format("coarse model: the change given back by {:.0f}% on average where it turns the faces "
                                    "beyond what the noise explains", 100 * held));
}

}  // namespace geotex::detail
