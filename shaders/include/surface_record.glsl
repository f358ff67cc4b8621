// Per-ray record of the water-surface stage (std430, one source for the shaders and the host:
// layout_prelude.glsl; the host's engine/surface/surface_record.h): which triangle the ray
// ended on and where, and what happened to it.
#ifndef REFRAX_SURFACE_RECORD_GLSL
#define REFRAX_SURFACE_RECORD_GLSL
#include "layout_prelude.glsl"
LAYOUT_STRUCT(SurfaceRecord, SurfaceRecord)
  LAYOUT_UINT(cell)  // i | j << 16 on the lattice of `level`
  LAYOUT_UINT(info)  // side | level << 1 | flags << 8
  LAYOUT_FLOAT(t)    // hit distance along the normalised direction
  LAYOUT_FLOAT(u)    // barycentric of corner 1
  LAYOUT_FLOAT(v)    // barycentric of corner 2
  LAYOUT_UINT(pad0)
  LAYOUT_UINT(pad1)
  LAYOUT_UINT(pad2)
LAYOUT_END(SurfaceRecord, 32)
LAYOUT_CONST(kSurfaceHit, 1u)            // refracted at the surface
LAYOUT_CONST(kSurfaceMissed, 2u)         // missed the domain: continues unrefracted
LAYOUT_CONST(kSurfaceInvalidRay, 4u)     // NaN/inf or zero-length input: traces nothing
LAYOUT_CONST(kSurfaceFallback, 8u)       // some level kept the nearest child by plane distance
LAYOUT_CONST(kSurfaceBackFacing, 16u)    // the interpolated normal faced away and was flipped
LAYOUT_CONST(kSurfaceDegenerate, 32u)    // parallel to the final triangle: continues unrefracted
LAYOUT_CONST(kSurfaceLookupFailed, 64u)  // a needed height was never evaluated (a bug if ever set)

// The fields packed in `cell` and `info`.
LAYOUT_FN uint surfaceRecordFlags(SurfaceRecord r) { return r.info >> 8u; }
LAYOUT_FN uint surfaceRecordSide(SurfaceRecord r) { return r.info & 1u; }
LAYOUT_FN uint surfaceRecordLevel(SurfaceRecord r) { return (r.info >> 1u) & 0x7Fu; }
LAYOUT_FN uint surfaceRecordCellI(SurfaceRecord r) { return r.cell & 0xFFFFu; }
LAYOUT_FN uint surfaceRecordCellJ(SurfaceRecord r) { return r.cell >> 16u; }
#endif
