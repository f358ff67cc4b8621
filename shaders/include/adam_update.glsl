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

#endif
