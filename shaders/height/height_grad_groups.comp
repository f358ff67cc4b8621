#version 460
// The group counts of the height backward's dispatches for a point count only the device
// knows (cmdAccumulateHeightGradientsQueued, engine/height/height_field.cpp). The host writes
// one 8-uint entry per dispatch, {first, limit, roundTo, groupSize, x, y, z, clear}; this fills
// x with the groups that cover the dispatch's share of the points [0, count): n = the count's
// part of [first, first + limit), rounded up to roundTo and capped at limit (pass 1 writes every
// scratch row that pass 2's tiles read). y and z are the host's. An entry with clear = 1 also
// zeroes dLossdHeight's rows [first + n, first + covered): they lie past the count, and pass 2
// reads them as part of the count's last tile.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Count { uint count[]; };
layout(std430, set = 0, binding = 1) buffer Entries { uint entries[]; };
layout(std430, set = 0, binding = 2) buffer DLossDHeight { float dLossdHeight[]; };
layout(push_constant) uniform Push { uint entryCount; } pc;
void main() {
  uint e = gl_GlobalInvocationID.x;
  if (e >= pc.entryCount) return;
  uint first = entries[8u * e], limit = entries[8u * e + 1u];
  uint roundTo = entries[8u * e + 2u], groupSize = entries[8u * e + 3u];
  uint n = count[0] > first ? min(count[0] - first, limit) : 0u;
  uint covered = min((n + roundTo - 1u) / roundTo * roundTo, limit);
  entries[8u * e + 4u] = (covered + groupSize - 1u) / groupSize;
  if (entries[8u * e + 7u] == 1u)
    for (uint k = first + n; k < first + covered; k++) dLossdHeight[k] = 0.0;
}
