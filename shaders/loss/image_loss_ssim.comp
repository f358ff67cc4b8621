#version 460
// Image loss pass 2: vertical window sums complete the moments; the SSIM map's slopes
// dS/dmu1, dS/dexx, dS/dexy go to one vec4 per element, |x - y| and the SSIM map value to a
// vec2 (summed by sum_pairs: a workgroup reduction with barriers here was slower on lavapipe).
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) readonly buffer Moments { vec4 m[]; };
layout(std430, set = 0, binding = 3) readonly buffer Cross { float mxy[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Slopes { vec4 slope[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Terms { vec2 term[]; };
void main() {
  int first = verticalFirst();
  vec4 mu[kBlock];  // mu1, mu2, exx, eyy
  float exy[kBlock];
  [[unroll]] for (int j = 0; j < kBlock; j++) {
    mu[j] = vec4(0.0);
    exy[j] = 0.0;
  }
  [[unroll]] for (int t = 0; t < kTaps; t++) {
    int row = first + t - kSsimRadius;
    uint i = verticalIndex(row);
    float inside = verticalInside(row);
    vec4 v = inside * m[i];
    float vxy = inside * mxy[i];
    [[unroll]] for (int j = 0; j < kBlock; j++) {
      float w = tapWeight(t, j);
      mu[j] += w * v;
      exy[j] += w * vxy;
    }
  }
  bool column = verticalColumnValid();
  [[unroll]] for (int j = 0; j < kBlock; j++) {
    float value, dMu1, dExx, dExy;
    ssimTerms(mu[j].x, mu[j].y, mu[j].z, mu[j].w, exy[j], value, dMu1, dExx, dExy);
    uint e = verticalIndex(first + j);
    float l1 = abs(x[e] - y[e]);
    if (column && first + j < int(pc.height)) {
      slope[e] = vec4(dMu1, dExx, dExy, 0.0);
      term[e] = vec2(l1, value);
    }
  }
}
