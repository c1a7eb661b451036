#include "geotex/tools/noise.h"

#include <cmath>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"

namespace geotex {

const OptionTable<NoiseOptions>& NoiseOptions::table() {
  using O = NoiseOptions;
  static const auto t = OptionTable<O>()
      .add("sigma", &O::sigma, "standard deviation, in mean edge lengths", non_negative())
      .add("along_normal", &O::along_normal, "displace along vertex normals (else along random directions)")
      .alias("normal")
      .add("impulsive_fraction", &O::impulsive_fraction, "fraction of vertices hit (impulsive noise); 0 = all",
           unit_interval())
      .alias("impulsive")
      .add("seed", &O::seed, "random seed: same seed, same noise");
  return t;
}

MatrixX3d add_noise(const Mesh& mesh, const NoiseOptions& opt) {
  require_valid(mesh, "noise: input mesh");
  if (!(opt.sigma >= 0) || !std::isfinite(opt.sigma)) throw InvalidInput("noise: sigma must be >= 0");
  if (!(opt.impulsive_fraction >= 0 && opt.impulsive_fraction <= 1))
    throw InvalidInput("noise: impulsive fraction must be in [0, 1]");
  const double s = opt.sigma * mean_edge_length(mesh);
  MatrixX3d X = positions(mesh);
  const MatrixX3d N = vertex_normals(mesh);
  Rng rng(opt.seed);
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    // Draw every number for every vertex, so that changing the fraction keeps the other draws.
    const double pick = rng.uniform();
    const double amount = s * rng.normal();
    Vec3 dir(rng.normal(), rng.normal(), rng.normal());
    if (opt.impulsive_fraction > 0 && pick >= opt.impulsive_fraction) continue;
    if (opt.along_normal) dir = N.row(i);
    else if (dir.norm() > 0) dir.normalize();
    X.row(i) += amount * dir.transpose();
  }
  // Coordinates near the double range (1e200) overflow here: say so rather than return inf (issue 14).
  if (!X.allFinite()) throw InvalidInput("noise: non-finite positions: the coordinates are too large and overflow; scale the mesh down");
  return X;
}

}  // namespace geotex
