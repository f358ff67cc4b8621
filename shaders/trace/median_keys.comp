#version 460
// The median-split order's start (engine/trace/device_order.h cmdMedianSplitOrder): point e's
// coordinate on each axis, its sort key (a float's bits that order as the float, -0 taken as +0 as
// the host's comparison does), and three lists of the elements, one per axis, that the radix
// sort orders by (key, element).
#extension GL_GOOGLE_include_directive : require
#include "ordered_float.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Points { float points[]; };  // point e at e * stride + offset
layout(std430, set = 0, binding = 1) writeonly buffer AxisCentres { float axisCentre[]; };  // [axis * n + e]
layout(std430, set = 0, binding = 2) writeonly buffer Keys { uint keys[]; };              // [axis * n + e]
layout(std430, set = 0, binding = 3) writeonly buffer Lists { uint lists[]; };            // [axis * n + e] = e
layout(push_constant) uniform Push { uint n, stride, offset; } pc;

void main() {
  uint e = gl_GlobalInvocationID.x;
  if (e >= pc.n) return;
  for (uint a = 0u; a < 3u; a++) {
    uint bits = floatBitsToUint(points[e * pc.stride + pc.offset + a]);
    if (bits == 0x80000000u) bits = 0u;  // on the bits: a float select may be folded away
    axisCentre[a * pc.n + e] = uintBitsToFloat(bits);
    keys[a * pc.n + e] = floatToOrdered(uintBitsToFloat(bits));
    lists[a * pc.n + e] = e;
  }
}
