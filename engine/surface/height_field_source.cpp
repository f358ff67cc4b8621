#include "engine/surface/height_field_source.h"

#include "engine/base/error.h"

namespace refrax {

HeightSource heightSource(const HeightField& hf) {
  HeightSource s;
  s.evaluate = [&hf](VkCommandBuffer cb, const Buffer& points, uint32_t count, Buffer& heights) {
    if (count) cmdEvaluateHeights(cb, hf, points, count, heights);
  };
  s.queuedGroup = heightsQueuedGroup(hf);
  if (s.queuedGroup)
    s.evaluateQueued = [&hf](VkCommandBuffer cb, const Buffer& points, Buffer& heights, const Buffer& args, VkDeviceSize offset,
                             uint32_t bound) { cmdEvaluateHeightsQueued(cb, hf, points, heights, args, offset, bound); };
  return s;
}

HeightSource heightSource(const HeightField& hf, const Buffer& dLossdWeights) {
  if (dLossdWeights.size < hf.parameterCount * sizeof(float))
    fail("water surface backward: dLossdWeights holds " + std::to_string(dLossdWeights.size / 4) + " floats, the height field has " +
         std::to_string(hf.parameterCount) + " weights");
  HeightSource s = heightSource(hf);
  s.accumulateGradients = [&hf, &dLossdWeights](VkCommandBuffer cb, const Buffer& points, const Buffer& dLossdHeight, uint32_t count) {
    if (count) cmdAccumulateHeightGradients(cb, hf, points, dLossdHeight, count, dLossdWeights);
  };
  s.accumulateQueued = [&hf, &dLossdWeights](VkCommandBuffer cb, const Buffer& points, const Buffer& dLossdHeight, const Buffer& count,
                                              uint32_t bound) {
    return cmdAccumulateHeightGradientsQueued(cb, hf, points, dLossdHeight, count, bound, dLossdWeights);
  };
  return s;
}

}  // namespace refrax
