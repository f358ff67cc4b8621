// Pinhole camera given as position and three basis vectors, right/up pre-scaled by
// tan(half field of view): pixel centre (px+0.5, py+0.5) maps to fwd + u*right - v*up.
#ifndef REFRAX_CAMERA_GLSL
#define REFRAX_CAMERA_GLSL
#include "pinhole_camera.glsl"
vec3 cameraRayDirection(PinholeCamera cam, uvec2 pixel, uvec2 size) {
  vec2 uv = (vec2(pixel) + 0.5) / vec2(size) * 2.0 - 1.0;
  return normalize(cam.forward.xyz + uv.x * cam.right.xyz - uv.y * cam.up.xyz);
}
#endif
