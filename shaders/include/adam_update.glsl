// One Adam update of one parameter, torch.optim.Adam's formula (engine/optim/adam.h):
//   m = b1 m + (1 - b1) g;  v = b2 v + (1 - b2) g^2;  p -= stepSize * m / (sqrt(v) * invSqrtBc2 + eps)
// with stepSize = lr / (1 - b1^t) and invSqrtBc2 = 1 / sqrt(1 - b2^t) for the t-th update.
// Shared GLSL/C++ (see shared_prelude.glsl): the device step (shaders/optim/adam_step.comp)
// and the host tables (engine/optim/table_adam.h) both run this, so Refrax has one Adam.
#if defined(__cplusplus) || !defined(REFRAX_ADAM_UPDATE_GLSL)
#ifndef __cplusplus
#define REFRAX_ADAM_UPDATE_GLSL
#endif

SHARED_FN void adamUpdate(INOUT(real) param, INOUT(real) m, INOUT(real) v, real grad, real beta1, real beta2, real epsilon,
                          real stepSize, real invSqrtBc2) {
  m = beta1 * m + (real(1) - beta1) * grad;
  v = beta2 * v + (real(1) - beta2) * grad * grad;
  param = param - stepSize * m / (sqrt(v) * invSqrtBc2 + epsilon);
}

// The same update with the step scaled by r^power, r = |m^| / sqrt(v^) = |m| invBc1 / (sqrt(v)
// invSqrtBc2) in [0, 1] (invBc1 = 1 / (1 - beta1^t)): the agreement of the gradients Adam has
// averaged. A gradient that keeps its sign reads r -> 1 and steps as plain Adam; one that is
// noise about zero reads r ~ 0.23 (beta1 0.9) and, power 2, steps a twentieth as far, where
// plain Adam walks it about the learning rate whatever its size (engine/optim/adam.h).
SHARED_FN void adamUpdateAgreed(INOUT(real) param, INOUT(real) m, INOUT(real) v, real grad, real beta1, real beta2, real epsilon,
                                real stepSize, real invSqrtBc2, real invBc1, real power) {
  m = beta1 * m + (real(1) - beta1) * grad;
  v = beta2 * v + (real(1) - beta2) * grad * grad;
  real denominator = sqrt(v) * invSqrtBc2 + epsilon;
  real agreement = min(abs(m) * invBc1 / denominator, real(1));
  param = param - stepSize * m / denominator * pow(agreement, power);
}

#endif
