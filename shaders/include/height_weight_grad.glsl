// Height field backward, pass 2 of 2 (included by height_weight_grad_atomic.comp and
// height_weight_grad_cas.comp): invocation (weight, slice) sums D_l[t][j] * X_l[t][k] over
// the slice's points of the chunk and adds the sum to the gradient with one float atomic.
#include "height_push.glsl"
#include "height_shape.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Scratch { float scratch[]; };
#include "height_grad_output.glsl"

void main() {
  uint weight = pc.weightBase + gl_GlobalInvocationID.x;
  uint l = 0u;
  while (l < HIDDEN && weight >= layerWeightOffset(l + 1u)) l++;
  uint local = weight - layerWeightOffset(l);
  uint n = layerFanIn(l), m = layerFanOut(l);
  if (l == HIDDEN && local >= WIDTH) return;  // past the last weight
  uint j = local / n, k = local % n;
  uint t0 = gl_GlobalInvocationID.y * pc.slice;
  uint t1 = min(pc.count, t0 + pc.slice);
  uint xb = scratchX(l, pc.chunk), db = scratchD(l, pc.chunk);
  float s = 0.0;
  for (uint t = t0; t < t1; t++) s += scratch[db + t * m + j] * scratch[xb + t * n + k];
  if (s != 0.0) addToGradient(weight, s);
}
