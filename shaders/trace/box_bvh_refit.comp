#version 460
// Bounds of one level of a box BVH (engine/trace/box_bvh.h): a leaf's from its slot's box, an
// internal node's from its two children (refitted by the previous dispatch).
#extension GL_GOOGLE_include_directive : require
#include "box_bvh.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) buffer Nodes { BvhNode nodes[]; };
layout(std430, set = 0, binding = 1) readonly buffer Boxes { float boxes[]; };
layout(push_constant) uniform Push { uint first, count, leaves, pad; } pc;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.count) return;
  uint i = pc.first + k;
  BvhNode n = nodes[i];
  if (n.left == kBvhLeaf) {
    uint b = 6u * n.right;
    nodes[i].lo = vec3(boxes[b], boxes[b + 1u], boxes[b + 2u]);
    nodes[i].hi = vec3(boxes[b + 3u], boxes[b + 4u], boxes[b + 5u]);
    return;
  }
  nodes[i].lo = min(nodes[n.left].lo, nodes[n.right].lo);
  nodes[i].hi = max(nodes[n.left].hi, nodes[n.right].hi);
}
