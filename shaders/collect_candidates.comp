#version 460
// Every AABB candidate a ray query reports for each ray (never committed), up to `capacity`
// per ray; counts[i] holds the true number, which may exceed capacity.
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Counts { uint counts[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Candidates { uint candidates[]; };
layout(push_constant) uniform Push { uint count; uint capacity; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  Ray r = rays[i];
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsNoOpaqueEXT, 0xFF, r.originTmin.xyz, r.originTmin.w, r.dirTmax.xyz, r.dirTmax.w);
  uint n = 0u;
  while (rayQueryProceedEXT(rq)) {
    if (rayQueryGetIntersectionTypeEXT(rq, false) == gl_RayQueryCandidateIntersectionAABBEXT) {
      if (n < pc.capacity) candidates[i * pc.capacity + n] = rayQueryGetIntersectionPrimitiveIndexEXT(rq, false);
      n++;
    }
  }
  counts[i] = n;
}
