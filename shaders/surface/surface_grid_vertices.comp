#version 460
// Lifts the coarse grid's interior vertices to z = H for the BLAS (xyz, 12-byte stride,
// index j * (cellsX + 1) + i as engine/surface/grid_mesh.h numbers them).
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_lattice.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer GridHeights { float gridHeights[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Vertices { float vertices[]; };
void main() {
  uint n = uint((pc.cellsX + 1) * (pc.cellsY + 1));
  uint k = gl_GlobalInvocationID.x;
  if (k >= n) return;
  int i = int(k % uint(pc.cellsX + 1)), j = int(k / uint(pc.cellsX + 1));
  int X = i << pc.levels, Y = j << pc.levels;
  vec2 xy = latticePoint(X, Y);
  vertices[3 * k] = xy.x;
  vertices[3 * k + 1] = xy.y;
  vertices[3 * k + 2] = gridHeights[coarseIndex(X, Y)];
}
