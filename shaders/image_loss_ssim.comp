#version 460
// Image loss pass 2: vertical window sums complete the moments; the SSIM map value and
// its slopes dS/dmu1, dS/dexx, dS/dexy go to three planes, and each workgroup writes its
// sums of the SSIM map and of |x - y| (reduced by reduce_sums).
#extension GL_GOOGLE_include_directive : require
#include "image_loss_pass.glsl"
layout(std430, set = 0, binding = 0) readonly buffer Rendered { float x[]; };
layout(std430, set = 0, binding = 1) readonly buffer Target { float y[]; };
layout(std430, set = 0, binding = 2) readonly buffer Moments { float m[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Slopes { float s[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Partials { vec2 partial[]; };
shared vec2 groupSum[256];
void main() {
  bool valid = gl_GlobalInvocationID.x < pc.count;
  uint e = min(gl_GlobalInvocationID.x, pc.count - 1u);
  float mu1 = 0.0, mu2 = 0.0, exx = 0.0, eyy = 0.0, exy = 0.0;
  [[unroll]] for (int k = -kSsimRadius; k <= kSsimRadius; k++) {
    uint i;
    float w;
    windowTap(e, k, true, i, w);
    mu1 += w * m[i];
    mu2 += w * m[pc.count + i];
    exx += w * m[2u * pc.count + i];
    eyy += w * m[3u * pc.count + i];
    exy += w * m[4u * pc.count + i];
  }
  float value, dMu1, dExx, dExy;
  ssimTerms(mu1, mu2, exx, eyy, exy, value, dMu1, dExx, dExy);
  if (valid) {
    s[e] = dMu1;
    s[pc.count + e] = dExx;
    s[2u * pc.count + e] = dExy;
  }
  uint l = gl_LocalInvocationID.x;
  groupSum[l] = valid ? vec2(abs(x[e] - y[e]), value) : vec2(0.0);
  barrier();
  [[unroll]] for (uint half_ = 128u; half_ > 0u; half_ >>= 1u) {
    if (l < half_) groupSum[l] += groupSum[l + half_];
    barrier();
  }
  if (l == 0u) partial[gl_WorkGroupID.x] = groupSum[0];
}
