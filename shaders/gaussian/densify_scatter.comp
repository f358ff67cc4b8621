#version 460
// Densification on the device, pass 3 of 3: the new table, the host's order (densify.h): the
// kept rows in their order, then the clones, then each split parent's two children, where
// `slots` (the scanned marks of densify_accept.comp) puts them. A kept row carries its Adam
// moments and, unless clones or splits were due, its statistic sums; a new row starts at zero.
// A child's mean is drawn from its parent's Gaussian (densify_split.glsl, the host's draws) and
// its sigmas divided by the split divisor.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "gaussian_math.glsl"
#include "densify_split.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Params { float param[]; };
layout(std430, set = 0, binding = 1) readonly buffer FirstMoment { float m[]; };
layout(std430, set = 0, binding = 2) readonly buffer SecondMoment { float v[]; };
layout(std430, set = 0, binding = 3) readonly buffer StatSums { float statSums[]; };
layout(std430, set = 0, binding = 4) readonly buffer Slots { uint slots[]; };
layout(std430, set = 0, binding = 5) writeonly buffer NewParams { float newParam[]; };
layout(std430, set = 0, binding = 6) writeonly buffer NewFirstMoment { float newM[]; };
layout(std430, set = 0, binding = 7) writeonly buffer NewSecondMoment { float newV[]; };
layout(std430, set = 0, binding = 8) writeonly buffer NewStatSums { float newStatSums[]; };
layout(push_constant) uniform Push {
  uint n;
  uint keepStats;       // 1: a prune alone (the survivors keep their statistic)
  uint key;             // the split draws' key
  float logDivisor;     // log of the children's sigma divisor
} pc;

void copyRow(uint from, uint to, bool carry) {
  for (uint c = 0u; c < kGaussFloats; c++) {
    newParam[to * kGaussFloats + c] = param[from * kGaussFloats + c];
    newM[to * kGaussFloats + c] = carry ? m[from * kGaussFloats + c] : 0.0;
    newV[to * kGaussFloats + c] = carry ? v[from * kGaussFloats + c] : 0.0;
  }
  bool stats = carry && pc.keepStats != 0u;
  newStatSums[2u * to] = stats ? statSums[2u * from] : 0.0;
  newStatSums[2u * to + 1u] = stats ? statSums[2u * from + 1u] : 0.0;
}

void main() {
  uint e = gl_GlobalInvocationID.x;
  if (e >= pc.n) return;
  uint n = pc.n;
  if (slots[e + 1u] != slots[e]) copyRow(e, slots[e], true);
  if (slots[n + e + 1u] != slots[n + e]) copyRow(e, slots[n + e], false);
  if (slots[2u * n + e + 1u] == slots[2u * n + e]) return;
  uint b = e * kGaussFloats;
  vec4 q = vec4(param[b + kGaussRotation], param[b + kGaussRotation + 1u], param[b + kGaussRotation + 2u], param[b + kGaussRotation + 3u]);
  vec3 ls = vec3(param[b + kGaussLogScale], param[b + kGaussLogScale + 1u], param[b + kGaussLogScale + 2u]);
  uint first = slots[2u * n] + 2u * (slots[2u * n + e] - slots[2u * n]);
  for (uint c = 0u; c < 2u; c++) {
    uint to = first + c;
    copyRow(e, to, false);
    vec3 offset = splitChildOffset(q, ls, pc.key, e, c);
    for (uint a = 0u; a < 3u; a++) {
      newParam[to * kGaussFloats + kGaussMean + a] = param[b + kGaussMean + a] + offset[a];
      newParam[to * kGaussFloats + kGaussLogScale + a] = ls[a] - pc.logDivisor;
    }
  }
}
