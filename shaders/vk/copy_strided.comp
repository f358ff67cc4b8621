#version 460
// dst[dstOffset + i * dstStride + c] = src[srcOffset + i * srcStride + c] for c < channels,
// and 0 for channels <= c < dstStride: moves per-ray values between the layouts of two stages
// on the device (the tracer's 32-byte results to the loss's rgb, the loss's rgb gradient to the
// tracer's rgba gradient) instead of through the host. With `weighted`, each element's copied
// channels are multiplied by weight[i] (a pixel mask: 0 where a pixel must not count).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Src { float src[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, set = 0, binding = 2) readonly buffer Weight { float weight[]; };
layout(push_constant) uniform Push { uint count, channels, srcStride, srcOffset, dstStride, dstOffset, weighted; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  float w = pc.weighted != 0u ? weight[i] : 1.0;
  for (uint c = 0u; c < pc.dstStride; c++)
    dst[pc.dstOffset + i * pc.dstStride + c] = c < pc.channels ? w * src[pc.srcOffset + i * pc.srcStride + c] : 0.0;
}
