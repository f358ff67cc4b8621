#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Gaussian ray tracer forward over an image's rays in 8x8 tiles (engine/gaussian/tiled_trace.h), stage
// 2 after tile_cull.comp: each ray collects its k-buffer hits from its tile's candidate list
// instead of traversing the BVH. Every ray of a tile loops over the same list, so the lanes of
// a SIMD group run in step, where BVH traversals diverge. The accepted hits and their order
// are those of gaussian_forward.comp: the list holds every Gaussian whose cut-off ellipsoid
// any ray of the tile can reach, and each is tested as the ray query's candidates are. A tile
// whose list overflowed its capacity traverses the BVH as gaussian_forward.comp does.
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "rays.glsl"
#include "gaussian_trace_types.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(constant_id = 0) const int K = 16;
layout(constant_id = 1) const bool kInstanced = false;
#include "trace_scene.glsl"
layout(std430, set = 0, binding = 1) restrict readonly buffer Trace { TraceGaussian tg[]; };
layout(std430, set = 0, binding = 2) restrict readonly buffer ShPacked { vec4 shPacked[]; };
layout(std430, set = 0, binding = 3) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Results { TraceResult results[]; };
layout(std430, set = 0, binding = 5) writeonly buffer HitRecords { HitRecord hitRecords[]; };
layout(std430, set = 0, binding = 6) restrict readonly buffer Counts { uint counts[]; };          // per tile
layout(std430, set = 0, binding = 7) restrict readonly buffer Candidates { uint candidates[]; };  // tileCapacity per tile
layout(std430, set = 0, binding = 8) restrict readonly buffer Spheres { vec4 spheres[]; };        // per trace record
REFRAX_TRACE_PUSH
#include "gaussian_kbuffer.glsl"

uint forwardRayIndex() {
  uvec2 px = gl_GlobalInvocationID.xy;
  uint height = pc.count / pc.imageWidth;
  return px.x < pc.imageWidth && px.y < height ? px.y * pc.imageWidth + px.x : 0xFFFFFFFFu;
}

int collectForward(vec3 o, vec3 d, float tcur, uint idcur, float tmax) {
  uint tile = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
  uint listed = counts[tile];
  if (listed > pc.tileCapacity) return collectHits(o, d, tcur, idcur, tmax);
  int n = 0;
  float invLen2 = 1.0 / dot(d, d);
  uint base = tile * pc.tileCapacity;
  for (uint c = 0u; c < listed; c++) {
    uint slot = candidates[base + c];
    // the bounding sphere first: most of a tile's list misses any one of its rays, and this
    // test is a third of insertCandidate's
    vec4 sphere = spheres[slot];
    vec3 p = sphere.xyz - o;
    vec3 off = p - (dot(p, d) * invLen2) * d;
    if (dot(off, off) <= sphere.w * sphere.w) insertCandidate(slot, o, d, invLen2, tcur, idcur, tmax, n);
  }
  return n;
}
#include "gaussian_forward_body.glsl"
