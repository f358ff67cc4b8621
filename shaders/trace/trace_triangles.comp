#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Closest opaque triangle hit for a list of rays: a ray query, or with the compute trace
// backend a walk of the triangles' BVH (include/triangle_bvh.glsl; the triangles in its order).
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "rays.glsl"
layout(local_size_x = 64) in;
#ifdef REFRAX_COMPUTE_TRACE
#include "box_bvh.glsl"
layout(std430, set = 0, binding = 0) readonly buffer BvhNodes { BvhNode bvhNodes[]; };
layout(std430, set = 0, binding = 3) readonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = 4) readonly buffer Indices { uint indices[]; };
vec3 positionAt(uint i) { return vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]); }
#include "triangle_bvh.glsl"
#else
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
#endif
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Hits { TriangleHit hits[]; };
layout(push_constant) uniform Push { uint count; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  Ray r = rays[i];
  TriangleHit h = TriangleHit(-1.0, 0.0, 0.0, kNoHit);
#ifdef REFRAX_COMPUTE_TRACE
  // as a ray query takes them: the direction as given (not unit), t in its units
  uint tri;
  float t;
  vec2 bary;
  if (bvhClosestTriangle(r.originTmin.xyz, r.dirTmax.xyz, r.originTmin.w, r.dirTmax.w, tri, t, bary)) h = TriangleHit(t, bary.x, bary.y, tri);
#else
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, r.originTmin.xyz, r.originTmin.w, r.dirTmax.xyz, r.dirTmax.w);
  while (rayQueryProceedEXT(rq)) {}
  if (rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    vec2 bary = rayQueryGetIntersectionBarycentricsEXT(rq, true);
    h = TriangleHit(rayQueryGetIntersectionTEXT(rq, true), bary.x, bary.y, rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
  }
#endif
  hits[i] = h;
}
