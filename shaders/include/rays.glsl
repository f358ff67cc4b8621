// Ray and hit records shared by the ray-query shaders (std430 layouts mirrored in
// engine/trace/rays.h). A ray is an origin with its tmin and a direction with its tmax.
#ifndef REFRAX_RAYS_GLSL
#define REFRAX_RAYS_GLSL
struct Ray {
  vec4 originTmin;
  vec4 dirTmax;
};
// Closest triangle hit: t < 0 and primitive == 0xFFFFFFFF on a miss.
struct TriangleHit {
  float t;
  float u;  // barycentric of vertex 1
  float v;  // barycentric of vertex 2
  uint primitive;
};
const uint kNoHit = 0xFFFFFFFFu;
// Gradient of the loss with respect to one ray's origin and direction (what the Gaussian
// tracer's backward hands to the surface backward).
struct RayGrad {
  vec4 dOrigin;  // xyz used
  vec4 dDir;     // xyz used
};
#endif
