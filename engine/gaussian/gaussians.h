#pragma once
// A set of 3D Gaussians as raw (pre-activation) parameters, kGaussFloats floats each in the
// layout of shaders/include/gaussian_math.glsl: mean, rotation quaternion (w first), log
// scale, logit density, SH degree 3 (coefficient-major, 16 x RGB). The same flat layout is
// uploaded to the device as is, and gradients come back in it.
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

#include "engine/vk/vk_buffer.h"

namespace refrax {

constexpr uint32_t kGaussianFloats = 59;

struct GaussianSet {
  std::vector<float> params;  // count() * kGaussianFloats
  size_t count() const { return params.size() / kGaussianFloats; }
  float* at(size_t i) { return params.data() + i * kGaussianFloats; }
  const float* at(size_t i) const { return params.data() + i * kGaussianFloats; }
};

// The device copy of a GaussianSet (same flat layout). Uploads are validated first.
struct DeviceGaussians {
  Buffer params;
  uint32_t count = 0;
};
DeviceGaussians uploadGaussians(Context& ctx, const GaussianSet& set);
void updateGaussians(Context& ctx, DeviceGaussians& dev, const GaussianSet& set);  // same count
GaussianSet downloadGaussians(Context& ctx, const DeviceGaussians& dev);

// Fails with one clear message if any parameter is NaN or infinite, or a quaternion is zero.
void validateGaussians(const GaussianSet& set, const char* what);

// Random Gaussians with means uniform in [lo, hi], sigmas in [sigmaMin, sigmaMax], random
// rotations, densities in [densityMin, densityMax] and SH coefficients of `shScale` (DC
// around a random colour). For tests and benchmarks.
struct RandomGaussianOptions {
  float lo[3] = {-0.5f, -0.5f, -1.0f};
  float hi[3] = {0.5f, 0.5f, 0.0f};
  float sigmaMin = 0.01f, sigmaMax = 0.05f;
  float densityMin = 0.05f, densityMax = 0.95f;
  float shScale = 0.3f;
};
GaussianSet randomGaussians(std::mt19937& rng, size_t count, const RandomGaussianOptions& options = {});

}  // namespace refrax
