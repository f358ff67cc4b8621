#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Every AABB candidate a ray query reports for each ray (never committed), up to `capacity`
// per ray; counts[i] holds the true number, which may exceed capacity. With the compute trace
// backend: every leaf of the boxes' BVH (engine/trace/box_bvh.h) whose box the ray meets.
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "rays.glsl"
layout(local_size_x = 64) in;
#ifdef REFRAX_COMPUTE_TRACE
#include "box_bvh.glsl"
layout(std430, set = 0, binding = 0) readonly buffer BvhNodes { BvhNode bvhNodes[]; };
#else
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
#endif
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Candidates { uint candidates[]; };
layout(push_constant) uniform Push { uint count; uint capacity; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  Ray r = rays[i];
  uint n = 0u;
#ifdef REFRAX_COMPUTE_TRACE
  vec3 invD = vec3(1.0) / r.dirTmax.xyz;
  uint stack[kBvhStack];
  int sp = 0;
  stack[sp++] = 0u;
  while (sp > 0) {
    BvhNode node = bvhNodes[stack[--sp]];
    if (!bvhBoxHit(node.lo, node.hi, r.originTmin.xyz, invD, r.originTmin.w, r.dirTmax.w)) continue;
    if (node.left != kBvhLeaf) {
      stack[sp++] = node.right;
      stack[sp++] = node.left;
      continue;
    }
    if (n < pc.capacity) candidates[i * pc.capacity + n] = node.right;
    n++;
  }
#else
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsNoOpaqueEXT, 0xFF, r.originTmin.xyz, r.originTmin.w, r.dirTmax.xyz, r.dirTmax.w);
  while (rayQueryProceedEXT(rq)) {
    if (rayQueryGetIntersectionTypeEXT(rq, false) == gl_RayQueryCandidateIntersectionAABBEXT) {
      if (n < pc.capacity) candidates[i * pc.capacity + n] = rayQueryGetIntersectionPrimitiveIndexEXT(rq, false);
      n++;
    }
  }
#endif
  counts[i] = n;
}
