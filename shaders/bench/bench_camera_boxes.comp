#version 460
// Benchmark: visit every AABB candidate along each camera ray and evaluate a Gaussian's
// peak response there (the same work as the rqprobe 'aabb ... all candidates' test).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "camera.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) writeonly buffer Out { vec4 result[]; };
// mean + density, then the symmetric precision matrix (a00 a01 a02 a11)(a12 a22 - -)
struct BenchGaussian { vec4 meanDensity; vec4 p0; vec4 p1; };
layout(std430, set = 0, binding = 2) readonly buffer Gaussians { BenchGaussian g[]; };
layout(push_constant) uniform Push { PinholeCamera cam; uvec4 size; vec4 thresholds; } pc;

float peakResponse(BenchGaussian q, vec3 o, vec3 d, out float tPeak) {
  vec3 om = o - q.meanDensity.xyz;
  mat3 A = mat3(q.p0.x, q.p0.y, q.p0.z, q.p0.y, q.p0.w, q.p1.x, q.p0.z, q.p1.x, q.p1.y);
  vec3 Ad = A * d;
  float dAd = dot(d, Ad), dAo = dot(om, Ad), oAo = dot(om, A * om);
  tPeak = -dAo / dAd;
  return q.meanDensity.w * exp(-0.5 * max(oAo - dAo * dAo / dAd, 0.0));
}

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.size.x || p.y >= pc.size.y) return;
  vec3 o = pc.cam.position.xyz;
  vec3 d = cameraRayDirection(pc.cam, p, pc.size.xy);
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsNoOpaqueEXT, 0xFF, o, 0.0, d, 100.0);
  uint candidates = 0u, hits = 0u;
  float T = 1.0, depth = 0.0;
  while (rayQueryProceedEXT(rq)) {
    if (rayQueryGetIntersectionTypeEXT(rq, false) == gl_RayQueryCandidateIntersectionAABBEXT) {
      uint id = rayQueryGetIntersectionPrimitiveIndexEXT(rq, false);
      candidates++;
      float tPeak;
      float a = peakResponse(g[id], o, d, tPeak);
      if (a > pc.thresholds.x) { hits++; depth += a * tPeak; T *= 1.0 - a; }
    }
  }
  result[p.y * pc.size.x + p.x] = vec4(float(candidates), float(hits), T, depth);
}
