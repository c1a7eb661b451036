// The share of a denoiser's change kept per vertex (coherent_change.h).

#include "geotex/denoise/coherent_change.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/denoise/reading_model.h"

namespace geotex {

Eigen::VectorXd coherent_change_gain(const Neighborhoods& N, const MatrixX3d& normals, const MatrixX3d& change,
                                     double noise_var, const CoherentChangeOptions& o) {
  const Eigen::Index n = N.size();
  if (normals.rows() != n || change.rows() != n)
    throw InvalidInput(fmt::format("coherent change: {} normals and {} changes for {} vertices", normals.rows(),
                                   change.rows(), n));
  Eigen::VectorXd gain = Eigen::VectorXd::Ones(n);
  if (o.weight <= 0) return gain;
  const Eigen::VectorXd d = (change.array() * normals.array()).rowwise().sum();
  // Each vertex's products d_v d_u over its edges, their squares and their count: summed over rings, the
  // mean is the local covariance across edges and the squares give its standard error.
  Eigen::VectorXd prod(n), sq(n), count(n);
  for (Eigen::Index v = 0; v < n; ++v) {
    double p = 0, s = 0;
    for (int j = N.offsets[v]; j < N.offsets[v + 1]; ++j) {
      const double q = d[v] * d[N.indices[j]];
      p += q;
      s += q * q;
    }
    prod[v] = p;
    sq[v] = s;
    count[v] = N.offsets[v + 1] - N.offsets[v];
  }
  prod = ring_sum(N, prod, o.rings);
  sq = ring_sum(N, sq, o.rings);
  count = ring_sum(N, count, o.rings);
  for (Eigen::Index v = 0; v < n; ++v) {
    const double m = std::max(1.0, count[v]);
    const double mean = prod[v] / m;
    const double se = std::sqrt(std::max(0.0, sq[v] / m - mean * mean) / m);
    const double coherent = std::max(0.0, mean - o.z * se) / o.rho;
    if (coherent > 0) gain[v] = noise_var / (noise_var + o.weight * coherent);
  }
  return gain;
}

}  // namespace geotex
