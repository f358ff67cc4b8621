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
  uint e = elementIndex();
  vec4 mu = vec4(0.0);  // mu1, mu2, exx, eyy
  float exy = 0.0;
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, true, i, w);
    mu += w * m[i];
    exy += w * mxy[i];
  }
  float value, dMu1, dExx, dExy;
  ssimTerms(mu.x, mu.y, mu.z, mu.w, exy, value, dMu1, dExx, dExy);
  float l1 = abs(x[e] - y[e]);
  if (!elementValid()) return;
  slope[e] = vec4(dMu1, dExx, dExy, 0.0);
  term[e] = vec2(l1, value);
}
