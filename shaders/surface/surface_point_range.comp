#version 460
// One level's new lattice points, counted on the device (the one-submission trace of
// engine/surface/water_surface.cpp): the points queued since the last evaluation,
// [range[0], counters[0]), as (base, n), and the group counts of the dispatches that gather,
// evaluate and scatter them. range: [0] evaluated so far, [1] base, [2] n, [4..6] groups of
// 64 points, [8..10] groups of the height source's heightGroup points.
layout(local_size_x = 1) in;
layout(std430, set = 0, binding = 0) readonly buffer Counters { uint counters[]; };
layout(std430, set = 0, binding = 1) buffer Range { uint range[]; };
layout(push_constant) uniform Push { uint heightGroup; uint capacity; } pc;
void main() {
  uint base = range[0];
  uint end = min(counters[0], pc.capacity);  // past the capacity the host fails after the trace
  uint n = end > base ? end - base : 0u;
  range[0] = end;
  range[1] = base;
  range[2] = n;
  range[4] = (n + 63u) / 64u;
  range[5] = 1u;
  range[6] = 1u;
  range[8] = (n + pc.heightGroup - 1u) / pc.heightGroup;
  range[9] = 1u;
  range[10] = 1u;
}
