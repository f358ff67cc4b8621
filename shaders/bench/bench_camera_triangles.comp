#version 460
// Benchmark: one closest-hit ray per pixel of a pinhole camera against a triangle scene
// (the same work as the rqprobe 'tri' test, so the two rates compare directly).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "camera.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) writeonly buffer Out { vec4 result[]; };
layout(push_constant) uniform Push { PinholeCamera cam; uvec4 size; } pc;
void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.size.x || p.y >= pc.size.y) return;
  vec3 d = cameraRayDirection(pc.cam, p, pc.size.xy);
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, pc.cam.position.xyz, 0.0, d, 100.0);
  while (rayQueryProceedEXT(rq)) {}
  vec4 r = vec4(-1.0);
  if (rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT) {
    r.x = rayQueryGetIntersectionTEXT(rq, true);
    r.yz = rayQueryGetIntersectionBarycentricsEXT(rq, true);
    r.w = float(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
  }
  result[p.y * pc.size.x + p.x] = r;
}
