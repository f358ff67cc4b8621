#pragma once
// A bounding-volume hierarchy over boxes in a given order, for devices without ray queries
// (the compute trace backend, engine/vk/vk_context.h TraceBackend): the Gaussians' proxy boxes
// in their median-split order, or a mesh's triangles. The tree is the one lavapipe builds
// over the same order (each node splits its range of slots at the middle index), laid out
// breadth-first with the leaves after the internal nodes, leaf k at node (leaves - 1) + k.
// Its topology depends only on the count (written once, on the host); its bounds are refitted
// on the device from the boxes (6 floats per slot, min xyz then max xyz), one dispatch per
// level from the leaves up. shaders/include/box_bvh.glsl traverses it.
#include <cstdint>
#include <vector>

#include "engine/base/gpu_layout.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

// BvhNode {lo[3], left, hi[3], right} and kBvhLeaf, declared once in
// shaders/include/bvh_node.glsl: a leaf has left == kBvhLeaf and its slot in right; an
// internal node's children are node indices.
#include "bvh_node.glsl"

// The tree's topology for `leaves` slots (at least 1): the nodes (bounds unset) and the
// breadth-first level of the internal nodes: level l holds nodes [levelStart[l], levelStart[l + 1]).
struct BvhTopology {
  std::vector<BvhNode> nodes;
  std::vector<uint32_t> levelStart;
};
BvhTopology bvhTopology(uint32_t leaves);

struct BoxBvh {
  uint32_t leaves = 0;
  Buffer nodes;
  std::vector<uint32_t> levelStart;
};

// The refit shader (one per context user: GaussianTracer, MeshSurface).
ComputePipeline createBvhRefitPipeline(Context& ctx);
BoxBvh createBoxBvh(Context& ctx, uint32_t leaves);
// The leaves' bounds from `boxes`, then every internal node's from its children.
void cmdRefitBoxBvh(VkCommandBuffer cb, const ComputePipeline& refit, const BoxBvh& bvh, const Buffer& boxes);

}  // namespace refrax
