// A box BVH's node (std430, one source for the shaders and the host: layout_prelude.glsl; the
// host's engine/trace/box_bvh.h builds the tree, box_bvh.glsl walks it). A leaf has
// left == kBvhLeaf and its slot in `right`; an internal node's children are node indices.
#ifndef REFRAX_BVH_NODE_GLSL
#define REFRAX_BVH_NODE_GLSL
#include "layout_prelude.glsl"
LAYOUT_STRUCT(BvhNode, BvhNode)
  LAYOUT_VEC3(lo)
  LAYOUT_UINT(left)  // kBvhLeaf: a leaf, its slot in `right`
  LAYOUT_VEC3(hi)
  LAYOUT_UINT(right)
LAYOUT_END(BvhNode, 32)
LAYOUT_CONST(kBvhLeaf, 0xFFFFFFFFu)
#endif
