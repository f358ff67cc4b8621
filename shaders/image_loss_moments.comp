#version 460
// Image loss pass 1: horizontal window sums of x, y, x^2, y^2, xy (x rendered, y target),
// written as five planes of `count` floats.
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Moments { float m[]; };
void main() {
  uint e = min(gl_GlobalInvocationID.x, pc.count - 1u);
  float sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, false, i, w);
    float a = x[i], b = y[i];
    sx += w * a;
    sy += w * b;
    sxx += w * a * a;
    syy += w * b * b;
    sxy += w * a * b;
  }
  if (gl_GlobalInvocationID.x >= pc.count) return;
  m[e] = sx;
  m[pc.count + e] = sy;
  m[2u * pc.count + e] = sxx;
  m[3u * pc.count + e] = syy;
  m[4u * pc.count + e] = sxy;
}
