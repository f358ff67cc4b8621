#version 460
// Pass 2 of the exclusive prefix sum (scan_blocks.comp): the `blocks` block totals scanned in
// place by one workgroup, each thread over a run of consecutive totals.
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) buffer BlockSums { uint blockSums[]; };
layout(push_constant) uniform Push { uint blocks; } pc;

shared uint partial[256];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint run = (pc.blocks + 255) / 256;
  uint first = t * run, last = min(first + run, pc.blocks);
  uint sum = 0;
  for (uint i = first; i < last; i++) sum += blockSums[i];
  partial[t] = sum;
  barrier();
  for (uint d = 1; d < 256; d <<= 1) {
    uint add = t >= d ? partial[t - d] : 0u;
    barrier();
    partial[t] += add;
    barrier();
  }
  uint running = partial[t] - sum;
  for (uint i = first; i < last; i++) {
    uint v = blockSums[i];
    blockSums[i] = running;
    running += v;
  }
}
