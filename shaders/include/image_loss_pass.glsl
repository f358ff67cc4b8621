// Declarations common to the image-loss passes over a row-major, channel-interleaved float
// image (element = (row * width + pixel) * channels + channel), window weights from the host.
//
// Shaped for lavapipe, where every load at a per-invocation index is a per-lane scalar gather
// with a bounds check (a vec4 costs four) and integer division is scalar:
//  - each invocation computes kBlock outputs along its blur direction from kBlock + 10 loads
//    (instead of 11 loads per output);
//  - loads are branch-free: a tap outside the image reads a clamped index with weight 0 (that
//    is the zero padding); only stores are guarded;
//  - no division: horizontal passes dispatch (pixel block, row, channel), vertical passes
//    (element of a row, row block).
#ifndef REFRAX_IMAGE_LOSS_PASS_GLSL
#define REFRAX_IMAGE_LOSS_PASS_GLSL
#extension GL_EXT_control_flow_attributes : require
#include "shared_prelude.glsl"
#include "image_loss.glsl"
layout(local_size_x = 64) in;
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint channels;
  uint count;  // width * height * channels
  // ssimWindowWeight(-5 .. 5) from the host: lavapipe evaluates exp with its own polynomial,
  // which LLVM cannot fold, so weights computed in the shader cost 12 exp per tap.
  float window[12];
} pc;

const int kBlock = 8;                         // outputs per invocation
const int kTaps = kBlock + 2 * kSsimRadius;   // loads per invocation

uint rowLength() { return pc.width * pc.channels; }

// Weight of tap t (of kTaps) for output j (of kBlock): constant-folded once unrolled.
float tapWeight(int t, int j) { return (t - j >= 0 && t - j <= 2 * kSsimRadius) ? pc.window[clamp(t - j, 0, 2 * kSsimRadius)] : 0.0; }

// Horizontal passes: invocation (x, y, z) = (pixel block, row, channel); output j is pixel
// x * kBlock + j, tap t is pixel x * kBlock + t - 5.
uint horizontalIndex(int pixel) {
  int p = clamp(pixel, 0, int(pc.width) - 1);
  return (gl_GlobalInvocationID.y * pc.width + uint(p)) * pc.channels + gl_GlobalInvocationID.z;
}
float horizontalInside(int pixel) { return (pixel >= 0 && pixel < int(pc.width)) ? 1.0 : 0.0; }
int horizontalFirst() { return int(gl_GlobalInvocationID.x) * kBlock; }

// Vertical passes: invocation (x, y) = (element of a row, row block); output j is row
// y * kBlock + j, tap t is row y * kBlock + t - 5.
uint verticalIndex(int row) {
  uint x = min(gl_GlobalInvocationID.x, rowLength() - 1u);
  return uint(clamp(row, 0, int(pc.height) - 1)) * rowLength() + x;
}
float verticalInside(int row) { return (row >= 0 && row < int(pc.height)) ? 1.0 : 0.0; }
int verticalFirst() { return int(gl_GlobalInvocationID.y) * kBlock; }
bool verticalColumnValid() { return gl_GlobalInvocationID.x < rowLength(); }
#endif
