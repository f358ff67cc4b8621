#version 460
// Closest opaque triangle hit for a list of rays.
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Hits { TriangleHit hits[]; };
layout(push_constant) uniform Push { uint count; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  Ray r = rays[i];
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, r.originTmin.xyz, r.originTmin.w, r.dirTmax.xyz, r.dirTmax.w);
  while (rayQueryProceedEXT(rq)) {}
  TriangleHit h = TriangleHit(-1.0, 0.0, 0.0, kNoHit);
  if (rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    vec2 bary = rayQueryGetIntersectionBarycentricsEXT(rq, true);
    h = TriangleHit(rayQueryGetIntersectionTEXT(rq, true), bary.x, bary.y, rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
  }
  hits[i] = h;
}
