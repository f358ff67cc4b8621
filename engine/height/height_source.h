#pragma once
// How the water surface asks for heights: evaluate H at a list of points, and push
// dLoss/dheight at a list of points back into H's parameters. The MLP height field
// (engine/height/height_field.h) and the closed-form test surface (engine/height/analytic_height.h) both
// provide one, so the surface geometry does not depend on which H it lifts.
#include <volk.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace refrax {

struct Buffer;

struct HeightSource {
  // heights[k] = H(points[k]) for k < count (points: float2, heights: float).
  std::function<void(VkCommandBuffer, const Buffer& points, uint32_t count, Buffer& heights)> evaluate;
  // The same for a count only the device knows when the commands run: heights[k] = H(points[k])
  // for k < n, dispatched with the group counts at args + argsOffset (a VkDispatchIndirectCommand
  // the caller wrote for groups of queuedGroup points: ceil(n / queuedGroup)). bound >= n is
  // what the caller's buffers hold; lanes past n in the last group may write heights up to it.
  // Empty for a source that cannot (the layered MLP forms): the caller reads n back instead.
  std::function<void(VkCommandBuffer, const Buffer& points, Buffer& heights, const Buffer& args, VkDeviceSize argsOffset, uint32_t bound)>
      evaluateQueued;
  uint32_t queuedGroup = 0;
  // Adds sum_k dLoss/dheight[k] * dH(points[k])/dparams to the source's gradient; empty
  // for sources without parameters.
  std::function<void(VkCommandBuffer, const Buffer& points, const Buffer& dLossdHeight, uint32_t count)> accumulateGradients;
  // The same for the points [0, n) of a count the device wrote (count[0]), bound >= n what the
  // caller's buffers hold: rows of dLossdHeight past n may be set to zero. Returns false,
  // recording nothing, where the source cannot (the caller reads n back instead); empty for
  // sources that never can.
  std::function<bool(VkCommandBuffer, const Buffer& points, const Buffer& dLossdHeight, const Buffer& count, uint32_t bound)>
      accumulateQueued;
};

struct ComputePipeline;
// A source without parameters whose heights one shader writes point by point, in groups of 64
// (the closed-form waves, a height grid): bindings points, heights, then `table` where given;
// push constants pushFor(count) for `count` points. accumulateGradients stays empty.
HeightSource pointwiseHeightSource(const ComputePipeline& pipeline, std::function<std::vector<uint8_t>(uint32_t count)> pushFor,
                                   const Buffer* table = nullptr);

}  // namespace refrax
