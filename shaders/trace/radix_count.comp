#version 460
// One pass of a stable least-significant-digit radix sort (engine/trace/device_order.h
// cmdRadixSort), 4 bits at a time: each block of 256 keys counts its digits, written digit-major
// (histogram[digit * blocks + block]) so that one exclusive scan of the histogram gives every
// block's first slot for every digit, blocks in order.
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Keys { uint keys[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Histogram { uint histogram[]; };
layout(push_constant) uniform Push { uint base, count, shift, blocks; } pc;

shared uint digits[16];

void main() {
  uint t = gl_LocalInvocationID.x;
  if (t < 16) digits[t] = 0;
  barrier();
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.count) atomicAdd(digits[(keys[pc.base + i] >> pc.shift) & 15u], 1u);
  barrier();
  if (t < 16) histogram[t * pc.blocks + gl_WorkGroupID.x] = digits[t];
}
