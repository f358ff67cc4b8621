#version 460
#extension GL_GOOGLE_include_directive : require
// Height field forward, loop-based: one invocation per point, any shape (specialization
// constants). Slow on lavapipe (loads inside loops are scalarised); the generated
// straight-line kernels replace it where one exists for the configuration.
#include "height_encoding.glsl"
#include "height_push.glsl"
#include "height_shape.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Weights { float w[]; };
layout(std430, set = 0, binding = 1) readonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Heights { float heights[]; };

void main() {
  if (gl_GlobalInvocationID.x >= pc.count) return;
  uint i = pc.first + gl_GlobalInvocationID.x;
  vec2 p = points[i];
  if (!heightPointFinite(p)) {
    heights[i] = heightNaN();
    return;
  }
  vec2 u = heightDomainToUnit(p, pc.domainMin, pc.domainMax);
  float enc[INPUTS];
  for (uint k = 0u; k < INPUTS; k++) enc[k] = heightEncodingFeature(u, k, pc.octaveWindow);
  float a[WIDTH];
  float b[WIDTH];
  for (uint j = 0u; j < WIDTH; j++) {
    float s = 0.0;
    for (uint k = 0u; k < INPUTS; k++) s += w[j * INPUTS + k] * enc[k];
    a[j] = heightLeakyRelu(s, SLOPE);
  }
  for (uint l = 1u; l < HIDDEN; l++) {
    uint o = layerWeightOffset(l);
    for (uint j = 0u; j < WIDTH; j++) {
      float s = 0.0;
      for (uint k = 0u; k < WIDTH; k++) s += w[o + j * WIDTH + k] * a[k];
      b[j] = heightLeakyRelu(s, SLOPE);
    }
    for (uint j = 0u; j < WIDTH; j++) a[j] = b[j];
  }
  uint o = layerWeightOffset(HIDDEN);
  float r = 0.0;
  for (uint k = 0u; k < WIDTH; k++) r += w[o + k] * a[k];
  heights[i] = r + pc.initialHeight;
}
