// The viewer's output colour per pixel: the traced RGB, or a heat map of how many Gaussian
// hits the ray blended; packed as RGBA8 (alpha 255) with the same rounding as the PNG writer
// (round half up), so a screenshot equals `refrax render`'s PNG of the same trace.
// Shared GLSL/C++ (see shared_prelude.glsl).
#if defined(__cplusplus) || !defined(REFRAX_VIEW_COMPOSE_GLSL)
#ifndef __cplusplus
#define REFRAX_VIEW_COMPOSE_GLSL
#endif

// hits / fullScale clamped to [0, 1] along a ramp black -> blue -> orange -> pale yellow
// (three linear segments), so zero hits stays black and the scale's top is the brightest.
SHARED_FN real3 heatMapColour(real hits, real fullScale) {
  real s = clamp(hits / fullScale, real(0), real(1)) * real(3);
  real3 a = mix(real3(0, 0, 0), real3(0.2, 0.1, 0.8), clamp(s, real(0), real(1)));
  real3 b = mix(a, real3(0.9, 0.3, 0.1), clamp(s - real(1), real(0), real(1)));
  return mix(b, real3(1.0, 1.0, 0.6), clamp(s - real(2), real(0), real(1)));
}

// One colour channel in [0, 1] (clamped) to 0..255.
SHARED_FN uint quantizeChannel(real v) { return uint(clamp(v, real(0), real(1)) * real(255) + real(0.5)); }

SHARED_FN uint packRgba8(real3 c) {
  return quantizeChannel(c.x) | (quantizeChannel(c.y) << 8u) | (quantizeChannel(c.z) << 16u) | (255u << 24u);
}

#endif
