// Pinhole camera rays (shared by the camera-ray shader and the CPU reference).
// Blender/NeRF convention: the camera-to-world matrix's columns are the camera's right (+X),
// up (+Y) and back (+Z) axes and its position; the camera looks down its -Z. Image x grows
// to the right and image y downwards, so a pixel at continuous coordinates (u, v) looks along
//   right * (u - cx) / fx - up * (v - cy) / fy - back,
// and pixel (i, j)'s ray goes through its centre (i + 0.5, j + 0.5).
#if defined(__cplusplus) || !defined(REFRAX_PINHOLE_GLSL)
#ifndef __cplusplus
#define REFRAX_PINHOLE_GLSL
#endif

// intrinsics = (fx, fy, cx, cy) in pixels; the returned direction has unit length.
SHARED_FN real3 pinholeDirection(real3 right, real3 up, real3 back, real4 intrinsics, real2 pixelCoord) {
  real3 d = right * ((pixelCoord.x - intrinsics.z) / intrinsics.x) - up * ((pixelCoord.y - intrinsics.w) / intrinsics.y) - back;
  return normalize(d);
}
#endif
