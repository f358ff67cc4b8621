#version 460
// Pass 3 of the exclusive prefix sum (scan_blocks.comp): each value gets its block's offset.
layout(local_size_x = 256) in;
const uint kScanBlock = 512;
layout(std430, set = 0, binding = 0) buffer Values { uint values[]; };
layout(std430, set = 0, binding = 1) readonly buffer BlockSums { uint blockSums[]; };
layout(push_constant) uniform Push { uint count; } pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.count) values[i] += blockSums[i / kScanBlock];
}
