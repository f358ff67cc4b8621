// Per-ray record of the water-surface stage (std430, mirrored in engine/surface/surface_record.h):
// which triangle the ray ended on and where, and what happened to it.
#ifndef REFRAX_SURFACE_RECORD_GLSL
#define REFRAX_SURFACE_RECORD_GLSL
struct SurfaceRecord {
  uint cell;  // i | j << 16 on the lattice of `level`
  uint info;  // side | level << 1 | flags << 8
  float t;    // hit distance along the normalised direction
  float u;    // barycentric of corner 1
  float v;    // barycentric of corner 2
  uint pad0;
  uint pad1;
  uint pad2;
};
const uint kSurfaceHit = 1u;           // refracted at the surface
const uint kSurfaceMissed = 2u;        // missed the domain: continues unrefracted
const uint kSurfaceInvalidRay = 4u;    // NaN/inf or zero-length input: traces nothing
const uint kSurfaceFallback = 8u;      // some level kept the nearest child by plane distance
const uint kSurfaceBackFacing = 16u;   // the interpolated normal faced away and was flipped
const uint kSurfaceDegenerate = 32u;   // parallel to the final triangle: continues unrefracted
const uint kSurfaceLookupFailed = 64u; // a needed height was never evaluated (a bug if ever set)
#endif
