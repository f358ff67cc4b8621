#version 460
// The scatter of one radix-sort pass (radix_count.comp): a key goes to its block's first slot
// for its digit (the scanned histogram) plus the number of keys with that digit before it in
// the block, so equal digits keep their order (the sort is stable: equal keys keep the values'
// order). That number is an exclusive scan of each thread's one-hot digit over the block, the
// 16 counters packed two to a word (a block holds 256 keys, so 16 bits never overflow).
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer KeysIn { uint keysIn[]; };
layout(std430, set = 0, binding = 1) readonly buffer ValuesIn { uint valuesIn[]; };
layout(std430, set = 0, binding = 2) writeonly buffer KeysOut { uint keysOut[]; };
layout(std430, set = 0, binding = 3) writeonly buffer ValuesOut { uint valuesOut[]; };
layout(std430, set = 0, binding = 4) readonly buffer Offsets { uint offsets[]; };  // the scanned histogram
layout(push_constant) uniform Push { uint base, count, shift, blocks; } pc;

shared uint counts[256][8];

void main() {
  uint t = gl_LocalInvocationID.x;
  uint i = gl_GlobalInvocationID.x;
  bool valid = i < pc.count;
  uint key = valid ? keysIn[pc.base + i] : 0u;
  uint digit = (key >> pc.shift) & 15u;
  uint word = digit >> 1, bit = (digit & 1u) * 16u;
  uint own[8];
  for (uint w = 0; w < 8; w++) own[w] = valid && w == word ? 1u << bit : 0u;
  for (uint w = 0; w < 8; w++) counts[t][w] = own[w];
  barrier();
  for (uint d = 1; d < 256; d <<= 1) {
    uint add[8];
    for (uint w = 0; w < 8; w++) add[w] = t >= d ? counts[t - d][w] : 0u;
    barrier();
    for (uint w = 0; w < 8; w++) counts[t][w] += add[w];
    barrier();
  }
  if (!valid) return;
  uint before = ((counts[t][word] >> bit) & 0xFFFFu) - 1u;  // the inclusive count less this key
  uint slot = offsets[digit * pc.blocks + gl_WorkGroupID.x] + before;
  keysOut[pc.base + slot] = key;
  valuesOut[pc.base + slot] = valuesIn[pc.base + i];
}
