#version 460
// Image loss pass 1: horizontal window sums of x, y, x^2, y^2 (one vec4 per element: lavapipe
// gathers a vec4 far cheaper than four floats) and of xy (x rendered, y target).
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Moments { vec4 m[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Cross { float mxy[]; };
void main() {
  uint e = elementIndex();
  vec4 s = vec4(0.0);
  float sxy = 0.0;
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, false, i, w);
    float a = x[i], b = y[i];
    s += w * vec4(a, b, a * a, b * b);
    sxy += w * a * b;
  }
  if (!elementValid()) return;
  m[e] = s;
  mxy[e] = sxy;
}
