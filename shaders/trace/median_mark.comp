#version 460
// One level of the median split: each list's element marked 1 where it goes left, the input of
// the exclusive scan that median_partition.comp reads.
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Lists { uint lists[]; };
layout(std430, set = 0, binding = 1) readonly buffer GoesLeft { uint goesLeft[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Marks { uint marks[]; };
layout(push_constant) uniform Push { uint n; } pc;

void main() {
  uint q = gl_GlobalInvocationID.x;
  if (q < 3u * pc.n) marks[q] = goesLeft[lists[q]];
}
