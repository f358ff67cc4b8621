#version 460
// Image loss pass 3 (backward): horizontal window sums of the slopes.
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Slopes { vec4 slope[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Blurred { vec4 blurred[]; };
void main() {
  uint e = elementIndex();
  vec3 s = vec3(0.0);  // .w is padding: not loaded (lavapipe loads gathered vectors per component)
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, false, i, w);
    s += w * slope[i].xyz;
  }
  if (!elementValid()) return;
  blurred[e] = vec4(s, 0.0);
}
