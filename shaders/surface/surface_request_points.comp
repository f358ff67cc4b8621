#version 460
// Queues the lattice points the next stage needs, each once (deduped through latticeIndex):
// mode 0: the edge midpoints of each ray's triangle of level `level` - 1 (the new vertices
//         of its children at `level`);
// mode 1: the corners of each ray's finest triangle and their 6 neighbours (vertex normals).
#extension GL_GOOGLE_include_directive : require
#include "shared_prelude.glsl"
#include "snell.glsl"
#include "surface_geometry.glsl"
#include "surface_record.glsl"
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Records { SurfaceRecord records[]; };
layout(std430, set = 0, binding = 1) buffer LatticeIndex { uint latticeIndex[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Points { vec2 points[]; };
layout(std430, set = 0, binding = 3) buffer Counters { uint counters[]; };
#define SURFACE_INSERT
#include "surface_lattice.glsl"
void main() {
  uint r = gl_GlobalInvocationID.x;
  if (r >= pc.count) return;
  SurfaceRecord rec = records[r];
  if (((rec.info >> 8) & kSurfaceHit) == 0u) return;
  int i, j;
  unpackCell(rec.cell, i, j);
  int side = int(rec.info & 1u);
  if (pc.mode == 0u) {
    int shift = pc.levels - pc.level;
    for (int m = 0; m < 3; m++) {
      int vi, vj;
      edgeMidpoint(i, j, side, m, vi, vj);
      requestPoint(vi << shift, vj << shift);
    }
  } else {
    // the 3 corners' rings overlap: 21 candidates, 12 distinct points; each requested once
    ivec2 seen[21];
    int n = 0;
    for (int c = 0; c < 3; c++) {
      int X, Y;
      finestCorner(i, j, side, c, pc.levels, X, Y);
      for (int k = -1; k < 6; k++) {
        int di = 0, dj = 0;
        if (k >= 0) ringOffset(k, di, dj);
        ivec2 q = ivec2(X + di, Y + dj);
        bool fresh = true;
        for (int m = 0; m < n; m++) fresh = fresh && seen[m] != q;
        if (!fresh) continue;
        seen[n++] = q;
        requestPoint(q.x, q.y);
      }
    }
  }
}
