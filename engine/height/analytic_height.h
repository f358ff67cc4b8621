#pragma once
// A closed-form height field H(x, y) = base + four directional sines or radial ripples
// (shaders/include/analytic_height.glsl) on the GPU and in double on the CPU: a surface to
// test and measure the water-surface geometry with, independent of the MLP.
#include <random>

#include "engine/height/height_source.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct AnalyticWaves {
  float base = 0;
  float waves[4][4] = {};  // (amplitude, kx, ky, phase), or a ripple's (amplitude, cx, cy, k)
  float sigma[4] = {};     // 0: waves[k] is a sine; > 0: a ripple with this envelope width
};

// Random ripples: amplitudes up to `amplitude`, wave numbers up to `maxWaveNumber`.
AnalyticWaves randomWaves(std::mt19937& rng, float amplitude, float maxWaveNumber);

double analyticHeightRef(const AnalyticWaves& w, double x, double y);

struct AnalyticHeightField {
  AnalyticWaves waves;
  ComputePipeline pipeline;
};
AnalyticHeightField createAnalyticHeightField(Context& ctx, const AnalyticWaves& waves);
// A source without parameters (accumulateGradients is empty).
HeightSource heightSource(const AnalyticHeightField& field);

}  // namespace refrax
