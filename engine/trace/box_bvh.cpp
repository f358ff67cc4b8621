#include "engine/trace/box_bvh.h"

#include <deque>

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"

namespace refrax {

namespace {
struct RefitPush {  // mirror of shaders/trace/box_bvh_refit.comp
  uint32_t first, count, leaves, pad;
};
}  // namespace

BvhTopology bvhTopology(uint32_t leaves) {
  if (leaves == 0) fail("a BVH needs at least one box");
  BvhTopology t;
  const uint32_t internal = leaves - 1;
  t.nodes.resize(size_t(internal) + leaves, BvhNode{{0, 0, 0}, 0, {0, 0, 0}, 0});
  for (uint32_t k = 0; k < leaves; k++) {
    t.nodes[internal + k].left = kBvhLeaf;
    t.nodes[internal + k].right = k;
  }
  if (internal == 0) {
    t.levelStart = {0};
    return t;
  }
  // Breadth-first over slot ranges [first, last]; a range of one slot is that slot's leaf.
  struct Range {
    uint32_t first, last, level;
  };
  std::deque<Range> queue{{0, leaves - 1, 0}};
  uint32_t next = 0, level = 0;
  t.levelStart.push_back(0);
  auto child = [&](uint32_t first, uint32_t last, uint32_t childLevel) -> uint32_t {
    if (first == last) return internal + first;
    queue.push_back({first, last, childLevel});
    return next + uint32_t(queue.size()) - 1;  // breadth-first: its index follows those queued before it
  };
  while (!queue.empty()) {
    Range r = queue.front();
    queue.pop_front();
    if (r.level != level) {
      level = r.level;
      t.levelStart.push_back(next);
    }
    uint32_t node = next++;
    uint32_t mid = r.first + (r.last - r.first) / 2;
    t.nodes[node].left = child(r.first, mid, r.level + 1);
    t.nodes[node].right = child(mid + 1, r.last, r.level + 1);
  }
  t.levelStart.push_back(next);
  return t;
}

ComputePipeline createBvhRefitPipeline(Context& ctx) {
  return createComputePipeline(ctx, "box_bvh_refit", {kStorageBuffer, kStorageBuffer}, sizeof(RefitPush));
}

BoxBvh createBoxBvh(Context& ctx, uint32_t leaves) {
  BvhTopology t = bvhTopology(leaves);
  BoxBvh b;
  b.leaves = leaves;
  b.nodes = createBufferFrom(ctx, t.nodes);
  b.levelStart = std::move(t.levelStart);
  return b;
}

void cmdRefitBoxBvh(VkCommandBuffer cb, const ComputePipeline& refit, const BoxBvh& bvh, const Buffer& boxes) {
  if (!boxes || boxes.size < uint64_t(bvh.leaves) * 24) fail("BVH refit: the boxes buffer is smaller than its leaves");
  const uint32_t internal = bvh.leaves - 1;
  RefitPush leaves{internal, bvh.leaves, bvh.leaves, 0};
  cmdDispatch(cb, refit, {bind(bvh.nodes), bind(boxes)}, &leaves, groupsFor(bvh.leaves, 64));
  cmdBarrier(cb);
  for (size_t l = bvh.levelStart.size() - 1; l-- > 0;) {
    RefitPush level{bvh.levelStart[l], bvh.levelStart[l + 1] - bvh.levelStart[l], bvh.leaves, 0};
    if (level.count == 0) continue;
    cmdDispatch(cb, refit, {bind(bvh.nodes), bind(boxes)}, &level, groupsFor(level.count, 64));
    cmdBarrier(cb);
  }
}

}  // namespace refrax
