#pragma once
// A height field given as a grid of heights (a HeightGrid: the dataset's ground-truth height map),
// sampled bilinearly on the device (shaders/height/grid_heights.comp) as sampleHeight samples it
// in double. Why: the known-water oracle lifts the true water into the surface, and the closed
// form (AnalyticWaves) holds at most four waves and ripples; the desk, kitchen and toys presets'
// water has more, and every dataset refrax synth writes carries its water as a height map.
#include "engine/height/height_source.h"
#include "engine/loss/metrics.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct GridHeightField {
  HeightGrid grid;  // the heights in double, for the host (sampleHeight)
  Buffer heights;   // the same in float, row by row
  ComputePipeline pipeline;
};

// refrax::Error for a grid validateHeightGrid refuses.
GridHeightField createGridHeightField(Context& ctx, HeightGrid grid);
// A source without parameters (accumulateGradients is empty).
HeightSource heightSource(const GridHeightField& field);

}  // namespace refrax
