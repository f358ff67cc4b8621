#pragma once
// Per-element copies between buffer layouts on the device (shaders/vk/copy_strided.comp): the
// first `channels` floats of each of `count` elements, from a stride of srcStride floats to
// a stride of dstStride floats, the rest of each destination element set to 0; with
// `weights` (one float per element), the copied channels times the element's weight.
#include <cstdint>

#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Buffer;

struct StridedLayout {
  uint32_t stride = 1;  // floats per element
  uint32_t offset = 0;  // floats before the first element
};

ComputePipeline createStridedCopyPipeline(Context& ctx);
// Refuses (refrax::Error) buffers too small for the layouts, before recording.
void cmdCopyStrided(VkCommandBuffer cb, const ComputePipeline& p, const Buffer& src, StridedLayout from, const Buffer& dst, StridedLayout to,
                    uint32_t channels, uint32_t count, const Buffer* weights = nullptr);

}  // namespace refrax
