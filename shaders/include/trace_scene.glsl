// Binding 0 of the Gaussian tracer's shaders: the proxies' acceleration structure, or with the
// compute trace backend (REFRAX_COMPUTE_TRACE, engine/vk/vk_context.h TraceBackend) their box BVH.
// The including shader enables GL_EXT_ray_query unless REFRAX_COMPUTE_TRACE is defined.
#ifndef REFRAX_TRACE_SCENE_GLSL
#define REFRAX_TRACE_SCENE_GLSL
#ifdef REFRAX_COMPUTE_TRACE
#include "box_bvh.glsl"
layout(std430, set = 0, binding = 0) restrict readonly buffer BvhNodes { BvhNode bvhNodes[]; };
#else
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
#endif
#endif
