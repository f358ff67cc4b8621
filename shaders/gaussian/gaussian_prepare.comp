#version 460
// Gaussian proxies from raw parameters, in proxy order (order[k] = Gaussian id of slot k):
// the tracer's per-candidate record, an axis-aligned box at the adaptive cut-off radius
// (AABB-BLAS variant) and a scaled-rotated unit-box instance (instanced variant); and the SH
// coefficients packed as vec4s per Gaussian id; and, in the record's order, the cut-off
// ellipsoid's bounding sphere (the tiled forward's culling, tile_cull.comp).
// Run again before a refit when the Gaussians move.
#extension GL_GOOGLE_include_directive : require
#include "gaussian_trace_types.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Params { float params[]; };
layout(std430, set = 0, binding = 1) readonly buffer Order { uint order[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Trace { TraceGaussian tg[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Boxes { float boxes[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Instances { uint instances[]; };
layout(std430, set = 0, binding = 5) writeonly buffer ShPacked { vec4 shPacked[]; };  // kShVec4s per Gaussian id
layout(std430, set = 0, binding = 6) writeonly buffer Spheres { vec4 spheres[]; };    // centre, radius per tg record
layout(push_constant) uniform Push {
  uint count;
  uint instanced;      // 1: tg indexed by Gaussian id (the instance's custom index)
  uvec2 unitBoxBlas;   // device address of the unit-box BLAS (instanced variant)
} pc;

// Slightly larger than the cut-off so float rounding never clips an accepted peak.
const float kBoxMargin = 1.001;
const uint kForceNoOpaque = 0x8u;  // VK_GEOMETRY_INSTANCE_FORCE_NO_OPAQUE_BIT_KHR

void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.count) return;
  uint id = order[k];
  uint b = id * kGaussFloats;
  vec3 mu = vec3(params[b + kGaussMean], params[b + kGaussMean + 1u], params[b + kGaussMean + 2u]);
  vec4 q = vec4(params[b + kGaussRotation], params[b + kGaussRotation + 1u], params[b + kGaussRotation + 2u], params[b + kGaussRotation + 3u]);
  vec3 s = exp(vec3(params[b + kGaussLogScale], params[b + kGaussLogScale + 1u], params[b + kGaussLogScale + 2u]));
  float density = sigmoidOf(params[b + kGaussLogitDensity]);
  mat3 R = rotationOf(q);
  mat3 M = worldToLocalOf(R, 1.0 / s);
  float radius = proxyRadiusOf(density) * kBoxMargin;
  mat3 A = transpose(M) * M;
  // the SH coefficients as vec4s, so the tracer loads a hit's colour in 12 loads, not 48
  for (uint j = 0u; j < kShVec4s; j++) {
    uint f = b + kGaussSH + 4u * j;
    shPacked[id * kShVec4s + j] = vec4(params[f], params[f + 1u], params[f + 2u], params[f + 3u]);
  }
  uint record = pc.instanced != 0u ? id : k;
  // the ellipsoid radius * R S * unit ball lies within radius * max scale of its centre
  spheres[record] = vec4(mu, radius * max(s.x, max(s.y, s.z)));
  tg[record] = TraceGaussian(vec4(mu, density), vec4(A[0][0], A[0][1], A[0][2], A[1][1]),
                             vec4(A[1][2], A[2][2], uintBitsToFloat(id), radius * radius));

  if (pc.instanced == 0u) {
    // world-axis half extent of the ellipsoid R S (radius * unit ball): |row a of R S|
    vec3 e;
    for (int a = 0; a < 3; a++) {
      float extent = radius * length(vec3(R[0][a] * s.x, R[1][a] * s.y, R[2][a] * s.z));
      e[a] = isnan(extent) ? kMaxProxyHalfExtent : min(extent, kMaxProxyHalfExtent);  // inf (and inf * 0) clamped too
    }
    for (int a = 0; a < 3; a++) {
      boxes[6u * k + uint(a)] = mu[a] - e[a];
      boxes[6u * k + 3u + uint(a)] = mu[a] + e[a];
    }
    return;
  }
  // VkAccelerationStructureInstanceKHR: 3x4 row-major transform, custom index | mask,
  // SBT offset | flags, BLAS address
  uint w = 16u * k;
  for (int r = 0; r < 3; r++) {
    for (int c = 0; c < 3; c++) instances[w + 4u * uint(r) + uint(c)] = floatBitsToUint(R[c][r] * s[c] * radius);
    instances[w + 4u * uint(r) + 3u] = floatBitsToUint(mu[r]);
  }
  instances[w + 12u] = (id & 0xFFFFFFu) | (0xFFu << 24);
  instances[w + 13u] = kForceNoOpaque << 24;
  instances[w + 14u] = pc.unitBoxBlas.x;
  instances[w + 15u] = pc.unitBoxBlas.y;
}
