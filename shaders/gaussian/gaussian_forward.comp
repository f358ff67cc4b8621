#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Gaussian ray tracer forward over any list of rays (camera rays or rays refracted at the
// water): each k-buffer round collects its hits from the proxies' BVH with a ray query (or,
// compute variant, by walking their box BVH). The blend is include/gaussian_forward_body.glsl.
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "rays.glsl"
#include "gaussian_trace_types.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const int K = 16;
layout(constant_id = 1) const bool kInstanced = false;
#include "trace_scene.glsl"
layout(std430, set = 0, binding = 1) restrict readonly buffer Trace { TraceGaussian tg[]; };
layout(std430, set = 0, binding = 2) restrict readonly buffer ShPacked { vec4 shPacked[]; };
layout(std430, set = 0, binding = 3) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Results { TraceResult results[]; };
// written only for the first pc.recordsPerRay hits of each ray (see HitRecord)
layout(std430, set = 0, binding = 5) writeonly buffer HitRecords { HitRecord hitRecords[]; };
REFRAX_TRACE_PUSH
#include "gaussian_kbuffer.glsl"

uint forwardRayIndex() { return gl_GlobalInvocationID.x < pc.count ? gl_GlobalInvocationID.x : 0xFFFFFFFFu; }
int collectForward(vec3 o, vec3 d, float tcur, uint idcur, float tmax) { return collectHits(o, d, tcur, idcur, tmax); }
#include "gaussian_forward_body.glsl"
