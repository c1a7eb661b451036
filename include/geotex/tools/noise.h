#pragma once
//! \file noise.h Seeded synthetic noise for denoising experiments.

#include <cstdint>

#include "geotex/core/options.h"
#include "geotex/core/mesh.h"

namespace geotex {

struct NoiseOptions {
  double sigma = 0.3;      //!< standard deviation, in units of the mean edge length
  bool along_normal = false;  //!< displace along vertex normals (else along uniformly random directions)
  //! Fraction of vertices hit by impulsive noise (0 = Gaussian noise on every vertex). Impulsive
  //! noise moves only that fraction, with the same σ, as in the "Impulsive" denoising benchmarks.
  double impulsive_fraction = 0.0;
  uint64_t seed = 1;
  static const OptionTable<NoiseOptions>& table();
};

//! \return #V by 3 noisy positions. Same seed, same noise, on every platform.
MatrixX3d add_noise(const Mesh& mesh, const NoiseOptions& options = {});

}  // namespace geotex
