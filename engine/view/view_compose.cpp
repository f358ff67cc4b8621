#include "engine/view/view_compose.h"

#include "engine/base/error.h"
#include "engine/base/shared_math.h"
#include "engine/vk/vk_commands.h"

namespace refrax::f64 {
#include "view_compose.glsl"
}  // namespace refrax::f64

namespace refrax {

namespace {
struct ComposePush {
  uint32_t count, mode;
  float heatFullScale;
  uint32_t pad;
};

void validate(const ComposeOptions& o) {
  if (!(o.heatFullScale > 0) || !std::isfinite(o.heatFullScale)) fail("view: the heat map's full scale must be a positive number of hits");
  if (o.mode != ComposeMode::Colour && o.mode != ComposeMode::HitHeatMap) fail("view: unknown compose mode");
}
}  // namespace

ComputePipeline createViewComposePipeline(Context& ctx) {
  return createComputePipeline(ctx, "view_compose", {kStorageBuffer, kStorageBuffer}, sizeof(ComposePush));
}

void cmdComposeView(VkCommandBuffer cb, const ComputePipeline& pipeline, const Buffer& results, const Buffer& pixels, uint32_t count,
                    const ComposeOptions& options) {
  validate(options);
  if (results.size < VkDeviceSize(count) * sizeof(GpuTraceResult) || pixels.size < VkDeviceSize(count) * 4)
    fail("view: buffers too small for " + std::to_string(count) + " pixels");
  ComposePush push{count, uint32_t(options.mode), options.heatFullScale, 0};
  cmdBarrier(cb);
  cmdDispatch(cb, pipeline, {bind(results), bind(pixels)}, &push, groupsFor(count, 64));
}

uint32_t composePixelReference(const GpuTraceResult& r, const ComposeOptions& options) {
  validate(options);
  using namespace f64;
  real3 c = options.mode == ComposeMode::HitHeatMap ? heatMapColour(real(r.hits), real(options.heatFullScale))
                                                    : real3(r.rgb[0], r.rgb[1], r.rgb[2]);
  return packRgba8(c);
}

}  // namespace refrax
