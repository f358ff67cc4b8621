#include "engine/trace/device_order.h"

#include <algorithm>
#include <utility>

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"

namespace refrax {
namespace {

constexpr uint32_t kGroup = 256;      // every shader's workgroup
constexpr uint32_t kScanBlock = 512;  // scan_blocks.comp: two values per thread
constexpr uint32_t kRadixBits = 4, kRadixDigits = 1u << kRadixBits;

struct RadixPush {  // radix_count.comp, radix_scatter.comp
  uint32_t base, count, shift, blocks;
};
struct LevelPush {  // median_flags.comp, median_partition.comp
  uint32_t n, level;
};
struct KeysPush {  // median_keys.comp
  uint32_t n, stride, offset;
};

VkDeviceSize words(uint64_t n) { return VkDeviceSize(std::max<uint64_t>(n, 1)) * sizeof(uint32_t); }

}  // namespace

DeviceOrderPipelines createDeviceOrderPipelines(Context& ctx) {
  DeviceOrderPipelines p;
  p.scanBlocks = createComputePipeline(ctx, "scan_blocks", storageBuffers(2), 4);
  p.scanBlockSums = createComputePipeline(ctx, "scan_block_sums", storageBuffers(1), 4);
  p.scanAdd = createComputePipeline(ctx, "scan_add", storageBuffers(2), 4);
  p.radixCount = createComputePipeline(ctx, "radix_count", storageBuffers(2), sizeof(RadixPush));
  p.radixScatter = createComputePipeline(ctx, "radix_scatter", storageBuffers(5), sizeof(RadixPush));
  p.medianKeys = createComputePipeline(ctx, "median_keys", storageBuffers(4), sizeof(KeysPush));
  p.medianFlags = createComputePipeline(ctx, "median_flags", storageBuffers(3), sizeof(LevelPush));
  p.medianMark = createComputePipeline(ctx, "median_mark", storageBuffers(3), 4);
  p.medianPartition = createComputePipeline(ctx, "median_partition", storageBuffers(4), sizeof(LevelPush));
  return p;
}

Buffer createScanBlockSums(Context& ctx, uint32_t count) { return createBuffer(ctx, words(groupsFor(count, kScanBlock))); }

void cmdExclusiveScan(VkCommandBuffer cb, const DeviceOrderPipelines& p, const Buffer& values, uint32_t count, const Buffer& blockSums) {
  if (count == 0) return;
  const uint32_t blocks = groupsFor(count, kScanBlock);
  if (blockSums.size < VkDeviceSize(blocks) * sizeof(uint32_t)) fail("cmdExclusiveScan: the block totals' buffer is too small");
  cmdDispatch(cb, p.scanBlocks, {bind(values), bind(blockSums)}, &count, blocks);
  cmdBarrier(cb);
  cmdDispatch(cb, p.scanBlockSums, {bind(blockSums)}, &blocks, 1);
  cmdBarrier(cb);
  cmdDispatch(cb, p.scanAdd, {bind(values), bind(blockSums)}, &count, groupsFor(count, kGroup));
  cmdBarrier(cb);
}

RadixSortScratch createRadixSortScratch(Context& ctx, uint32_t count) {
  const uint32_t histogram = kRadixDigits * std::max<uint32_t>(groupsFor(count, kGroup), 1);
  return {createBuffer(ctx, words(histogram)), createScanBlockSums(ctx, histogram)};
}

void cmdRadixSort(VkCommandBuffer cb, const DeviceOrderPipelines& p, const Buffer& keys, const Buffer& values, const Buffer& tmpKeys,
                  const Buffer& tmpValues, uint32_t base, uint32_t count, const RadixSortScratch& s) {
  if (count <= 1) return;
  const uint32_t blocks = groupsFor(count, kGroup);
  if (s.histogram.size < VkDeviceSize(blocks) * kRadixDigits * sizeof(uint32_t)) fail("cmdRadixSort: the scratch is for fewer keys");
  const Buffer* from[2] = {&keys, &values};
  const Buffer* to[2] = {&tmpKeys, &tmpValues};
  for (uint32_t shift = 0; shift < 32; shift += kRadixBits) {  // 8 passes: the result lands back in keys / values
    RadixPush push{base, count, shift, blocks};
    cmdDispatch(cb, p.radixCount, {bind(*from[0]), bind(s.histogram)}, &push, blocks);
    cmdBarrier(cb);
    cmdExclusiveScan(cb, p, s.histogram, blocks * kRadixDigits, s.blockSums);
    cmdDispatch(cb, p.radixScatter, {bind(*from[0]), bind(*from[1]), bind(*to[0]), bind(*to[1]), bind(s.histogram)}, &push, blocks);
    cmdBarrier(cb);
    std::swap(from[0], to[0]);
    std::swap(from[1], to[1]);
  }
}

MedianSplitScratch createMedianSplitScratch(Context& ctx, uint32_t count) {
  MedianSplitScratch s;
  s.capacity = count;
  const uint64_t lists = 3ull * count;
  s.axisCentres = createBuffer(ctx, words(lists));
  s.keys = createBuffer(ctx, words(lists));
  s.lists = createBuffer(ctx, words(lists));
  s.tmpKeys = createBuffer(ctx, words(lists));
  s.tmpLists = createBuffer(ctx, words(lists));
  s.goesLeft = createBuffer(ctx, words(count));
  s.scanBlockSums = createScanBlockSums(ctx, uint32_t(lists));
  s.sort = createRadixSortScratch(ctx, count);
  return s;
}

uint32_t medianSplitLevels(uint32_t n) {
  uint32_t levels = 0;
  for (uint64_t largest = n; largest > 1; largest = (largest + 1) / 2) levels++;  // a range of s splits into ceil(s/2) and floor(s/2)
  return levels;
}

void cmdMedianSplitOrder(VkCommandBuffer cb, const DeviceOrderPipelines& p, MedianSplitScratch& s, const Buffer& points, PointLayout layout,
                         uint32_t n, const Buffer& order) {
  if (n == 0) return;
  if (n > s.capacity) fail("cmdMedianSplitOrder: the scratch holds fewer points");
  if (n > 0x55555555u) fail("cmdMedianSplitOrder: more points than three lists of uint indices hold");
  if (layout.stride < 3 || layout.offset > layout.stride - 3) fail("cmdMedianSplitOrder: a point's three floats lie outside its stride");
  if (order.size < VkDeviceSize(n) * sizeof(uint32_t)) fail("cmdMedianSplitOrder: the order's buffer holds fewer slots");
  const uint32_t lists = 3 * n;
  KeysPush keys{n, layout.stride, layout.offset};
  cmdDispatch(cb, p.medianKeys, {bind(points), bind(s.axisCentres), bind(s.keys), bind(s.lists)}, &keys, groupsFor(n, kGroup));
  cmdBarrier(cb);
  for (uint32_t axis = 0; axis < 3; axis++)
    cmdRadixSort(cb, p, s.keys, s.lists, s.tmpKeys, s.tmpLists, axis * n, n, s.sort);
  // The keys are spent: their buffer holds each level's marks and their scan.
  const Buffer* in = &s.lists;
  const Buffer* out = &s.tmpLists;
  for (uint32_t level = 0, levels = medianSplitLevels(n); level < levels; level++) {
    LevelPush push{n, level};
    cmdDispatch(cb, p.medianFlags, {bind(*in), bind(s.axisCentres), bind(s.goesLeft)}, &push, groupsFor(n, kGroup));
    cmdBarrier(cb);
    cmdDispatch(cb, p.medianMark, {bind(*in), bind(s.goesLeft), bind(s.keys)}, &n, groupsFor(lists, kGroup));
    cmdBarrier(cb);
    cmdExclusiveScan(cb, p, s.keys, lists, s.scanBlockSums);
    cmdDispatch(cb, p.medianPartition, {bind(*in), bind(s.goesLeft), bind(s.keys), bind(*out)}, &push, groupsFor(lists, kGroup));
    cmdBarrier(cb);
    std::swap(in, out);
  }
  // Every range is one point now, so the three lists agree: the first is the order.
  VkBufferCopy copy{0, 0, VkDeviceSize(n) * sizeof(uint32_t)};
  vkCmdCopyBuffer(cb, in->buffer, order.buffer, 1, &copy);
  cmdBarrier(cb);
}

}  // namespace refrax
