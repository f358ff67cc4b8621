#include "engine/trace/presort.h"

#include <algorithm>
#include <utility>

namespace refrax {

std::vector<uint32_t> medianSplitOrder(const std::vector<Box>& boxes) {
  const int n = int(boxes.size());
  std::vector<uint32_t> idx(n);
  for (int i = 0; i < n; i++) idx[i] = uint32_t(i);
  auto centre2 = [&](uint32_t i, int axis) {  // twice the centroid: the factor does not change the order
    const Box& b = boxes[i];
    return axis == 0 ? b.minX + b.maxX : axis == 1 ? b.minY + b.maxY : b.minZ + b.maxZ;
  };
  std::vector<std::pair<int, int>> stack{{0, n - 1}};
  while (!stack.empty()) {
    auto [first, last] = stack.back();
    stack.pop_back();
    if (first >= last) continue;
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (int i = first; i <= last; i++)
      for (int a = 0; a < 3; a++) {
        float c = centre2(idx[i], a);
        lo[a] = std::min(lo[a], c);
        hi[a] = std::max(hi[a], c);
      }
    int axis = 0;
    for (int a = 1; a < 3; a++)
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    int split = (first + last) / 2;  // lavapipe's split point
    std::nth_element(idx.begin() + first, idx.begin() + split, idx.begin() + last + 1,
                     [&](uint32_t a, uint32_t b) {
                       // ties by index: one order for any std::nth_element, the device's (device_order.h)
                       float ca = centre2(a, axis), cb = centre2(b, axis);
                       return ca < cb || (ca == cb && a < b);
                     });
    stack.push_back({first, split});
    stack.push_back({split + 1, last});
  }
  return idx;
}

namespace {
uint32_t spreadBits16(uint32_t v) {  // 16 bits -> even bit positions
  v &= 0xFFFF;
  v = (v | (v << 8)) & 0x00FF00FF;
  v = (v | (v << 4)) & 0x0F0F0F0F;
  v = (v | (v << 2)) & 0x33333333;
  v = (v | (v << 1)) & 0x55555555;
  return v;
}
}  // namespace

std::vector<uint32_t> mortonCellOrder(uint32_t cellsX, uint32_t cellsY) {
  std::vector<std::pair<uint32_t, uint32_t>> keys;
  keys.reserve(size_t(cellsX) * cellsY);
  for (uint32_t j = 0; j < cellsY; j++)
    for (uint32_t i = 0; i < cellsX; i++) {
      // Cell coordinates scaled to the full 16-bit range first: a Z-curve over the raw indices
      // of a non-power-of-two grid splits it unevenly at lavapipe's middle-index splits
      // (measured 1.6x slower tracing for 200x200 cells).
      uint32_t qx = uint32_t((uint64_t(i) << 16) / cellsX), qy = uint32_t((uint64_t(j) << 16) / cellsY);
      keys.push_back({(spreadBits16(qx) << 1) | spreadBits16(qy), j * cellsX + i});
    }
  std::sort(keys.begin(), keys.end());
  std::vector<uint32_t> order(keys.size());
  for (size_t k = 0; k < keys.size(); k++) order[k] = keys[k].second;
  return order;
}

}  // namespace refrax
