#version 460
// One level of the median split: every list partitioned stably within each range, the elements
// going left first, so each list stays sorted on its axis within the ranges of the next level.
// `before` is the exclusive scan of median_mark.comp's marks over the three lists end to end:
// the left-going elements ahead of slot p in its range are before[q] - before[range start].
#extension GL_GOOGLE_include_directive : require
#include "median_split.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Lists { uint lists[]; };
layout(std430, set = 0, binding = 1) readonly buffer GoesLeft { uint goesLeft[]; };
layout(std430, set = 0, binding = 2) readonly buffer Before { uint before[]; };
layout(std430, set = 0, binding = 3) writeonly buffer ListsOut { uint listsOut[]; };
layout(push_constant) uniform Push { uint n, level; } pc;

void main() {
  uint q = gl_GlobalInvocationID.x;
  if (q >= 3u * pc.n) return;
  uint a = q / pc.n, p = q - a * pc.n;
  uvec2 r = medianSplitRange(p, pc.n, pc.level);
  uint e = lists[q];
  if (r.x == r.y) {
    listsOut[q] = e;
    return;
  }
  uint left = before[q] - before[a * pc.n + r.x];
  uint slot = goesLeft[e] != 0u ? r.x + left : (r.x + r.y) / 2u + 1u + (p - r.x - left);
  listsOut[a * pc.n + slot] = e;
}
