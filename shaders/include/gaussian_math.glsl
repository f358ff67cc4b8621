// Gaussian particle math shared by the tracer shaders and the CPU double reference
// (see shared_prelude.glsl): parameter layout, activations, the maximum-response kernel
// along a ray (3DGRT, paper §3.3), the hit acceptance rule, spherical harmonics, and the
// derivatives of each. Written once; compiled as GLSL and as C++ (refrax::f32 / f64).
#ifndef __cplusplus
#ifndef REFRAX_GAUSSIAN_MATH_GLSL
#define REFRAX_GAUSSIAN_MATH_GLSL
#include "shared_prelude.glsl"
#define REFRAX_GAUSSIAN_MATH_BODY
#endif
#else
#define REFRAX_GAUSSIAN_MATH_BODY
#endif
#ifdef REFRAX_GAUSSIAN_MATH_BODY
#undef REFRAX_GAUSSIAN_MATH_BODY

// Raw (pre-activation) parameters of one Gaussian, as consecutive floats; gradients use the
// same layout. SH coefficient k of channel c is at kGaussSH + 3k + c.
const uint kGaussMean = 0u;         // x y z
const uint kGaussRotation = 3u;     // quaternion w x y z (normalised when used)
const uint kGaussLogScale = 7u;     // log sigma per local axis
const uint kGaussLogitDensity = 10u;
const uint kGaussSH = 11u;          // 16 coefficients x 3 channels
const uint kGaussFloats = 59u;
const uint kShCoefficients = 16u;

// Hit rules (3DGRT): kernel cut-off, smallest alpha blended, alpha clamp, early stop.
const real kMinKernelResponse = real(0.0113);
const real kMinAlpha = real(1.0) / real(255.0);
const real kMaxAlpha = real(0.99);
const real kMinTransmittance = real(0.001);
// Largest half extent of a proxy box (metres). A Gaussian larger than any scene (a log-scale
// of 46, scale 1e20, in a PLY) gave a box whose bounds overflow the BVH build's float
// arithmetic, and every ray then missed every Gaussian; clamped, its box still covers the scene.
const real kMaxProxyHalfExtent = real(1e15);

SHARED_FN real sigmoidOf(real x) { return real(1) / (real(1) + exp(-x)); }

// The density decay on a logit: logit(f p), p = sigmoid(x), written as
// log f + log p - log(1 - f p) with 1 - f p = sigmoid(-x) + (1 - f) p, so neither a large nor a
// very negative logit loses its value to rounding; then at least floorLogit (the decay's floor).
SHARED_FN real decayedLogit(real x, real f, real floorLogit) {
  real logP = x >= real(0) ? -log(real(1) + exp(-x)) : x - log(real(1) + exp(x));
  real decayed = log(f) + logP - log(sigmoidOf(-x) + (real(1) - f) * sigmoidOf(x));
  return max(f == real(1) ? x : decayed, floorLogit);  // factor 1: the identity, even where the formula overflows
}

// Rotation of a (not necessarily unit) quaternion q = (w, x, y, z).
// The largest of a Gaussian's sigmas, from its log scales: densification's clone/split and
// large-prune test (engine/gaussian/densify.h), the same on the host and the device.
SHARED_FN real largestSigmaOf(real3 logScale) { return exp(max(logScale.x, max(logScale.y, logScale.z))); }

SHARED_FN real3x3 rotationOf(real4 q) {
  real4 u = q / length(q);
  real w = u.x, x = u.y, y = u.z, z = u.w;
  // columns
  return real3x3(real3(real(1) - real(2) * (y * y + z * z), real(2) * (x * y + w * z), real(2) * (x * z - w * y)),
                 real3(real(2) * (x * y - w * z), real(1) - real(2) * (x * x + z * z), real(2) * (y * z + w * x)),
                 real3(real(2) * (x * z + w * y), real(2) * (y * z - w * x), real(1) - real(2) * (x * x + y * y)));
}

// M = S^-1 R^T maps world offsets to the Gaussian's unit-sphere frame.
SHARED_FN real3x3 worldToLocalOf(real3x3 R, real3 invScale) {
  real3x3 Rt = transpose(R);
  return real3x3(Rt[0] * invScale, Rt[1] * invScale, Rt[2] * invScale);
}

// Squared local distance m of the ray p + t w to the mean at the point of maximum response,
// and that point's t (in the ray's own parametrisation). `r` is the local residual
// M (p + t w - mu) and `x` the world offset p + t w - mu, both needed by the backward.
// The ray is first moved to its closest approach to the mean in world space, which keeps
// the local vectors small and the float result accurate for distant origins.
SHARED_FN real gaussianPeak(real3 p, real3 w, real3 mu, real3x3 M, OUT(real) t, OUT(real3) r, OUT(real3) x) {
  real t0 = dot(mu - p, w) / dot(w, w);
  real3 x0 = (p - mu) + t0 * w;
  real3 a = M * x0;
  real3 b = M * w;
  real tl = -dot(a, b) / dot(b, b);
  r = a + tl * b;
  x = x0 + tl * w;
  t = t0 + tl;
  return dot(r, r);
}

// The same m and t from the precision matrix A = M^T M (symmetric), the form the tracer
// evaluates for every candidate (6 numbers to load instead of 9). invLen2 = 1 / dot(w, w).
// Centred at the closest approach to the mean like gaussianPeak, so the subtraction only
// removes the along-ray part: as accurate as the M form.
SHARED_FN real gaussianPeakPrecision(real3 p, real3 w, real invLen2, real3 mu, real3x3 A, OUT(real) t) {
  real t0 = dot(mu - p, w) * invLen2;
  real3 x0 = (p - mu) + t0 * w;
  real3 Aw = A * w;
  real xAw = dot(x0, Aw);
  real tl = -xAw / dot(w, Aw);
  t = t0 + tl;
  return max(dot(x0, A * x0) + tl * xAw, real(0));
}

// Radius (in sigmas) of the proxy box: where density * kernel falls to the smallest value
// acceptedAlpha keeps, max(min(0.0113, 0.97 density), 1/255) (the adaptive cut-off of
// docs/method.md §1.4, capped for faint Gaussians, and no further than alpha 1/255 reaches). Zero
// for a Gaussian fainter than 1/255, which no ray can hit (trained scenes hold many: the
// density decay and resets leave them behind; a point box keeps them out of every ray).
SHARED_FN real proxyRadiusOf(real density) {
  real threshold = max(min(kMinKernelResponse, real(0.97) * density), kMinAlpha);
  return sqrt(max(real(-2) * log(threshold / density), real(0)));
}

// Hit acceptance: the peak must lie inside the proxy's ellipsoid (density * kernel above
// min(0.0113, 0.97 density), i.e. m < proxyRadius^2, so the box always contains
// every accepted peak) and alpha >= 1/255. Returns the unclamped alpha (density * kernel),
// or 0 when rejected.
SHARED_FN real acceptedAlpha(real m, real density) {
  real a = density * exp(real(-0.5) * m);
  bool inside = a > min(kMinKernelResponse, real(0.97) * density);
  return (inside && a >= kMinAlpha) ? a : real(0);
}

SHARED_FN real clampedAlpha(real rawAlpha) { return min(rawAlpha, kMaxAlpha); }

// ---- spherical harmonics (degree <= 3, the 3DGS real basis and constants)
SHARED_FN real shBasis(uint k, real3 d) {
  real x = d.x, y = d.y, z = d.z;
  if (k == 0u) return real(0.28209479177387814);
  if (k == 1u) return real(-0.4886025119029199) * y;
  if (k == 2u) return real(0.4886025119029199) * z;
  if (k == 3u) return real(-0.4886025119029199) * x;
  if (k == 4u) return real(1.0925484305920792) * x * y;
  if (k == 5u) return real(-1.0925484305920792) * y * z;
  if (k == 6u) return real(0.31539156525252005) * (real(2) * z * z - x * x - y * y);
  if (k == 7u) return real(-1.0925484305920792) * x * z;
  if (k == 8u) return real(0.5462742152960396) * (x * x - y * y);
  if (k == 9u) return real(-0.5900435899266435) * y * (real(3) * x * x - y * y);
  if (k == 10u) return real(2.890611442640554) * x * y * z;
  if (k == 11u) return real(-0.4570457994644658) * y * (real(4) * z * z - x * x - y * y);
  if (k == 12u) return real(0.3731763325901154) * z * (real(2) * z * z - real(3) * x * x - real(3) * y * y);
  if (k == 13u) return real(-0.4570457994644658) * x * (real(4) * z * z - x * x - y * y);
  if (k == 14u) return real(1.445305721320277) * z * (x * x - y * y);
  return real(-0.5900435899266435) * x * (x * x - real(3) * y * y);
}

// d shBasis(k, d) / d(d.x, d.y, d.z) (the polynomial, before any normalisation).
SHARED_FN real3 shBasisGradient(uint k, real3 d) {
  real x = d.x, y = d.y, z = d.z;
  if (k == 0u) return real3(0);
  if (k == 1u) return real(-0.4886025119029199) * real3(0, 1, 0);
  if (k == 2u) return real(0.4886025119029199) * real3(0, 0, 1);
  if (k == 3u) return real(-0.4886025119029199) * real3(1, 0, 0);
  if (k == 4u) return real(1.0925484305920792) * real3(y, x, 0);
  if (k == 5u) return real(-1.0925484305920792) * real3(0, z, y);
  if (k == 6u) return real(0.31539156525252005) * real3(real(-2) * x, real(-2) * y, real(4) * z);
  if (k == 7u) return real(-1.0925484305920792) * real3(z, 0, x);
  if (k == 8u) return real(0.5462742152960396) * real3(real(2) * x, real(-2) * y, 0);
  if (k == 9u) return real(-0.5900435899266435) * real3(real(6) * x * y, real(3) * (x * x - y * y), 0);
  if (k == 10u) return real(2.890611442640554) * real3(y * z, x * z, x * y);
  if (k == 11u)
    return real(-0.4570457994644658) * real3(real(-2) * x * y, real(4) * z * z - x * x - real(3) * y * y, real(8) * y * z);
  if (k == 12u)
    return real(0.3731763325901154) * real3(real(-6) * x * z, real(-6) * y * z, real(6) * z * z - real(3) * x * x - real(3) * y * y);
  if (k == 13u)
    return real(-0.4570457994644658) * real3(real(4) * z * z - real(3) * x * x - y * y, real(-2) * x * y, real(8) * x * z);
  if (k == 14u) return real(1.445305721320277) * real3(real(2) * x * z, real(-2) * y * z, x * x - y * y);
  return real(-0.5900435899266435) * real3(real(3) * (x * x - y * y), real(-6) * x * y, 0);
}

SHARED_FN uint shCoefficientsFor(uint degree) { return (degree + 1u) * (degree + 1u); }

// ---- derivatives of one hit's alpha
// Given dL/dm for the squared peak distance m (with r, x, t from gaussianPeak), the
// gradients with respect to the ray origin p and direction w, the mean, and M.
// m(p, w) = min_t |M (p + t w - mu)|^2, so (envelope theorem) dm/dp = 2 M^T r,
// dm/dw = 2 t M^T r, dm/dmu = -2 M^T r, dm/dM = 2 r x^T.
SHARED_FN void peakBackward(real dm, real3x3 M, real3 r, real3 x, real t, OUT(real3) dp, OUT(real3) dw, OUT(real3x3) dM) {
  real3 g = real(2) * dm * r;
  dp = transpose(M) * g;
  dw = t * dp;
  dM = real3x3(g * x.x, g * x.y, g * x.z);
}

// dL/dM for M = diag(invScale) R^T -> dL/dR and dL/d(log scale).
SHARED_FN void localBackward(real3x3 dM, real3x3 M, real3 invScale, OUT(real3x3) dR, OUT(real3) dLogScale) {
  // M_ij = invScale_i R_ji: dR_ji = dM_ij invScale_i; dlogscale_i = -sum_j dM_ij M_ij
  real3x3 scaled = real3x3(dM[0] * invScale, dM[1] * invScale, dM[2] * invScale);
  dR = transpose(scaled);
  real3 acc = real3(0);
  for (int j = 0; j < 3; j++) acc += dM[j] * M[j];
  dLogScale = -acc;
}

// dL/dR -> dL/dq for R = rotationOf(q), q = (w, x, y, z) unnormalised.
SHARED_FN real4 rotationBackward(real4 q, real3x3 dR) {
  real n = length(q);
  real4 u = q / n;
  real w = u.x, x = u.y, y = u.z, z = u.w;
  // G(row, col) = dR[col][row]
  real g00 = dR[0][0], g01 = dR[1][0], g02 = dR[2][0];
  real g10 = dR[0][1], g11 = dR[1][1], g12 = dR[2][1];
  real g20 = dR[0][2], g21 = dR[1][2], g22 = dR[2][2];
  real dw = real(2) * (-z * g01 + y * g02 + z * g10 - x * g12 - y * g20 + x * g21);
  real dx = real(2) * (y * g01 + z * g02 + y * g10 - real(2) * x * g11 - w * g12 + z * g20 + w * g21 - real(2) * x * g22);
  real dy = real(2) * (real(-2) * y * g00 + x * g01 + w * g02 + x * g10 + z * g12 - w * g20 + z * g21 - real(2) * y * g22);
  real dz = real(2) * (real(-2) * z * g00 - w * g01 + x * g02 + w * g10 - real(2) * z * g11 + y * g12 + x * g20 + y * g21);
  real4 du = real4(dw, dx, dy, dz);
  return (du - u * dot(u, du)) / n;
}

// d normalize(v) chained: dL/dv from dL/d(v/|v|).
SHARED_FN real3 normalizeBackward(real3 v, real3 dn) {
  real len = length(v);
  real3 n = v / len;
  return (dn - n * dot(n, dn)) / len;
}

#endif
