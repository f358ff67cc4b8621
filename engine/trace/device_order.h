#pragma once
// Orders on the device (issue 48: the training step's proxies reordered without the host's
// copy of the Gaussians): an exclusive prefix sum, a stable radix sort of uint keys with uint
// values, and the median-split order of presort.h medianSplitOrder over points (the Gaussians'
// centres), which the proxies' BVH is built in.
//
// The median split on the device: the points sorted once on each axis by (coordinate, index),
// then level by level every slot range [first, last] (split at (first + last) / 2 as the host
// and lavapipe split) picks the axis of its longest extent, read off the ends of that axis's
// sorted list, and partitions all three lists stably, the list's first half going left, so
// each stays sorted within the next level's ranges. The result is the host's order over boxes
// of no size at those points, exactly, ties in a coordinate taken by index
// (tests/test_device_order.cpp); a level costs 3 scans' worth of passes over 3n values, not a sort.
#include <cstdint>

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

struct DeviceOrderPipelines {
  ComputePipeline scanBlocks, scanBlockSums, scanAdd;
  ComputePipeline radixCount, radixScatter;
  ComputePipeline medianKeys, medianFlags, medianMark, medianPartition;
};
DeviceOrderPipelines createDeviceOrderPipelines(Context& ctx);

// The block totals an exclusive scan of up to `count` values needs.
Buffer createScanBlockSums(Context& ctx, uint32_t count);
// values[0, count) replaced by their exclusive prefix sums (uint, wrapping).
void cmdExclusiveScan(VkCommandBuffer cb, const DeviceOrderPipelines& p, const Buffer& values, uint32_t count, const Buffer& blockSums);

// Scratch of a radix sort of up to `count` keys: the digit histogram and its scan's block totals.
struct RadixSortScratch {
  Buffer histogram, blockSums;
};
RadixSortScratch createRadixSortScratch(Context& ctx, uint32_t count);
// keys[base, base + count) sorted ascending, values moved with them, stably (equal keys keep
// their values' order); tmpKeys / tmpValues hold the passes between (the same size).
void cmdRadixSort(VkCommandBuffer cb, const DeviceOrderPipelines& p, const Buffer& keys, const Buffer& values, const Buffer& tmpKeys,
                  const Buffer& tmpValues, uint32_t base, uint32_t count, const RadixSortScratch& scratch);

// Scratch of a median-split order of up to `count` points.
struct MedianSplitScratch {
  uint32_t capacity = 0;
  Buffer axisCentres, keys, lists, tmpKeys, tmpLists, goesLeft, scanBlockSums;
  RadixSortScratch sort;
};
MedianSplitScratch createMedianSplitScratch(Context& ctx, uint32_t count);
// The median-split order of n points, point e's x y z the floats at e * stride + offset of
// `points` (the Gaussians' means in their parameters): order[k] = the point in slot k.
struct PointLayout {
  uint32_t stride = 3, offset = 0;  // in floats
};
void cmdMedianSplitOrder(VkCommandBuffer cb, const DeviceOrderPipelines& p, MedianSplitScratch& s, const Buffer& points, PointLayout layout,
                         uint32_t n, const Buffer& order);

// The number of split levels the order of n points takes (ceil(log2 n)).
uint32_t medianSplitLevels(uint32_t n);

}  // namespace refrax
