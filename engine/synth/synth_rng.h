#pragma once
// Counter-based random numbers for the synthetic data generator: every draw is a pure
// function of (seed, stream keys), so renders are byte-identical however threads interleave.
#include <cmath>
#include <cstdint>

namespace refrax::synth {

inline uint64_t splitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline uint64_t mixKeys(uint64_t a, uint64_t b) { return splitMix64(a ^ splitMix64(b + 0x632BE59BD9B4E019ull)); }

struct SynthRng {
  uint64_t state;
  explicit SynthRng(uint64_t seed) : state(splitMix64(seed)) {}
  uint64_t next() { return state = splitMix64(state); }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Standard normal by Box-Muller (one value per call; simple over fast).
  double normal() {
    double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
};

}  // namespace refrax::synth
