#pragma once
//! \file noise.h Seeded synthetic noise for denoising experiments.

#include <cstdint>

#include "geotex/core/options.h"
#include "geotex/core/mesh.h"

namespace geotex {

//! How the noise varies over the surface. Real scanners do not add independent noise per vertex: their
//! error is correlated over patches (registration, calibration drift) and banded (structured-light
//! stripes, scan lines).
enum class NoisePattern {
  White,         //!< independent per vertex
  LowFrequency,  //!< a smooth random field: correlated over `wavelength` mean edge lengths
  Striped,       //!< bands across the first axis of `axis` (or x): s·√2·sin(2π t / wavelength + φ) plus 30% white
};
const EnumNames<NoisePattern>& noise_pattern_names();

//! The direction of each displacement.
enum class NoiseDirection {
  Random,  //!< uniformly random per vertex (white noise; the other patterns use Normal instead)
  Normal,  //!< along the vertex normal
  Depth,   //!< along one fixed axis (`axis`): a range scanner's viewing direction
};
const EnumNames<NoiseDirection>& noise_direction_names();

struct NoiseOptions {
  double sigma = 0.3;      //!< standard deviation, in units of the mean edge length
  bool along_normal = false;  //!< displace along vertex normals (else along uniformly random directions)
  //! The displacement direction; `along_normal` is the same as Normal (kept for old callers and flags).
  NoiseDirection direction = NoiseDirection::Random;
  NoisePattern pattern = NoisePattern::White;
  double wavelength = 8;   //!< LowFrequency / Striped: correlation length or stripe period, mean edge lengths
  Vec3 axis = Vec3(0, 0, 1);  //!< Depth: the viewing direction; Striped: the stripes run across it
  //! Fraction of vertices hit by impulsive noise (0 = Gaussian noise on every vertex). Impulsive
  //! noise moves only that fraction, with the same σ, as in the "Impulsive" denoising benchmarks.
  double impulsive_fraction = 0.0;
  uint64_t seed = 1;
  static const OptionTable<NoiseOptions>& table();
};

//! \return #V by 3 noisy positions. Same seed, same noise, on every platform.
MatrixX3d add_noise(const Mesh& mesh, const NoiseOptions& options = {});

}  // namespace geotex
