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
  int first = verticalFirst();
  vec3 s[kBlock];
  [[unroll]] for (int j = 0; j < kBlock; j++) s[j] = vec3(0.0);
  [[unroll]] for (int t = 0; t < kTaps; t++) {
    int row = first + t - kSsimRadius;
    vec3 v = verticalInside(row) * blurred[verticalIndex(row)].xyz;  // .w is padding, not loaded
    [[unroll]] for (int j = 0; j < kBlock; j++) s[j] += tapWeight(t, j) * v;
  }
  bool column = verticalColumnValid();
  [[unroll]] for (int j = 0; j < kBlock; j++) {
    uint e = verticalIndex(first + j);
    float xe = x[e], ye = y[e];
    float dSsim = s[j].x + 2.0 * xe * s[j].y + ye * s[j].z;
    if (column && first + j < int(pc.height))
      grad[e] = (kLossL1Weight * l1Slope(xe, ye) - kLossSsimWeight * dSsim) / float(pc.count);
  }
}
