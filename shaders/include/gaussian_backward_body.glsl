// Gaussian ray tracer, backward (docs/method.md §1.5). Included by gaussian_backward.comp (float
// atomicAdd) and gaussian_backward_cas.comp (REFRAX_CAS_ATOMICS: compare-and-swap loop, for
// devices without shaderBufferFloat32AtomicAdd).
//
// Each ray's blended hits come from the recording forward's hit records (HitRecord) where
// they all fit, else the ray is re-traced exactly as in the forward; with the forward's final colour C
// (background share included) the suffix sums need no second pass:
//   dC/dalpha_k = T_k c_k - (C - C_<=k) / (1 - alpha_k),  dOpacity/dalpha_k = T_final / (1 - alpha_k).
// Per hit, the chain runs through the kernel to mean, rotation, log scale, logit density,
// through the SH to its coefficients, and to the ray's origin and direction (through alpha
// and through the SH direction). Per-Gaussian sums are accumulated atomically.
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#ifndef REFRAX_CAS_ATOMICS
#extension GL_EXT_shader_atomic_float : require
#endif
#include "rays.glsl"
#include "gaussian_trace_types.glsl"
layout(local_size_x = 64) in;
layout(constant_id = 0) const int K = 16;
layout(constant_id = 1) const bool kInstanced = false;
#include "trace_scene.glsl"
layout(std430, set = 0, binding = 1) restrict readonly buffer Trace { TraceGaussian tg[]; };
layout(std430, set = 0, binding = 2) restrict readonly buffer Params { float params[]; };
layout(std430, set = 0, binding = 3) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 4) readonly buffer Results { TraceResult results[]; };
layout(std430, set = 0, binding = 5) readonly buffer LossGrad { vec4 dLoss[]; };  // dL/d(rgb, opacity)
#ifdef REFRAX_CAS_ATOMICS
layout(std430, set = 0, binding = 6) buffer Grads { uint gradBits[]; };
layout(std430, set = 0, binding = 7) buffer Stats { uint statBits[]; };
#else
layout(std430, set = 0, binding = 6) buffer Grads { float grads[]; };
layout(std430, set = 0, binding = 7) buffer Stats { float stats[]; };
#endif
layout(std430, set = 0, binding = 8) writeonly buffer RayGrads { RayGrad rayGrads[]; };
layout(std430, set = 0, binding = 9) readonly buffer HitRecords { HitRecord hitRecords[]; };
layout(std430, set = 0, binding = 10) restrict readonly buffer ShPacked { vec4 shPacked[]; };
REFRAX_TRACE_PUSH
#include "gaussian_kbuffer.glsl"

#ifdef REFRAX_CAS_ATOMICS
#define REFRAX_ADD_FLOAT(bufferBits, index, value)                                          \
  {                                                                                         \
    uint expected = bufferBits[index];                                                      \
    for (;;) {                                                                              \
      uint prev = atomicCompSwap(bufferBits[index], expected, floatBitsToUint(uintBitsToFloat(expected) + (value))); \
      if (prev == expected) break;                                                          \
      expected = prev;                                                                      \
    }                                                                                       \
  }
void addGrad(uint index, float v) {
  if (v != 0.0) REFRAX_ADD_FLOAT(gradBits, index, v)
}
void addStat(uint index, float v) { REFRAX_ADD_FLOAT(statBits, index, v) }
#else
void addGrad(uint index, float v) {
  if (v != 0.0) atomicAdd(grads[index], v);
}
void addStat(uint index, float v) { atomicAdd(stats[index], v); }
#endif

// Per-ray state shared by main() and backwardHit().
vec3 o, d;
uint coefficients;
// sum over hits of dot(dL/dcolour, coefficient k): the direction gradient through the SH
// is then sum_k shDir[k] * grad shBasis(k), evaluated once per ray
float shDir[16];
vec3 C, gC;        // the forward's colour, dL/dcolour
float Tfinal, gA;  // the forward's final transmittance, dL/dopacity
vec3 dOrigin, dDir, Cprefix;
float T, distanceBefore;

// One blended hit, in blending order: its share of every gradient.
void backwardHit(uint id, float rawAlpha) {
  float alpha = clampedAlpha(rawAlpha);
  loadShCoefficients(id, coefficients);
  vec3 cRaw = shColorRaw();
  vec3 c = max(cRaw, vec3(0.0));
  float w = T * alpha;
  Cprefix += w * c;
  float oneMinus = 1.0 - alpha;
  float dAlpha = dot(gC, T * c - (C - Cprefix) / oneMinus) + gA * Tfinal / oneMinus;
  vec3 dColor = w * gC * vec3(greaterThan(cRaw, vec3(0.0)));

  uint b = id * kGaussFloats;
  // SH coefficients and the SH direction
  for (uint kk = 0u; kk < kShCoefficients; kk++) {  // constant bound: unrolls, shBasis folds
    if (kk >= coefficients) break;
    float Y = shY[kk];
    vec3 coef = shC[kk];
    addGrad(b + kGaussSH + 3u * kk, dColor.r * Y);
    addGrad(b + kGaussSH + 3u * kk + 1u, dColor.g * Y);
    addGrad(b + kGaussSH + 3u * kk + 2u, dColor.b * Y);
    shDir[kk] += dot(dColor, coef);
  }
  // the kernel (alpha at or above the clamp passes no gradient to the Gaussian or the ray)
  if (rawAlpha < kMaxAlpha) {
    vec3 mu = vec3(params[b + kGaussMean], params[b + kGaussMean + 1u], params[b + kGaussMean + 2u]);
    vec4 q = vec4(params[b + kGaussRotation], params[b + kGaussRotation + 1u], params[b + kGaussRotation + 2u], params[b + kGaussRotation + 3u]);
    vec3 invScale = exp(-vec3(params[b + kGaussLogScale], params[b + kGaussLogScale + 1u], params[b + kGaussLogScale + 2u]));
    float density = sigmoidOf(params[b + kGaussLogitDensity]);
    mat3 R = rotationOf(q);
    mat3 M = worldToLocalOf(R, invScale);
    float t;
    vec3 r, x;
    float m = gaussianPeak(o, d, mu, M, t, r, x);
    float kernel = exp(-0.5 * m);
    float dm = dAlpha * (-0.5 * density * kernel);
    vec3 dp, dw;
    mat3 dM;
    peakBackward(dm, M, r, x, t, dp, dw, dM);
    mat3 dR;
    vec3 dLogScale;
    localBackward(dM, M, invScale, dR, dLogScale);
    vec4 dq = rotationBackward(q, dR);
    for (uint a = 0u; a < 3u; a++) {
      addGrad(b + kGaussMean + a, -dp[a]);
      addGrad(b + kGaussLogScale + a, dLogScale[a]);
    }
    for (uint a = 0u; a < 4u; a++) addGrad(b + kGaussRotation + a, dq[a]);
    addGrad(b + kGaussLogitDensity, dAlpha * kernel * density * (1.0 - density));
    dOrigin += dp;
    dDir += dw;
    // densification statistics: |dL/dmean| times the distance from the viewpoint, halved (3DGRT)
    addStat(2u * id, length(dp) * (distanceBefore + t * length(d)) * 0.5);
  }
  addStat(2u * id + 1u, 1.0);
  T *= oneMinus;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  Ray ray = rays[i];
  o = ray.originTmin.xyz;
  d = ray.dirTmax.xyz;
  vec3 dn = normalize(d);
  coefficients = shCoefficientsFor(pc.shDegree);
  evaluateShBasis(dn, coefficients);
  for (uint k = 0u; k < kShCoefficients; k++) shDir[k] = 0.0;
  TraceResult fwd = results[i];
  C = fwd.rgbOpacity.rgb;
  Tfinal = fwd.transmittance;
  gC = dLoss[i].rgb;
  gA = dLoss[i].a;
  // A ray without a loss gradient (a masked pixel) changes nothing: the backward is linear in
  // (gC, gA). It is skipped, so it neither costs a traversal nor counts in the statistics.
  if (gC == vec3(0.0) && gA == 0.0) {
    rayGrads[i] = RayGrad(vec4(0.0), vec4(0.0));
    return;
  }
  dOrigin = vec3(0.0);
  dDir = vec3(0.0);
  Cprefix = vec3(0.0);
  T = 1.0;
  distanceBefore = pc.statViewpoint.w > 0.5 ? distance(pc.statViewpoint.xyz, o) : 0.0;

  if (fwd.hits <= pc.recordsPerRay) {
    // the recording forward kept every hit it blended: no traversal
    for (uint k = 0u; k < fwd.hits; k++) {
      HitRecord h = hitRecords[i * pc.recordsPerRay + k];
      backwardHit(h.x, uintBitsToFloat(h.y));
    }
  } else {
    // re-trace exactly as the forward did
    float tcur = ray.originTmin.w;
    uint idcur = 0xFFFFFFFFu, rounds = 0u;
    for (;;) {
      rounds++;
      int n = collectHits(o, d, tcur, idcur, ray.dirTmax.w);
      for (int k = 0; k < n; k++) {
        backwardHit(kid[k], ka[k]);
        if (T < kMinTransmittance) break;
      }
      if (T < kMinTransmittance || n < K || rounds >= pc.maxRounds) break;
      tcur = kt[K - 1];
      idcur = kid[K - 1];
    }
  }
  vec3 dDirUnit = vec3(0.0);
  for (uint k = 1u; k < kShCoefficients; k++)
    if (k < coefficients) dDirUnit += shDir[k] * shBasisGradient(k, dn);
  dDir += normalizeBackward(d, dDirUnit);
  rayGrads[i] = RayGrad(vec4(dOrigin, 0.0), vec4(dDir, 0.0));
}
