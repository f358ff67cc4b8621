// The height field's input encoding and activation, shared by the shaders and the CPU
// double reference (see shared_prelude.glsl). One place for this math.
//
// Encoding (NeRF frequency encoding of the domain-normalised point u in [-1,1]^2), with
// L octaves, 2 + 4L inputs:
//   e[0] = u.x, e[1] = u.y, and for octave k = 0..L-1:
//   e[2+4k] = sin(2^k pi u.x), e[3+4k] = sin(2^k pi u.y),
//   e[4+4k] = cos(2^k pi u.x), e[5+4k] = cos(2^k pi u.y).
// Coarse-to-fine window (BARF, Lin et al. 2021): octave k's four features are scaled by
// w_k(a) = (1 - cos(pi clamp(a - k, 0, 1))) / 2 for the window a in [0, L]; a = L keeps
// every octave (w = 1), a = 2 keeps octaves 0 and 1 and silences the rest. Why: the surface
// gradient reaches the heights through normals (slopes), which weight a height mode of
// frequency f by f, so high octaves make the optimisation stiff; opening them late lets the
// low frequencies settle first (measured: docs/training.md).
// The phase 2^k u is reduced to [-1, 1) exactly before multiplying by pi (a power-of-two
// scale and the subtraction of an even integer are exact in float), so float shaders keep
// ~1e-7 absolute accuracy even at the top octave instead of losing it to |2^k pi u| ~ 100.
#ifndef __cplusplus
#ifndef REFRAX_HEIGHT_ENCODING_GLSL
#define REFRAX_HEIGHT_ENCODING_GLSL
#include "shared_prelude.glsl"
#define REFRAX_HEIGHT_ENCODING_BODY
#endif
#else
#define REFRAX_HEIGHT_ENCODING_BODY
#endif

#ifdef REFRAX_HEIGHT_ENCODING_BODY
#undef REFRAX_HEIGHT_ENCODING_BODY

SHARED_FN uint heightInputCount(uint octaves) { return 2u + 4u * octaves; }

// World (x, y) to [-1,1]^2 over the configured domain.
SHARED_FN real2 heightDomainToUnit(real2 p, real2 domainMin, real2 domainMax) {
  return (p - domainMin) / (domainMax - domainMin) * real(2) - real(1);
}

// sin/cos(pi * t) after reducing t to [-1, 1) by an even integer (exact).
SHARED_FN real heightReducedPhase(real t) { return t - real(2) * floor(t * real(0.5) + real(0.5)); }

// The coarse-to-fine weight of octave k under window a (see above).
// Written as sin^2(pi r / 2), the same value: (1 - cos(pi r)) / 2 loses it to cancellation in
// float just after an octave opens (r = 0.002: w ~ 1e-5 with a 3e-3 relative error, which the
// backward test caught against the double reference on seed 1296416736).
SHARED_FN real heightOctaveWeight(uint octave, real window) {
  real r = clamp(window - real(octave), real(0), real(1));
  real s = sin(real(1.57079632679489661923) * r);
  return s * s;
}

// Input i (0 <= i < 2 + 4L) of the encoding of u under the coarse-to-fine window.
SHARED_FN real heightEncodingFeature(real2 u, uint i, real window) {
  if (i == 0u) return u.x;
  if (i == 1u) return u.y;
  uint j = i - 2u;
  uint octave = j / 4u;
  uint kind = j % 4u;  // 0: sin x, 1: sin y, 2: cos x, 3: cos y
  real t = ((kind % 2u) == 0u ? u.x : u.y) * real(1u << octave);
  real phase = real(3.14159265358979323846) * heightReducedPhase(t);
  return heightOctaveWeight(octave, window) * (kind < 2u ? sin(phase) : cos(phase));
}

// Leaky ReLU and its derivative as a function of the activation's output (which has the
// sign of its input for 0 < slope): 1 above zero, slope at and below zero.
SHARED_FN real heightLeakyRelu(real z, real slope) { return max(z, slope * z); }
SHARED_FN real heightLeakyReluSlopeAt(real activated, real slope) { return activated > real(0) ? real(1) : slope; }

#endif
