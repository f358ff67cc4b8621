#version 460
// Image loss pass 3 (backward): horizontal window sums of the three slope planes.
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Slopes { float s[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Blurred { float b[]; };
void main() {
  uint e = min(gl_GlobalInvocationID.x, pc.count - 1u);
  float s0 = 0.0, s1 = 0.0, s2 = 0.0;
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, false, i, w);
    s0 += w * s[i];
    s1 += w * s[pc.count + i];
    s2 += w * s[2u * pc.count + i];
  }
  if (gl_GlobalInvocationID.x >= pc.count) return;
  b[e] = s0;
  b[pc.count + e] = s1;
  b[2u * pc.count + e] = s2;
}
