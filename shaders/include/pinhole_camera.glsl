// A pinhole camera as position and three basis vectors, right/up pre-scaled by the tangents of
// the half fields of view (std430, one source for the shaders and the host: layout_prelude.glsl;
// the host's GpuPinholeCamera in engine/view/fly_camera.h); xyz used.
#ifndef REFRAX_PINHOLE_CAMERA_GLSL
#define REFRAX_PINHOLE_CAMERA_GLSL
#include "layout_prelude.glsl"
LAYOUT_STRUCT(PinholeCamera, GpuPinholeCamera)
  LAYOUT_VEC4(position)
  LAYOUT_VEC4(forward)
  LAYOUT_VEC4(right)
  LAYOUT_VEC4(up)
LAYOUT_END(GpuPinholeCamera, 64)
#endif
