// A box BVH (engine/trace/box_bvh.h) for the compute trace backend: the node layout and the slab
// test. A traversal (gaussian_kbuffer.glsl, mesh_refract.comp) pops nodes from a stack, tests
// their boxes against the ray's interval (which shrinks as hits are found) and visits the
// leaves it meets: what a ray query reports as AABB candidates, in another order.
#ifndef REFRAX_BOX_BVH_GLSL
#define REFRAX_BOX_BVH_GLSL
#include "bvh_node.glsl"
const int kBvhStack = 64;  // the tree's depth is log2 of the slots, rounded up: 24 for 16M

// Ray o + t d against the box [lo, hi] within [t0, t1] (invD = 1 / d per axis, +-inf where d
// is 0); `enter` is where the ray enters it (at least t0).
bool bvhBoxHit(vec3 lo, vec3 hi, vec3 o, vec3 invD, float t0, float t1, out float enter) {
  vec3 a = (lo - o) * invD, b = (hi - o) * invD;
  vec3 near = min(a, b), far = max(a, b);
  // (a NaN from 0 * inf, a ray along a face, takes the box as hit: it is only a candidate)
  enter = max(t0, max(near.x, max(near.y, near.z)));
  float leave = min(t1, min(far.x, min(far.y, far.z)));
  return !(enter > leave);
}
bool bvhBoxHit(vec3 lo, vec3 hi, vec3 o, vec3 invD, float t0, float t1) {
  float enter;
  return bvhBoxHit(lo, hi, o, invD, t0, t1, enter);
}
#endif

