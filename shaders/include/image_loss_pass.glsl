// Declarations common to the image-loss passes: one invocation per image element
// (pixel * channels + channel) of a row-major, channel-interleaved float image, and the
// separable window taps done branch-free, weights from the push constants (an out-of-image tap reads the centre element
// with weight 0: that is the zero padding, and lavapipe keeps straight-line loads fast).
#ifndef REFRAX_IMAGE_LOSS_PASS_GLSL
#define REFRAX_IMAGE_LOSS_PASS_GLSL
#extension GL_EXT_control_flow_attributes : require
#include "shared_prelude.glsl"
#include "image_loss.glsl"
// Dispatch: x over the elements of an image row (width * channels), y over the rows, so no
// invocation divides (integer division is scalar on lavapipe): a horizontal tap k stays in
// the row iff x + k * channels does, a vertical tap iff row + k does.
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

uint rowLength() { return pc.width * pc.channels; }
bool elementValid() { return gl_GlobalInvocationID.x < rowLength(); }
// This invocation's element, clamped into its row (invocations past the row's end compute a
// duplicate and store nothing).
uint elementIndex() { return gl_GlobalInvocationID.y * rowLength() + min(gl_GlobalInvocationID.x, rowLength() - 1u); }

// Element index of tap k along the row (horizontal) or column (vertical) of this invocation's
// element e, and its window weight (0 outside the image).
void windowTap(uint e, int k, bool vertical, out uint index, out float weight) {
  int x = int(min(gl_GlobalInvocationID.x, rowLength() - 1u));
  int row = int(gl_GlobalInvocationID.y);
  bool inside = vertical ? (row + k >= 0 && row + k < int(pc.height))
                         : (x + k * int(pc.channels) >= 0 && x + k * int(pc.channels) < int(rowLength()));
  int stride = vertical ? int(rowLength()) : int(pc.channels);
  index = inside ? uint(int(e) + k * stride) : e;
  weight = inside ? pc.window[k + kSsimRadius] : 0.0;
}
#endif
