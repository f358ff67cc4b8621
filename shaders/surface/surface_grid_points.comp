#version 460
// The coarse lattice points, with a one-vertex border ring, where H is evaluated each step.
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_lattice.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) writeonly buffer Points { vec2 gridPoints[]; };
void main() {
  uint n = uint((pc.cellsX + 3) * (pc.cellsY + 3));
  uint k = gl_GlobalInvocationID.x;
  if (k >= n) return;
  int i = int(k % uint(pc.cellsX + 3)) - 1, j = int(k / uint(pc.cellsX + 3)) - 1;
  gridPoints[k] = latticePoint(i << pc.levels, j << pc.levels);
}
