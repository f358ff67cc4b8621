#version 460
// Densification on the device, pass 1 of 3 (engine/gaussian/densify_device.h; the host's
// engine/gaussian/densify.h is the rule): each Gaussian's fate, pruned for a low density or
// (from pruneLargeFromStep) a large sigma, or a clone/split candidate for its mean gradient
// statistic; the candidates keyed for a stable radix sort by decreasing statistic (the host's
// order: ties by lower row), every other row after them.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "gaussian_math.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Params { float param[]; };
layout(std430, set = 0, binding = 1) readonly buffer StatSums { float statSums[]; };  // per row: gradient statistic, rays
layout(std430, set = 0, binding = 2) writeonly buffer Fate { uint fate[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Keys { uint keys[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Rows { uint rows[]; };
layout(std430, set = 0, binding = 5) buffer Counters { uint counters[]; };  // pruned low, pruned large, candidates, capped out
layout(push_constant) uniform Push {
  uint n;
  uint pruneDue, pruneLarge, densifyDue;
  float minLogit;       // prune below (a very negative logit: none)
  float largeLimit;     // prune a largest sigma above, when pruneLarge
  float gradThreshold;  // a candidate at or above
} pc;

const uint kKeep = 0u, kPrunedLow = 1u, kPrunedLarge = 2u, kCandidate = 3u;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.n) return;
  uint b = i * kGaussFloats;
  float largest = largestSigmaOf(vec3(param[b + kGaussLogScale], param[b + kGaussLogScale + 1u], param[b + kGaussLogScale + 2u]));
  uint f = kKeep;
  if (pc.pruneDue != 0u) {
    if (param[b + kGaussLogitDensity] < pc.minLogit) f = kPrunedLow;
    else if (pc.pruneLarge != 0u && largest > pc.largeLimit) f = kPrunedLarge;
  }
  float hits = statSums[2u * i + 1u];
  float statistic = hits > 0.0 ? statSums[2u * i] / hits : 0.0;
  if (f == kKeep && pc.densifyDue != 0u && statistic >= pc.gradThreshold) f = kCandidate;
  fate[i] = f;
  // The statistic is positive here (at or above a positive threshold): its bits order as it
  // does, so their complement sorts the largest first; no candidate's key reaches ~0u.
  keys[i] = f == kCandidate ? ~floatBitsToUint(statistic) : 0xFFFFFFFFu;
  rows[i] = i;
  if (f != kKeep) atomicAdd(counters[f - 1u], 1u);
}
