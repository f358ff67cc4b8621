// The host side of engine/gaussian/gaussians.h: checks and random sets, without a device (the PLY and
// checkpoint loaders use it, also in the fuzz build).
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussians.h"

namespace refrax {

void validateGaussians(const GaussianSet& set, const char* what) {
  if (set.params.size() % kGaussianFloats != 0) fail(std::string(what) + ": parameter count is not a multiple of " + std::to_string(kGaussianFloats));
  for (size_t i = 0; i < set.count(); i++) {
    const float* g = set.at(i);
    for (uint32_t k = 0; k < kGaussianFloats; k++)
      if (!std::isfinite(g[k]))
        fail(std::string(what) + ": Gaussian " + std::to_string(i) + " has a non-finite parameter (float " + std::to_string(k) + ")");
    const float* q = g + f32::kGaussRotation;
    if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0) fail(std::string(what) + ": Gaussian " + std::to_string(i) + " has a zero rotation quaternion");
  }
}

GaussianSet randomGaussians(std::mt19937& rng, size_t count, const RandomGaussianOptions& o) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::normal_distribution<float> N(0.0f, 1.0f);
  GaussianSet set;
  set.params.assign(count * kGaussianFloats, 0.0f);
  for (size_t i = 0; i < count; i++) {
    float* g = set.at(i);
    for (int a = 0; a < 3; a++) g[f32::kGaussMean + a] = o.lo[a] + (o.hi[a] - o.lo[a]) * U(rng);
    for (int a = 0; a < 4; a++) g[f32::kGaussRotation + a] = N(rng);
    if (std::fabs(g[f32::kGaussRotation]) < 1e-3f) g[f32::kGaussRotation] = 1.0f;
    for (int a = 0; a < 3; a++) g[f32::kGaussLogScale + a] = std::log(o.sigmaMin + (o.sigmaMax - o.sigmaMin) * U(rng));
    float density = o.densityMin + (o.densityMax - o.densityMin) * U(rng);
    g[f32::kGaussLogitDensity] = std::log(density / (1.0f - density));
    // DC: a random colour in [0.1, 0.9] (SH0 * c + 0.5 = colour), higher bands small.
    for (int c = 0; c < 3; c++) g[f32::kGaussSH + c] = (0.1f + 0.8f * U(rng) - 0.5f) / 0.28209479177387814f;
    for (uint32_t k = 1; k < f32::kShCoefficients; k++)
      for (int c = 0; c < 3; c++) g[f32::kGaussSH + 3 * k + c] = o.shScale * (2 * U(rng) - 1) / float(k);
  }
  return set;
}

}  // namespace refrax
