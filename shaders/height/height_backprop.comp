#version 460
#extension GL_GOOGLE_include_directive : require
// Height field backward, pass 1 of 2: per point of one chunk, the forward activations and
// the backpropagated deltas of every layer into the scratch (layout: height_shape.glsl).
// A point with non-finite coordinates or dLoss/dHeight gets zero deltas, so it adds nothing.
#include "height_encoding.glsl"
#include "height_push.glsl"
#include "height_shape.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Weights { float w[]; };
layout(std430, set = 0, binding = 1) readonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 2) readonly buffer DLossDHeight { float dLossdHeight[]; };
layout(std430, set = 0, binding = 3) buffer Scratch { float scratch[]; };

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= pc.count) return;
  uint i = pc.first + t;
  vec2 p = points[i];
  float g = dLossdHeight[i];
  if (!heightPointFinite(p) || isnan(g) || isinf(g)) {
    p = pc.domainMin;
    g = 0.0;
  }
  vec2 u = heightDomainToUnit(p, pc.domainMin, pc.domainMax);
  uint x0 = scratchX(0u, pc.chunk) + t * INPUTS;
  for (uint k = 0u; k < INPUTS; k++) scratch[x0 + k] = heightEncodingFeature(u, k, pc.octaveWindow);
  for (uint l = 0u; l < HIDDEN; l++) {
    uint n = layerFanIn(l);
    uint xin = scratchX(l, pc.chunk) + t * n;
    uint xout = scratchX(l + 1u, pc.chunk) + t * WIDTH;
    uint o = layerWeightOffset(l);
    for (uint j = 0u; j < WIDTH; j++) {
      float s = 0.0;
      for (uint k = 0u; k < n; k++) s += w[o + j * n + k] * scratch[xin + k];
      scratch[xout + j] = heightLeakyRelu(s, SLOPE);
    }
  }
  scratch[scratchD(HIDDEN, pc.chunk) + t] = g;
  for (uint l = HIDDEN; l > 0u; l--) {
    // D_{l-1}[k] = (sum_j W_l[j][k] D_l[j]) * lrelu'(X_l[k])
    uint m = layerFanOut(l);
    uint din = scratchD(l, pc.chunk) + t * m;
    uint dout = scratchD(l - 1u, pc.chunk) + t * WIDTH;
    uint xl = scratchX(l, pc.chunk) + t * WIDTH;
    uint o = layerWeightOffset(l);
    for (uint k = 0u; k < WIDTH; k++) {
      float s = 0.0;
      for (uint j = 0u; j < m; j++) s += w[o + j * WIDTH + k] * scratch[din + j];
      scratch[dout + k] = s * heightLeakyReluSlopeAt(scratch[xl + k], SLOPE);
    }
  }
}
