#version 460
// Density regulariser: weight * mean(sigmoid(logit)^2). Adds its gradient to gradLogit
// (the Gaussian backward has written its own part there first) and writes per-workgroup
// sums of sigmoid(logit)^2 for reduce_sums. Logit i (and its gradient) is element
// i * stride + offset: training passes the Gaussian table and its gradient as they are.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "shared_prelude.glsl"
#include "image_loss.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Logits { float logit[]; };
layout(std430, set = 0, binding = 1) buffer GradLogits { float gradLogit[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Partials { vec2 partial[]; };
layout(push_constant) uniform Push {
  uint count;
  float scale;  // weight / count
  uint stride, offset;
} pc;
shared float groupSum[256];
void main() {
  uint i = gl_GlobalInvocationID.x;
  bool valid = i < pc.count;
  uint e = min(i, pc.count - 1u);
  uint at = e * pc.stride + pc.offset;
  float z = logit[at];
  float s = sigmoidOf(z);
  if (valid) gradLogit[at] += pc.scale * densitySquareSlope(z);
  uint l = gl_LocalInvocationID.x;
  groupSum[l] = valid ? s * s : 0.0;
  barrier();
  [[unroll]] for (uint half_ = 128u; half_ > 0u; half_ >>= 1u) {
    if (l < half_) groupSum[l] += groupSum[l + half_];
    barrier();
  }
  if (l == 0u) partial[gl_WorkGroupID.x] = vec2(groupSum[0], 0.0);
}
