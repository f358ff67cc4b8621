#version 460
// One Adam update of `count` parameters from `offset` (torch.optim.Adam's formula; see
// engine/adam.h). Moments are the group's own, indexed from 0. Loads use a clamped index
// rather than an early return (lavapipe turns loads under a branch into one-lane loads);
// only the stores are guarded, since a clamped duplicate must not update twice.
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) buffer Params { float param[]; };
layout(std430, set = 0, binding = 1) buffer Grads { float grad[]; };
layout(std430, set = 0, binding = 2) buffer FirstMoment { float m[]; };
layout(std430, set = 0, binding = 3) buffer SecondMoment { float v[]; };
layout(push_constant) uniform Push {
  uint count;
  uint offset;
  uint clearGradients;
  float beta1;
  float beta2;
  float epsilon;
  float stepSize;    // lr / (1 - beta1^t)
  float invSqrtBc2;  // 1 / sqrt(1 - beta2^t)
} pc;
void main() {
  bool valid = gl_GlobalInvocationID.x < pc.count;
  uint i = min(gl_GlobalInvocationID.x, pc.count - 1u);
  uint k = pc.offset + i;
  float g = grad[k];
  float mi = pc.beta1 * m[i] + (1.0 - pc.beta1) * g;
  float vi = pc.beta2 * v[i] + (1.0 - pc.beta2) * g * g;
  float p = param[k] - pc.stepSize * mi / (sqrt(vi) * pc.invSqrtBc2 + pc.epsilon);
  if (valid) {
    m[i] = mi;
    v[i] = vi;
    param[k] = p;
    if (pc.clearGradients != 0u) grad[k] = 0.0;
  }
}
