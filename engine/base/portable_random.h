#pragma once
// Random numbers that are the same on every standard library (std:: distributions are not):
// what densification draws must not change with the platform's library.
#include <cmath>
#include <random>

namespace refrax {

// Uniform in (0, 1) from 24 random bits.
inline double portableUniform(std::mt19937& rng) { return (double(rng() >> 8) + 0.5) / 16777216.0; }

// Standard normal from 2 x 24 random bits (Box-Muller).
inline double standardNormal(std::mt19937& rng) {
  double u1 = portableUniform(rng);
  double u2 = double(rng() >> 8) / 16777216.0;  // [0, 1)
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

}  // namespace refrax
