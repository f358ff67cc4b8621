#version 460
// Image loss pass 3 (backward): horizontal window sums of the slopes.
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Slopes { vec4 slope[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Blurred { vec4 blurred[]; };
void main() {
  int first = horizontalFirst();
  vec3 s[kBlock];
  [[unroll]] for (int j = 0; j < kBlock; j++) s[j] = vec3(0.0);
  [[unroll]] for (int t = 0; t < kTaps; t++) {
    int pixel = first + t - kSsimRadius;
    vec3 v = horizontalInside(pixel) * slope[horizontalIndex(pixel)].xyz;  // .w is padding, not loaded
    [[unroll]] for (int j = 0; j < kBlock; j++) s[j] += tapWeight(t, j) * v;
  }
  [[unroll]] for (int j = 0; j < kBlock; j++)
    if (first + j < int(pc.width)) blurred[horizontalIndex(first + j)] = vec4(s[j], 0.0);
}
