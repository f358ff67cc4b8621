#version 460
// Image loss pass 1: horizontal window sums of x, y, x^2, y^2 (one vec4 per element) and of
// xy (x rendered, y target).
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Moments { vec4 m[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Cross { float mxy[]; };
void main() {
  int first = horizontalFirst();
  vec4 s[kBlock];
  float sxy[kBlock];
  [[unroll]] for (int j = 0; j < kBlock; j++) {
    s[j] = vec4(0.0);
    sxy[j] = 0.0;
  }
  [[unroll]] for (int t = 0; t < kTaps; t++) {
    int pixel = first + t - kSsimRadius;
    uint i = horizontalIndex(pixel);
    float inside = horizontalInside(pixel);
    float a = inside * x[i], b = inside * y[i];
    vec4 v = vec4(a, b, a * a, b * b);
    [[unroll]] for (int j = 0; j < kBlock; j++) {
      float w = tapWeight(t, j);
      s[j] += w * v;
      sxy[j] += w * a * b;
    }
  }
  [[unroll]] for (int j = 0; j < kBlock; j++) {
    if (first + j < int(pc.width)) {
      uint e = horizontalIndex(first + j);
      m[e] = s[j];
      mxy[e] = sxy[j];
    }
  }
}
