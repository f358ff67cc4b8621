// A split child's offset from its parent's mean (engine/gaussian/densify.h: children drawn from
// N(mean, R S^2 R^T)), from counter-based normals, so the host's densify and the device's
// (shaders/gaussian/densify_*.comp) draw the same children with no random stream to share:
// normal (key, counter) is a hash of the two, key drawn once per densification from the run's
// generator, counter = (parent row * 2 + child) * 3 + axis. Shared by GLSL and C++
// (engine/gaussian/densify_split.h); include gaussian_math.glsl first.
#ifndef __cplusplus
#ifndef REFRAX_DENSIFY_SPLIT_GLSL
#define REFRAX_DENSIFY_SPLIT_GLSL
#define REFRAX_DENSIFY_SPLIT_BODY
#endif
#else
#define REFRAX_DENSIFY_SPLIT_BODY
#endif
#ifdef REFRAX_DENSIFY_SPLIT_BODY
#undef REFRAX_DENSIFY_SPLIT_BODY

// A 32-bit integer mix (the "lowbias32" constants): every input bit moves every output bit.
SHARED_FN uint counterHash(uint x) {
  x ^= x >> 16u;
  x *= 0x7feb352du;
  x ^= x >> 15u;
  x *= 0x846ca68bu;
  x ^= x >> 16u;
  return x;
}

// A standard normal from two 24-bit uniforms (Box-Muller), as engine/base/portable_random.h draws.
SHARED_FN real counterNormal(uint key, uint counter) {
  uint h1 = counterHash(counterHash(counter) ^ key);
  uint h2 = counterHash(h1 ^ 0x68e31da4u);
  real u1 = (real(h1 >> 8u) + real(0.5)) / real(16777216.0);
  real u2 = real(h2 >> 8u) / real(16777216.0);
  return sqrt(real(-2.0) * log(u1)) * cos(real(6.283185307179586) * u2);
}

// Child `child` (0 or 1) of the parent in row `row`: R (scale * z), z three counter normals.
SHARED_FN real3 splitChildOffset(real4 q, real3 logScale, uint key, uint row, uint child) {
  uint first = (row * 2u + child) * 3u;
  real3 local = real3(counterNormal(key, first) * exp(logScale.x), counterNormal(key, first + 1u) * exp(logScale.y),
                      counterNormal(key, first + 2u) * exp(logScale.z));
  return rotationOf(q) * local;
}
#endif
