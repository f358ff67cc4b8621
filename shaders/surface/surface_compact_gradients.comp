#version 460
// Appends the points whose dL/dheight is not zero, with that gradient, to one list (the
// surface's pending gradient is pushed into H's parameters over that list only: about two
// thirds of the coarse grid and a few of the cached points have none).
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { uint count; } pc;
layout(std430, set = 0, binding = 0) readonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 1) readonly buffer Grads { float grads[]; };
layout(std430, set = 0, binding = 2) writeonly buffer OutPoints { vec2 outPoints[]; };
layout(std430, set = 0, binding = 3) writeonly buffer OutGrads { float outGrads[]; };
layout(std430, set = 0, binding = 4) buffer Count { uint outCount; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  float g = grads[i];
  if (g == 0.0) return;  // NaN and inf pass: the height field's backward counts them out
  uint k = atomicAdd(outCount, 1u);
  outPoints[k] = points[i];
  outGrads[k] = g;
}
