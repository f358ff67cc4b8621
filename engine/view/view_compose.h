#pragma once
// The viewer's last compute stage: the Gaussian tracer's results (GpuTraceResult per ray,
// one ray per pixel) to packed RGBA8 pixels, as the traced colour or as a heat map of the
// hits blended per pixel (shaders/include/view_compose.glsl). Recording starts with a
// barrier, like the other cmd* stages, so it may read the trace recorded just before.
#include <cstdint>
#include <vector>

#include "engine/gaussian/gaussian_trace.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

enum class ComposeMode : uint32_t { Colour = 0, HitHeatMap = 1 };

struct ComposeOptions {
  ComposeMode mode = ComposeMode::Colour;
  float heatFullScale = 32.0f;  // hits shown at the heat map's top colour (> 0)
};

ComputePipeline createViewComposePipeline(Context& ctx);
// pixels[i] = RGBA8 of results[i] for i < count.
void cmdComposeView(VkCommandBuffer cb, const ComputePipeline& pipeline, const Buffer& results, const Buffer& pixels, uint32_t count,
                    const ComposeOptions& options);

// The double-precision reference of one pixel.
uint32_t composePixelReference(const GpuTraceResult& result, const ComposeOptions& options);

}  // namespace refrax
