// A closed-form height field: H(x, y) = base + the sum of four components, used to test the
// surface geometry without the MLP and as the known-water oracle. Shared GLSL/C++.
// Component k is w_k = (amplitude, kx, ky, phase), a directional sine
// a sin(kx x + ky y + phase), when sigma[k] is 0; and w_k = (amplitude, cx, cy, k), a radial
// ripple a cos(k r) exp(-r^2 / (2 sigma^2)) about (cx, cy), when sigma[k] > 0: the two shapes
// refrax synth draws (engine/synth/wave_surface.h). An unused component has amplitude 0.
#if defined(__cplusplus) || !defined(REFRAX_ANALYTIC_HEIGHT_GLSL)
#ifndef __cplusplus
#define REFRAX_ANALYTIC_HEIGHT_GLSL
#endif

SHARED_FN real analyticComponent(real x, real y, real4 w, real sigma) {
  if (!(sigma > real(0))) return w.x * sin(w.y * x + w.z * y + w.w);
  real dx = x - w.y, dy = y - w.z, r2 = dx * dx + dy * dy;
  return w.x * cos(w.w * sqrt(r2)) * exp(-r2 / (real(2) * sigma * sigma));
}

SHARED_FN real analyticHeight(real x, real y, real base, real4 w0, real4 w1, real4 w2, real4 w3, real4 sigmas) {
  return base + analyticComponent(x, y, w0, sigmas.x) + analyticComponent(x, y, w1, sigmas.y) +
         analyticComponent(x, y, w2, sigmas.z) + analyticComponent(x, y, w3, sigmas.w);
}

#endif
