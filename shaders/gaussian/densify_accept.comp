#version 460
// Densification on the device, pass 2 of 3: the candidates, sorted by decreasing statistic,
// are taken while the count stays within the cap (every clone or split adds one row, so that
// is the first `room` of them), cloned when their largest sigma is at most the clone limit and
// split otherwise; each row marked in one array of three parts for one exclusive scan: kept
// rows [0, n), clones [n, 2n), split parents [2n, 3n), and a last 0 whose scan is the total.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "gaussian_math.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Params { float param[]; };
layout(std430, set = 0, binding = 1) readonly buffer Fate { uint fate[]; };
layout(std430, set = 0, binding = 2) readonly buffer SortedRows { uint sortedRows[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Marks { uint marks[]; };  // 3n + 1
layout(std430, set = 0, binding = 4) buffer Counters { uint counters[]; };
layout(push_constant) uniform Push {
  uint n;
  uint maxGaussians;
  float cloneLimit;
} pc;

const uint kKeep = 0u, kCandidate = 3u;

void main() {
  uint j = gl_GlobalInvocationID.x;
  if (j >= pc.n) return;
  if (j == 0u) marks[3u * pc.n] = 0u;
  uint e = sortedRows[j];
  uint f = fate[e];
  uint kept = pc.n - counters[0] - counters[1];  // the pruned rows are gone
  uint room = pc.maxGaussians > kept ? pc.maxGaussians - kept : 0u;
  bool accepted = f == kCandidate && j < room;  // the candidates come first, by decreasing statistic
  uint b = e * kGaussFloats;
  float largest = largestSigmaOf(vec3(param[b + kGaussLogScale], param[b + kGaussLogScale + 1u], param[b + kGaussLogScale + 2u]));
  bool clone = accepted && largest <= pc.cloneLimit;
  bool split = accepted && !clone;
  marks[e] = (f == kKeep || (f == kCandidate && !split)) ? 1u : 0u;
  marks[pc.n + e] = clone ? 1u : 0u;
  marks[2u * pc.n + e] = split ? 1u : 0u;
  if (f == kCandidate && !accepted) atomicAdd(counters[3], 1u);  // capped out
}
