#include "engine/trace/triangle_bvh.h"

#include <algorithm>
#include <cmath>

#include "engine/vk/vk_commands.h"

namespace refrax {

std::vector<Box> triangleBoxes(const std::vector<float>& positions, const std::vector<uint32_t>& triangles) {
  std::vector<Box> boxes(triangles.size() / 3);
  for (size_t k = 0; k < boxes.size(); k++) {
    Box& b = boxes[k];
    b = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
    for (int c = 0; c < 3; c++) {
      const float* p = &positions[3 * size_t(triangles[3 * k + c])];
      b.minX = std::min(b.minX, p[0]), b.minY = std::min(b.minY, p[1]), b.minZ = std::min(b.minZ, p[2]);
      b.maxX = std::max(b.maxX, p[0]), b.maxY = std::max(b.maxY, p[1]), b.maxZ = std::max(b.maxZ, p[2]);
    }
  }
  return boxes;
}

std::vector<uint32_t> trianglesInSplitOrder(const std::vector<float>& positions, const std::vector<uint32_t>& triangles) {
  std::vector<uint32_t> order = medianSplitOrder(triangleBoxes(positions, triangles)), out(triangles.size());
  for (size_t k = 0; k < order.size(); k++)
    for (int c = 0; c < 3; c++) out[3 * k + c] = triangles[3 * size_t(order[k]) + c];
  return out;
}

BoxBvh createTriangleBvh(Context& ctx, const std::vector<float>& positions, const std::vector<uint32_t>& trianglesInOrder) {
  Buffer boxes = createBufferFrom(ctx, triangleBoxes(positions, trianglesInOrder));
  BoxBvh bvh = createBoxBvh(ctx, uint32_t(trianglesInOrder.size() / 3));
  ComputePipeline refit = createBvhRefitPipeline(ctx);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdRefitBoxBvh(cb, refit, bvh, boxes); });
  return bvh;
}

}  // namespace refrax
