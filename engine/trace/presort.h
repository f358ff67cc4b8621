#pragma once
// Primitive orders for acceleration-structure builders that do not sort (lavapipe builds a
// binary tree over primitives in input order, splitting at the middle index). Each function
// returns a permutation `order` with order[k] = original index of the k-th primitive to
// submit; keep it to map a hit's primitive index back (original = order[primitiveIndex]).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace refrax {

struct Box {
  float minX, minY, minZ, maxX, maxY, maxZ;  // layout of VkAabbPositionsKHR
};

// Recursive median split on the longest axis of the centroids (the first of equal extents),
// matching lavapipe's (first+last)/2 split exactly (measured 1.6x faster to trace than Morton
// order for boxes); centroids equal on the axis are taken by index, so the order is one order,
// the one engine/trace/device_order.h computes on the device.
std::vector<uint32_t> medianSplitOrder(const std::vector<Box>& boxes);

// Z-order of the cells of a cellsX x cellsY grid (measured 1.8x over row-major for a grid
// mesh); returns cell indices j*cellsX+i in Morton order.
std::vector<uint32_t> mortonCellOrder(uint32_t cellsX, uint32_t cellsY);

template <typename T>
std::vector<T> permuted(const std::vector<T>& items, const std::vector<uint32_t>& order) {
  std::vector<T> out(order.size());
  for (size_t k = 0; k < order.size(); k++) out[k] = items[order[k]];
  return out;
}

}  // namespace refrax
