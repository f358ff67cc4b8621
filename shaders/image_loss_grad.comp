#version 460
// Image loss pass 4 (backward): vertical window sums of the slopes give, at element q,
// A = sum_p G(p-q) dS/dmu1(p), B = ... dS/dexx, C = ... dS/dexy, and
//   dL/dx(q) = (0.8 * sign(x - y) - 0.2 * (A + 2 x B + y C)) / count.
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) readonly buffer Blurred { vec4 blurred[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Grad { float grad[]; };
void main() {
  uint e = elementIndex();
  vec3 s = vec3(0.0);  // .w is padding: not loaded
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, true, i, w);
    s += w * blurred[i].xyz;
  }
  float xe = x[e], ye = y[e];
  float dSsim = s.x + 2.0 * xe * s.y + ye * s.z;
  if (!elementValid()) return;
  grad[e] = (kLossL1Weight * l1Slope(xe, ye) - kLossSsimWeight * dSsim) / float(pc.count);
}
