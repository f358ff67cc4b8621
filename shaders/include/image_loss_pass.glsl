// Declarations common to the image-loss passes: one invocation per image element
// (pixel * channels + channel) of a row-major, channel-interleaved float image, and the
// separable window taps done branch-free (an out-of-image tap reads the centre element
// with weight 0: that is the zero padding, and lavapipe keeps straight-line loads fast).
#ifndef REFRAX_IMAGE_LOSS_PASS_GLSL
#define REFRAX_IMAGE_LOSS_PASS_GLSL
#extension GL_EXT_control_flow_attributes : require
#include "shared_prelude.glsl"
#include "image_loss.glsl"
layout(local_size_x = 256) in;
layout(push_constant) uniform Push {
  uint width;
  uint height;
  uint channels;
  uint count;  // width * height * channels
} pc;

// Element index of the tap `k` along the row (horizontal) or column (vertical) of element e,
// and its window weight (0 outside the image).
void windowTap(uint e, int k, bool vertical, out uint index, out float weight) {
  uint pixel = e / pc.channels;
  int coord = vertical ? int(pixel / pc.width) : int(pixel % pc.width);
  int extent = vertical ? int(pc.height) : int(pc.width);
  int stride = vertical ? int(pc.width * pc.channels) : int(pc.channels);
  bool inside = coord + k >= 0 && coord + k < extent;
  index = inside ? uint(int(e) + k * stride) : e;
  weight = inside ? ssimWindowWeight(k) : 0.0;
}
#endif
