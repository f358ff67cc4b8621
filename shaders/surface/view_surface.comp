#version 460
// refrax-variant: compute REFRAX_COMPUTE_TRACE
// Viewer/preview: the water surface mesh seen from a pinhole camera, shaded by its face
// normal (mode 0) or with its triangle edges drawn over (mode 1). Writes packed RGBA8.
#extension GL_GOOGLE_include_directive : require
#ifndef REFRAX_COMPUTE_TRACE
#extension GL_EXT_ray_query : require
#endif
#include "camera.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
#ifdef REFRAX_COMPUTE_TRACE
#include "box_bvh.glsl"
layout(std430, set = 0, binding = 0) readonly buffer BvhNodes { BvhNode bvhNodes[]; };
#else
layout(set = 0, binding = 0) uniform accelerationStructureEXT surface;
#endif
layout(std430, set = 0, binding = 1) readonly buffer Vertices { float vertices[]; };
layout(std430, set = 0, binding = 2) readonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Pixels { uint pixels[]; };
layout(push_constant) uniform Push {
  PinholeCamera cam;
  uvec4 size;  // width, height, mode, unused
  vec4 background;
} pc;

vec3 vertexAt(uint i) { return vec3(vertices[3 * i], vertices[3 * i + 1], vertices[3 * i + 2]); }
#ifdef REFRAX_COMPUTE_TRACE
vec3 positionAt(uint i) { return vertexAt(i); }
#include "grid_walk.glsl"
#include "triangle_bvh.glsl"
#endif

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  if (p.x >= pc.size.x || p.y >= pc.size.y) return;
  vec3 d = cameraRayDirection(pc.cam, p, pc.size.xy);
  vec3 colour = pc.background.rgb;
  uint prim;
  vec2 bary;
#ifdef REFRAX_COMPUTE_TRACE
  float t;
  bool hit = bvhClosestTriangle(pc.cam.position.xyz, d, 0.0, 1e4, prim, t, bary);
#else
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, surface, gl_RayFlagsOpaqueEXT, 0xFF, pc.cam.position.xyz, 0.0, d, 1e4);
  while (rayQueryProceedEXT(rq)) {}
  bool hit = rayQueryGetIntersectionTypeEXT(rq, true) == gl_RayQueryCommittedIntersectionTriangleEXT;
  prim = hit ? rayQueryGetIntersectionPrimitiveIndexEXT(rq, true) : 0u;
  bary = hit ? rayQueryGetIntersectionBarycentricsEXT(rq, true) : vec2(0.0);
#endif
  if (hit) {
    vec3 a = vertexAt(indices[3 * prim]), b = vertexAt(indices[3 * prim + 1]), c = vertexAt(indices[3 * prim + 2]);
    vec3 n = normalize(cross(b - a, c - a));
    if (dot(n, d) > 0.0) n = -n;
    colour = n * 0.5 + 0.5;
    if (pc.size.z == 1u) {
      float edge = min(min(bary.x, bary.y), 1.0 - bary.x - bary.y);
      if (edge < 0.03) colour = vec3(1.0);
    }
  }
  uvec3 q = uvec3(clamp(colour, 0.0, 1.0) * 255.0 + 0.5);
  pixels[p.y * pc.size.x + p.x] = q.r | (q.g << 8) | (q.b << 16) | (255u << 24);
}
