#version 460
// Heights of the closed-form test surface (include/analytic_height.glsl) at a list of points.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "analytic_height.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Heights { float heights[]; };
layout(push_constant) uniform Push { vec4 waves[4]; vec4 sigmas; float base; uint count; } pc;
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= pc.count) return;
  vec2 p = points[k];
  heights[k] = analyticHeight(p.x, p.y, pc.base, pc.waves[0], pc.waves[1], pc.waves[2], pc.waves[3], pc.sigmas);
}
