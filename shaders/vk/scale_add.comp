#version 460
// y[i] = a * x[i] + b: the smallest compute stage, used to test buffers and dispatch.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer X { float x[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Y { float y[]; };
layout(push_constant) uniform Push { float a; float b; uint count; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.count) y[i] = pc.a * x[i] + pc.b;
}
