#version 460
// The Gaussians' optimiser step on the device, per Gaussian (its row of the table):
//   1. Adam on every column of its groups (include/adam_update.glsl, the host table's update:
//      engine/optim/table_adam.h), a non-finite gradient counting as 0;
//   2. the density schedule of this step: the decay on the density logit
//      (gaussian_math.glsl decayedLogit), then the reset's clamp with its group's moments zeroed;
//   3. the densification statistic of this step's rays added to the run's sums (the gradient
//      statistic scaled by the batch: engine/gaussian/densify.h densifyStatScale).
// The order is the host's (engine/train/train_session.cpp gaussianStep): Adam, decay, reset.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "adam_update.glsl"
#include "gaussian_math.glsl"
layout(local_size_x = 64) in;
struct Group {
  uint first, width;     // columns [first, first + width) of every row
  float stepSize;        // lr / (1 - beta1^t) of this step
  float invSqrtBc2;      // 1 / sqrt(1 - beta2^t)
};
layout(std430, set = 0, binding = 0) buffer Params { float param[]; };
layout(std430, set = 0, binding = 1) readonly buffer Grads { float grad[]; };
layout(std430, set = 0, binding = 2) buffer FirstMoment { float m[]; };
layout(std430, set = 0, binding = 3) buffer SecondMoment { float v[]; };
layout(std430, set = 0, binding = 4) readonly buffer Groups { Group groups[]; };
layout(std430, set = 0, binding = 5) readonly buffer StepStats { float stepStats[]; };  // per row: gradient statistic, rays
layout(std430, set = 0, binding = 6) buffer StatSums { float statSums[]; };
layout(push_constant) uniform Push {
  uint rows;
  uint rowWidth;
  uint groupCount;
  uint densityColumn;
  float beta1, beta2, epsilon;
  float statScale;
  uint decay;             // 1: the density decay is due this step
  float decayFactor;
  float decayFloorLogit;  // the decay's floor (a very negative logit: none)
  uint reset;             // 1: the density reset is due this step
  float resetLogit;       // the reset's ceiling
  uint resetGroup;        // the group whose moments the reset zeroes (the density's)
} pc;

bool finite(float x) { return !isnan(x) && !isinf(x); }

// One thread per row. (A thread per float, its group looked up by column, read contiguous
// memory but ran 3x slower on lavapipe: 8.2 against 2.7 ms for 7,900 Gaussians, its lanes
// diverging on the lookup and the row's events.)
void main() {
  uint row = gl_GlobalInvocationID.x;
  if (row >= pc.rows) return;
  uint base = row * pc.rowWidth;
  for (uint g = 0; g < pc.groupCount; g++) {
    Group group = groups[g];
    bool zero = pc.reset != 0u && g == pc.resetGroup;  // the reset's fresh moments
    for (uint c = group.first; c < group.first + group.width; c++) {
      uint k = base + c;
      float p = param[k], mk = m[k], vk = v[k], gk = grad[k];
      adamUpdate(p, mk, vk, finite(gk) ? gk : 0.0, pc.beta1, pc.beta2, pc.epsilon, group.stepSize, group.invSqrtBc2);
      param[k] = p;
      m[k] = zero ? 0.0 : mk;
      v[k] = zero ? 0.0 : vk;
    }
  }
  uint d = base + pc.densityColumn;
  if (pc.decay != 0u) param[d] = decayedLogit(param[d], pc.decayFactor, pc.decayFloorLogit);
  if (pc.reset != 0u) param[d] = min(param[d], pc.resetLogit);
  statSums[2 * row] += stepStats[2 * row] * pc.statScale;
  statSums[2 * row + 1] += stepStats[2 * row + 1];
}
