#version 460
// One Adam update of parameters [first, count) from `offset` (shaders/include/adam_update.glsl,
// engine/optim/adam.h). Moments are the group's own, indexed from 0. Loads use a clamped index rather
// than an early return (lavapipe turns loads under a branch into one-lane loads). The host runs
// whole workgroups unguarded and only the last partial one with guarded stores (a clamped
// duplicate must not update twice): the guard costs lavapipe about 30% when applied everywhere.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "adam_update.glsl"
layout(local_size_x = 256) in;
layout(constant_id = 0) const bool kGuardStores = true;
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
  uint first;        // first parameter of this dispatch
  float invBc1;      // 1 / (1 - beta1^t)
  float agreementPower;  // > 0: steps scaled by the gradients' agreement (adamUpdateAgreed)
} pc;
void store(uint i, uint k, float mi, float vi, float p) {
  m[i] = mi;
  v[i] = vi;
  param[k] = p;
  if (pc.clearGradients != 0u) grad[k] = 0.0;
}
void main() {
  uint unclamped = pc.first + gl_GlobalInvocationID.x;
  uint i = min(unclamped, pc.count - 1u);
  uint k = pc.offset + i;
  float mi = m[i], vi = v[i], p = param[k];
  if (pc.agreementPower > 0.0)
    adamUpdateAgreed(p, mi, vi, grad[k], pc.beta1, pc.beta2, pc.epsilon, pc.stepSize, pc.invSqrtBc2, pc.invBc1, pc.agreementPower);
  else
    adamUpdate(p, mi, vi, grad[k], pc.beta1, pc.beta2, pc.epsilon, pc.stepSize, pc.invSqrtBc2);
  if (kGuardStores) {
    if (unclamped < pc.count) store(i, k, mi, vi, p);
  } else {
    store(i, k, mi, vi, p);
  }
}
