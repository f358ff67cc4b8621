#version 460
// An exclusive prefix sum over `count` uints, pass 1 of 3 (engine/trace/device_order.h
// cmdExclusiveScan): each block of kScanBlock values is scanned in place, and its total written
// to blockSums[block]. Pass 2 (scan_block_sums.comp) scans the totals, pass 3 (scan_add.comp)
// adds each block's offset.
layout(local_size_x = 256) in;
const uint kScanBlock = 512;  // two values per thread
layout(std430, set = 0, binding = 0) buffer Values { uint values[]; };
layout(std430, set = 0, binding = 1) buffer BlockSums { uint blockSums[]; };
layout(push_constant) uniform Push { uint count; } pc;

shared uint partial[256];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint base = gl_WorkGroupID.x * kScanBlock + 2 * t;
  uint a = base < pc.count ? values[base] : 0u;
  uint b = base + 1 < pc.count ? values[base + 1] : 0u;
  // Inclusive scan of the threads' pair sums (Hillis-Steele: log2(256) rounds).
  partial[t] = a + b;
  barrier();
  for (uint d = 1; d < 256; d <<= 1) {
    uint add = t >= d ? partial[t - d] : 0u;
    barrier();
    partial[t] += add;
    barrier();
  }
  uint before = partial[t] - (a + b);
  if (base < pc.count) values[base] = before;
  if (base + 1 < pc.count) values[base + 1] = before + a;
  if (t == 255) blockSums[gl_WorkGroupID.x] = partial[255];
}
