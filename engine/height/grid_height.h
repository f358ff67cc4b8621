#pragma once
// A height field given as a grid of heights (the dataset's ground-truth height map), sampled
// bilinearly on the device (shaders/height/grid_heights.comp) as sampleHeight
// (engine/loss/metrics.h, the reference) samples it in double. Why: the known-water oracle
// lifts the true water into the surface, and the closed form (AnalyticWaves) holds at most four
// waves and ripples; the desk, kitchen and toys presets' water has more, and every dataset
// refrax synth writes carries its water as a height map.
#include <cstdint>
#include <vector>

#include "engine/height/height_source.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct GridHeightField {
  uint32_t nx = 0, ny = 0;  // vertices along x and y
  float box[4] = {};        // xMin, yMin, xMax, yMax: vertex (i, j) at xMin + i (xMax - xMin) / (nx - 1), ...
  Buffer heights;           // row by row from yMin, float
  ComputePipeline pipeline;
};

// `heights` row by row from box[1] (nx x ny of them). refrax::Error for fewer than 2 x 2
// vertices, a count that does not match, an empty box or a height that is not finite.
GridHeightField createGridHeightField(Context& ctx, uint32_t nx, uint32_t ny, const double box[4], const std::vector<double>& heights);
// A source without parameters (accumulateGradients is empty).
HeightSource heightSource(const GridHeightField& field);

}  // namespace refrax
