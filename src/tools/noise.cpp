#include "geotex/tools/noise.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "geotex/core/error.h"
#include "geotex/core/geometry.h"
#include "geotex/core/random.h"
#include "geotex/toolkit/laplace.h"

namespace geotex {

const EnumNames<NoisePattern>& noise_pattern_names() {
  static const EnumNames<NoisePattern> n{{"white", NoisePattern::White},
                                         {"low-frequency", NoisePattern::LowFrequency},
                                         {"striped", NoisePattern::Striped}};
  return n;
}

const EnumNames<NoiseDirection>& noise_direction_names() {
  static const EnumNames<NoiseDirection> n{
      {"random", NoiseDirection::Random}, {"normal", NoiseDirection::Normal}, {"depth", NoiseDirection::Depth}};
  return n;
}

const OptionTable<NoiseOptions>& NoiseOptions::table() {
  using O = NoiseOptions;
  static const auto t = OptionTable<O>()
      .add("sigma", &O::sigma, "standard deviation, in mean edge lengths", non_negative())
      .add("along_normal", &O::along_normal, "displace along vertex normals (the same as direction normal)")
      .alias("normal")
      .choice("direction", &O::direction, noise_direction_names(),
              "displacement direction: random per vertex (white only; patterns use the normal), the vertex normal, or depth (along axis: a range scanner's view)")
      .choice("pattern", &O::pattern, noise_pattern_names(),
              "white (independent per vertex), low-frequency (correlated over wavelength), striped (bands across axis)")
      .add("wavelength", &O::wavelength, "low-frequency correlation length / stripe period, mean edge lengths",
           between(1, 1e6))
      .add("axis", &O::axis, "depth: the viewing direction; striped: the stripes run across it", between(-1e6, 1e6))
      .add("impulsive_fraction", &O::impulsive_fraction, "fraction of vertices hit (impulsive noise); 0 = all",
           unit_interval())
      .alias("impulsive")
      .add("seed", &O::seed, "random seed: same seed, same noise");
  return t;
}

namespace {

// A smooth random field of unit standard deviation: white values diffused over the mesh graph (Jacobi
// averaging; k rounds spread a value over about √k rings, so k = (wavelength/2)² gives a correlation over
// ~wavelength edges), then rescaled to unit variance.
Eigen::VectorXd smooth_field(const Mesh& mesh, Eigen::VectorXd x, double wavelength) {
  const int rounds = std::max(1, static_cast<int>(std::lround(0.25 * wavelength * wavelength)));
  const SparseMatrix A = adjacency_matrix(mesh);
  const Eigen::VectorXd inv_size = (1.0 + (A * Eigen::VectorXd::Ones(x.size())).array()).inverse().matrix();  // 1 / (1 + valence)
  for (int r = 0; r < rounds; ++r) x = (A * x + x).cwiseProduct(inv_size);
  x.array() -= x.mean();
  const double sd = std::sqrt(x.squaredNorm() / std::max<Eigen::Index>(1, x.size()));
  if (sd > 0) x /= sd;
  return x;
}

}  // namespace

MatrixX3d add_noise(const Mesh& mesh, const NoiseOptions& opt) {
  require_valid(mesh, "noise: input mesh");
  NoiseOptions::table().check(opt);  // sigma >= 0 and finite, the fraction in [0, 1], the wavelength, …
  const bool fixed_axis = opt.direction == NoiseDirection::Depth || opt.pattern == NoisePattern::Striped;
  if (fixed_axis && !(opt.axis.norm() > 0)) throw InvalidOption("noise: axis must not be zero");
  const Vec3 axis = fixed_axis ? Vec3(opt.axis.normalized()) : Vec3::UnitZ();
  const double s = opt.sigma * mean_edge_length(mesh);
  MatrixX3d X = positions(mesh);
  const MatrixX3d N = vertex_normals(mesh);
  Rng rng(opt.seed);
  const Eigen::Index n = X.rows();
  // Draw every number for every vertex, so that changing the fraction keeps the other draws.
  Eigen::VectorXd pick(n), amount(n);
  MatrixX3d dirs(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    pick[i] = rng.uniform();
    amount[i] = rng.normal();
    dirs.row(i) = Eigen::RowVector3d(rng.normal(), rng.normal(), rng.normal());
  }
  if (opt.pattern == NoisePattern::LowFrequency) {
    amount = smooth_field(mesh, amount, opt.wavelength);
  } else if (opt.pattern == NoisePattern::Striped) {
    // Bands across the axis: t is the position along it, in mean edge lengths.
    const double h = mean_edge_length(mesh), phase = 2 * M_PI * rng.uniform();
    for (Eigen::Index i = 0; i < n; ++i) {
      const double t = X.row(i).dot(axis) / h;
      amount[i] = std::sqrt(0.91) * std::sqrt(2.0) * std::sin(2 * M_PI * t / opt.wavelength + phase) + 0.3 * amount[i];
    }
  }
  // A correlated amount along random directions would be uncorrelated again: the patterns displace along
  // the normals unless told the depth axis.
  NoiseDirection direction = opt.along_normal ? NoiseDirection::Normal : opt.direction;
  if (opt.pattern != NoisePattern::White && direction == NoiseDirection::Random) direction = NoiseDirection::Normal;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (opt.impulsive_fraction > 0 && pick[i] >= opt.impulsive_fraction) continue;
    Vec3 dir = dirs.row(i).transpose();
    if (direction == NoiseDirection::Normal) dir = N.row(i).transpose();
    else if (direction == NoiseDirection::Depth) dir = axis;
    else if (dir.norm() > 0) dir.normalize();
    X.row(i) += s * amount[i] * dir.transpose();
  }
  // Coordinates near the double range (1e200) overflow here: say so rather than return inf (issue 14).
  if (!X.allFinite()) throw InvalidInput("noise: non-finite positions: the coordinates are too large and overflow; scale the mesh down");
  // An output no command could compute with is no output (issue 30): refuse it, naming the limit.
  if (const double reach = X.cwiseAbs().maxCoeff(); reach > kMaxCoordinate)
    throw InvalidInput(fmt::format("noise: sigma {:g} moves vertices to coordinates of {:.3g}, beyond the {:g} geotex computes "
                                   "with: use a smaller sigma", opt.sigma, reach, kMaxCoordinate));
  return X;
}

}  // namespace geotex
