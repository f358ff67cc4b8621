#include "engine/height/height_source.h"

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

HeightSource pointwiseHeightSource(const ComputePipeline& pipeline, std::function<std::vector<uint8_t>(uint32_t count)> pushFor,
                                   const Buffer* table) {
  HeightSource s;
  s.evaluate = [&pipeline, pushFor, table](VkCommandBuffer cb, const Buffer& points, uint32_t count, Buffer& heights) {
    if (count == 0) return;
    const std::vector<uint8_t> push = pushFor(count);
    if (table) cmdDispatch(cb, pipeline, {bind(points), bind(heights), bind(*table)}, push.data(), groupsFor(count, 64));
    else cmdDispatch(cb, pipeline, {bind(points), bind(heights)}, push.data(), groupsFor(count, 64));
  };
  s.evaluateQueued = [&pipeline, pushFor, table](VkCommandBuffer cb, const Buffer& points, Buffer& heights, const Buffer& args,
                                                 VkDeviceSize offset, uint32_t bound) {
    const std::vector<uint8_t> push = pushFor(bound);
    if (table) cmdDispatchIndirect(cb, pipeline, {bind(points), bind(heights), bind(*table)}, push.data(), args, offset);
    else cmdDispatchIndirect(cb, pipeline, {bind(points), bind(heights)}, push.data(), args, offset);
  };
  s.queuedGroup = 64;
  return s;
}

}  // namespace refrax
