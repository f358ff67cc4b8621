// A closed-form height field, H(x, y) = base + sum_k a_k sin(kx_k x + ky_k y + phase_k),
// used to test the surface geometry without the MLP. Shared GLSL/C++.
// waves[k] = (amplitude, kx, ky, phase).
#if defined(__cplusplus) || !defined(REFRAX_ANALYTIC_HEIGHT_GLSL)
#ifndef __cplusplus
#define REFRAX_ANALYTIC_HEIGHT_GLSL
#endif

SHARED_FN real analyticHeight(real x, real y, real base, real4 w0, real4 w1, real4 w2, real4 w3) {
  return base + w0.x * sin(w0.y * x + w0.z * y + w0.w) + w1.x * sin(w1.y * x + w1.z * y + w1.w) +
         w2.x * sin(w2.y * x + w2.z * y + w2.w) + w3.x * sin(w3.y * x + w3.z * y + w3.w);
}

#endif
