#pragma once
//! \file random.h A small, seeded, platform-independent random generator (xoshiro256**, seeded by
//! SplitMix64). std::normal_distribution differs between standard libraries; this does not, so a
//! seed gives the same noise and the same Metropolis run everywhere.

#include <cmath>
#include <cstdint>

namespace geotex {

class Rng {
 public:
  explicit Rng(uint64_t seed = 1) {
    for (auto& s : s_) {
      seed += 0x9E3779B97F4A7C15ull;  // SplitMix64
      uint64_t z = seed;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      s = z ^ (z >> 31);
    }
  }
  uint64_t next() {
    const uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }
  //! Uniform in [0, 1).
  double uniform() { return (next() >> 11) * 0x1.0p-53; }
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  //! Standard normal (Box–Muller; one value per call, the pair's second is discarded for simplicity).
  double normal() {
    double u = uniform();
    while (u <= 0) u = uniform();
    const double v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * M_PI * v);
  }
  //! Uniform integer in [0, n).
  uint64_t below(uint64_t n) { return n ? next() % n : 0; }

 private:
  static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  uint64_t s_[4];
};

}  // namespace geotex
