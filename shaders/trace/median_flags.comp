#version 460
// One level of the median split (engine/trace/device_order.h): each range of slots at this
// level splits on the axis of its centres' longest extent (the first of equal ones, as the host
// chooses), read off the ends of that axis's list, which is sorted within every range; the
// elements in the range's first half of that list go left. A range of one element stays.
#extension GL_GOOGLE_include_directive : require
#include "median_split.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Lists { uint lists[]; };
layout(std430, set = 0, binding = 1) readonly buffer AxisCentres { float axisCentre[]; };
layout(std430, set = 0, binding = 2) writeonly buffer GoesLeft { uint goesLeft[]; };  // per element
layout(push_constant) uniform Push { uint n, level; } pc;

void main() {
  uint p = gl_GlobalInvocationID.x;
  if (p >= pc.n) return;
  uvec2 r = medianSplitRange(p, pc.n, pc.level);
  if (r.x == r.y) {
    goesLeft[lists[p]] = 1u;
    return;
  }
  float extent[3];
  for (uint a = 0u; a < 3u; a++)
    extent[a] = axisCentre[a * pc.n + lists[a * pc.n + r.y]] - axisCentre[a * pc.n + lists[a * pc.n + r.x]];
  uint axis = 0u;
  if (extent[1] > extent[axis]) axis = 1u;
  if (extent[2] > extent[axis]) axis = 2u;
  goesLeft[lists[axis * pc.n + p]] = p <= (r.x + r.y) / 2u ? 1u : 0u;
}
