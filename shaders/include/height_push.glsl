// Push constants of every height-field shader (mirrored by HeightPush in engine/height/height_field.cpp),
// and the specialization constants that carry the network's shape into the loop-based shaders.
#ifndef REFRAX_HEIGHT_PUSH_GLSL
#define REFRAX_HEIGHT_PUSH_GLSL
layout(push_constant) uniform HeightPush {
  vec2 domainMin;
  vec2 domainMax;
  uint count;          // points handled by this dispatch
  uint first;          // index of its first point in the points / heights / dLossdHeight buffers
  uint chunk;          // backward scratch capacity, in points
  uint slice;          // points summed by one invocation of the weight-gradient pass
  float initialHeight;
  uint weightBase;     // first weight of this dispatch (weight-gradient pass) / weight offset (layered)
  uint inOffset;       // layered forward: scratch offsets of the layer's input and output
  uint outOffset;
  float octaveWindow;  // coarse-to-fine encoding window (height_encoding.glsl), in [0, octaves]
} pc;

float heightNaN() { return uintBitsToFloat(0x7FC00000u); }
bool heightPointFinite(vec2 p) { return !any(isnan(p)) && !any(isinf(p)); }
#endif
