// Ray and hit records shared by the ray-query shaders and the host (std430, one source:
// layout_prelude.glsl; the host's engine/trace/rays.h). A ray is an origin with its tmin and a
// direction with its tmax.
#ifndef REFRAX_RAYS_GLSL
#define REFRAX_RAYS_GLSL
#include "layout_prelude.glsl"
LAYOUT_STRUCT(Ray, GpuRay)
  LAYOUT_XYZ_W(origin, tmin, originTmin)
  LAYOUT_XYZ_W(dir, tmax, dirTmax)
LAYOUT_END(GpuRay, 32)
// Closest triangle hit: t < 0 and primitive == kNoHit on a miss.
LAYOUT_STRUCT(TriangleHit, GpuTriangleHit)
  LAYOUT_FLOAT(t)
  LAYOUT_FLOAT(u)  // barycentric of vertex 1
  LAYOUT_FLOAT(v)  // barycentric of vertex 2
  LAYOUT_UINT(primitive)
LAYOUT_END(GpuTriangleHit, 16)
LAYOUT_CONST(kNoHit, 0xFFFFFFFFu)
// Gradient of the loss with respect to one ray's origin and direction (what the Gaussian
// tracer's backward hands to the surface backward); xyz used.
LAYOUT_STRUCT(RayGrad, GpuRayGrad)
  LAYOUT_XYZ_W(dOrigin, pad0, dOrigin)
  LAYOUT_XYZ_W(dDir, pad1, dDir)
LAYOUT_END(GpuRayGrad, 32)
#endif
