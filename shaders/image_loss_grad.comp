#version 460
// Image loss pass 4 (backward): vertical window sums of the slope planes give, at element q,
// A = sum_p G(p-q) dS/dmu1(p), B = ... dS/dexx, C = ... dS/dexy, and
//   dL/dx(q) = (0.8 * sign(x - y) - 0.2 * (A + 2 x B + y C)) / count.
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) readonly buffer Blurred { float b[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Grad { float grad[]; };
void main() {
  uint e = min(gl_GlobalInvocationID.x, pc.count - 1u);
  float A = 0.0, B = 0.0, C = 0.0;
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, true, i, w);
    A += w * b[i];
    B += w * b[pc.count + i];
    C += w * b[2u * pc.count + i];
  }
  if (gl_GlobalInvocationID.x >= pc.count) return;
  float xe = x[e], ye = y[e];
  float dSsim = A + 2.0 * xe * B + ye * C;
  grad[e] = (kLossL1Weight * l1Slope(xe, ye) - kLossSsimWeight * dSsim) / float(pc.count);
}
