// Camera rays through the lens (shared by the camera-ray shader and the CPU reference).
// Blender/NeRF convention: the camera-to-world matrix's columns are the camera's right (+X),
// up (+Y) and back (+Z) axes and its position; the camera looks down its -Z. Image x grows
// to the right and image y downwards, so through a pinhole a pixel at continuous coordinates
// (u, v) looks along
//   right * (u - cx) / fx - up * (v - cy) / fy - back,
// and pixel (i, j)'s ray goes through its centre (i + 0.5, j + 0.5). A distorted lens
// (lens.glsl) bends the same normalised point ((u - cx) / fx, (v - cy) / fy) first; its
// OpenCV-frame direction (x right, y down, z forward) becomes right * x - up * y - back * z.
#if defined(__cplusplus) || !defined(REFRAX_CAMERA_DIRECTION_GLSL)
#ifndef __cplusplus
#define REFRAX_CAMERA_DIRECTION_GLSL
#endif
#include "lens.glsl"

// intrinsics = (fx, fy, cx, cy) in pixels; the returned direction has unit length.
SHARED_FN real3 cameraDirection(real3 right, real3 up, real3 back, real4 intrinsics, int lensKind, real4 lensRadial, real4 lensExtra,
                                real2 pixelCoord) {
  real2 m = real2((pixelCoord.x - intrinsics.z) / intrinsics.x, (pixelCoord.y - intrinsics.w) / intrinsics.y);
  real3 d = lensUnproject(lensKind, lensRadial, lensExtra, m);
  return normalize(right * d.x - up * d.y - back * d.z);
}
#endif
