#version 460
// One ray per pixel of a camera through its lens (shaders/include/camera_direction.glsl): every
// pixel in row-major order, or the pixels listed (index y * width + x) for a patch or ray-batch sampler.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "camera_direction.glsl"
#include "rays.glsl"
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Pixels { uint pixelIndex[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Rays { Ray rays[]; };
layout(push_constant) uniform Push {
  vec4 right;
  vec4 up;
  vec4 back;
  vec4 positionTmin;
  vec4 intrinsics;  // fx fy cx cy
  vec4 lensRadial;  // lens.glsl's coefficients
  vec4 lensExtra;
  uint width;
  uint count;
  uint flags;  // bit 0: read the pixel list; bits 8-15: the lens kind (LENS_*)
  float tmax;
} pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint p = (pc.flags & 1u) != 0u ? pixelIndex[i] : i;
  vec2 centre = vec2(float(p % pc.width), float(p / pc.width)) + 0.5;
  int lensKind = int((pc.flags >> 8) & 0xffu);
  vec3 d = cameraDirection(pc.right.xyz, pc.up.xyz, pc.back.xyz, pc.intrinsics, lensKind, pc.lensRadial, pc.lensExtra, centre);
  rays[i].originTmin = pc.positionTmin;
  rays[i].dirTmax = vec4(d, pc.tmax);
}
