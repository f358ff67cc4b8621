// Refraction at the water surface: the vector form of Snell's law and its backward.
// Shared GLSL/C++ (see shared_prelude.glsl). eta = n_air / n_water (< 1 for air into water).
//   c1 = -n.d with n facing the incoming ray, c2 = sqrt(1 - eta^2 (1 - c1^2)),
//   w  = eta d + (eta c1 - c2) n.
// Air into water cannot totally reflect (the radicand is >= 1 - eta^2 > 0). Two cases still
// need a defined result: a normal that faces away from the ray (an interpolated normal on a
// steep wave can), which is flipped to face the ray (snellFacingSign), and eta > 1 (a user
// IOR below 1), where the radicand is clamped at 0 so the ray leaves along the surface
// instead of producing NaN; its derivative is then taken as 0.
#if defined(__cplusplus) || !defined(REFRAX_SNELL_GLSL)
#ifndef __cplusplus
#define REFRAX_SNELL_GLSL
#endif

// +1 when n already faces the ray (n.d <= 0), -1 when it must be flipped.
SHARED_FN real snellFacingSign(real3 d, real3 n) { return dot(n, d) > real(0) ? real(-1) : real(1); }

// Refracted direction for unit d and unit n facing the ray (n.d <= 0).
SHARED_FN real3 snellRefract(real3 d, real3 n, real eta) {
  real c1 = -dot(n, d);
  real c2 = sqrt(max(real(1) - eta * eta * (real(1) - c1 * c1), real(0)));
  return eta * d + (eta * c1 - c2) * n;
}

// Backward of snellRefract: gw = dL/dw in, dL/dd and dL/dn out.
SHARED_FN void snellRefractBackward(real3 d, real3 n, real eta, real3 gw, OUT(real3) gd, OUT(real3) gn) {
  real c1 = -dot(n, d);
  real radicand = real(1) - eta * eta * (real(1) - c1 * c1);
  real c2 = sqrt(max(radicand, real(0)));
  // dc2/dc1 = eta^2 c1 / c2; zero where the radicand is clamped (see above)
  real dc2dc1 = radicand > real(0) ? eta * eta * c1 / c2 : real(0);
  real gc1 = dot(gw, n) * (eta - dc2dc1);  // dL/dc1
  gn = (eta * c1 - c2) * gw - gc1 * d;
  gd = eta * gw - gc1 * n;
}

#endif
