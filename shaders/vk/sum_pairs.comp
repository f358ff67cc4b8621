#version 460
// Partial sums of `count` vec2: invocation i sums elements [64 i, 64 i + 64), straight-line
// (clamped index, zero weight past the end), and writes one vec2 for reduce_sums. No shared
// memory or barriers (slow on lavapipe).
#extension GL_EXT_control_flow_attributes : require
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Pairs { vec2 v[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Partials { vec2 partial[]; };
layout(push_constant) uniform Push { uint count; } pc;
void main() {
  uint first = gl_GlobalInvocationID.x * 64u;
  vec2 sum = vec2(0.0);
  [[unroll]] for (uint k = 0u; k < 64u; k++) {
    uint e = first + k;
    sum += (e < pc.count ? 1.0 : 0.0) * v[min(e, pc.count - 1u)];
  }
  if (first < pc.count) partial[gl_GlobalInvocationID.x] = sum;
}
