#version 460
// A triangle mesh swapped in for the water (engine/mesh_surface.h): one ray query per ray,
// closest opaque hit; at the hit, the interpolated vertex normal and Snell's law give the
// refracted ray. Output conventions are those of surface_refract.comp, so the Gaussian tracer
// treats both alike: a hit gives (origin p, tmin 0, unit direction w, tmax = what was left of
// the ray's range); a miss continues unchanged; an invalid ray becomes an empty ray
// (origin 0, tmin = tmax = 0).
#extension GL_EXT_ray_query : require
#extension GL_GOOGLE_include_directive : require
#include "rays.glsl"
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "mesh_refract.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0) uniform accelerationStructureEXT scene;
layout(std430, set = 0, binding = 1) readonly buffer Rays { Ray rays[]; };
layout(std430, set = 0, binding = 2) readonly buffer Positions { float positions[]; };  // xyz per vertex (the BLAS input)
layout(std430, set = 0, binding = 3) readonly buffer Normals { float normals[]; };      // unit xyz per vertex
layout(std430, set = 0, binding = 4) readonly buffer Indices { uint indices[]; };       // 3 per triangle
layout(std430, set = 0, binding = 5) writeonly buffer Refracted { Ray refracted[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Flags { uint flags[]; };
layout(push_constant) uniform Push {
  uint count;
  float eta;
} pc;

vec3 positionAt(uint i) { return vec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]); }
vec3 normalAt(uint i) { return vec3(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]); }

void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  Ray ray = rays[r];
  // As loadRay in surface_lattice.glsl: unit direction, tmin/tmax rescaled to it.
  float len = length(ray.dirTmax.xyz);
  vec3 o = ray.originTmin.xyz;
  vec3 d = ray.dirTmax.xyz / len;
  float tmin = ray.originTmin.w * len;
  float tmax = ray.dirTmax.w * len;
  bool finite = !any(isnan(ray.originTmin)) && !any(isinf(ray.originTmin)) && !any(isnan(ray.dirTmax)) && !any(isinf(ray.dirTmax));
  if (!(finite && len > 0.0 && !isinf(len) && tmin >= 0.0 && tmax >= tmin)) {
    refracted[r] = Ray(vec4(0.0), vec4(0.0, 0.0, -1.0, 0.0));
    flags[r] = kSurfaceInvalidRay;
    return;
  }
  rayQueryEXT rq;
  rayQueryInitializeEXT(rq, scene, gl_RayFlagsOpaqueEXT, 0xFF, o, tmin, d, tmax);
  while (rayQueryProceedEXT(rq)) {}
  if (rayQueryGetIntersectionTypeEXT(rq, true) != gl_RayQueryCommittedIntersectionTriangleEXT) {
    refracted[r] = ray;
    flags[r] = kSurfaceMissed;
    return;
  }
  uint tri = uint(rayQueryGetIntersectionPrimitiveIndexEXT(rq, true));
  float t = rayQueryGetIntersectionTEXT(rq, true);
  vec2 bary = rayQueryGetIntersectionBarycentricsEXT(rq, true);
  uint i0 = indices[3 * tri], i1 = indices[3 * tri + 1], i2 = indices[3 * tri + 2];
  vec3 P0 = positionAt(i0);
  vec3 face = cross(positionAt(i1) - P0, positionAt(i2) - P0);
  vec3 n, w;
  bool backFacing;
  meshHitRefract(d, bary.x, bary.y, normalAt(i0), normalAt(i1), normalAt(i2), face, pc.eta, n, w, backFacing);
  refracted[r] = Ray(vec4(o + t * d, 0.0), vec4(w, max(tmax - t, 0.0)));
  flags[r] = kSurfaceHit | (backFacing ? kSurfaceBackFacing : 0u);
}
