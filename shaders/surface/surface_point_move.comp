#version 460
// The one-submission trace's copies around the height source, for the range that
// surface_point_range.comp wrote: mode 0 gathers the level's new points into evalPoints[0, n);
// mode 1 scatters their heights into pointHeights[base, base + n).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Range { uint range[]; };
layout(std430, set = 0, binding = 1) readonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 2) buffer EvalPoints { vec2 evalPoints[]; };
layout(std430, set = 0, binding = 3) readonly buffer EvalHeights { float evalHeights[]; };
layout(std430, set = 0, binding = 4) buffer PointHeights { float pointHeights[]; };
layout(push_constant) uniform Push { uint mode; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= range[2]) return;
  uint k = range[1] + i;
  if (pc.mode == 0u) evalPoints[i] = points[k];
  else pointHeights[k] = evalHeights[i];
}
