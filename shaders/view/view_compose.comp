#version 460
// Viewer: the Gaussian tracer's per-ray results to packed RGBA8 pixels, as RGB (mode 0) or
// as a heat map of the hits blended per ray (mode 1), in view_compose.glsl's shared math.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "gaussian_trace_types.glsl"
#include "view_compose.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Results { TraceResult results[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Pixels { uint pixels[]; };
layout(push_constant) uniform Push {
  uint count;
  uint mode;
  float heatFullScale;
  uint pad;
} pc;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  TraceResult r = results[i];
  vec3 c = pc.mode == 1u ? heatMapColour(float(r.hits), pc.heatFullScale) : r.rgbOpacity.rgb;
  pixels[i] = packRgba8(c);
}
