#version 460
// The lowest and highest z of the proxy mesh's vertices (as ordered uints, include/ordered_float.glsl),
// for the compute trace backend's grid walk (surface_global_trace.comp): the slab its walk
// stays in. range[0] starts at 0xFFFFFFFF and range[1] at 0 (filled by the caller).
#extension GL_GOOGLE_include_directive : require
#include "ordered_float.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Vertices { float vertices[]; };
layout(std430, set = 0, binding = 1) buffer Range { uint range[2]; };
layout(push_constant) uniform Push { uint count; } pc;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.count) return;
  uint z = floatToOrdered(vertices[3 * k + 2]);
  atomicMin(range[0], z);
  atomicMax(range[1], z);
}
