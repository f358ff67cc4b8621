// GLSL side of the surface lattice (see surface_geometry.glsl): push constants, the height
// of a finest-lattice point, and the table that gives every evaluated point an index.
// Coarse-lattice points (with a one-vertex border ring for the normals of boundary
// vertices) live in gridHeights, (cellsX + 3) x (cellsY + 3); every other point requested
// during a trace gets an index into the point arrays through latticeIndex, one uint per
// point of the bordered finest lattice (a few MB: direct addressing beats hashing), which
// dedupes the requests so H is evaluated once per point.
// The including shader declares the buffers the parts it enables use:
//   SURFACE_LOOKUP: gridHeights[], latticeIndex[], pointHeights[]
//   SURFACE_INSERT: latticeIndex[] (writable), points[] (vec2), counters[]
#ifndef REFRAX_SURFACE_LATTICE_GLSL
#define REFRAX_SURFACE_LATTICE_GLSL

layout(push_constant) uniform Push {
  vec2 origin;   // (x0, y0)
  vec2 spacing;  // finest-lattice spacing (hx, hy)
  int cellsX;
  int cellsY;
  int levels;    // K
  uint latticeStride;  // (cellsX << levels) + 3: row length of latticeIndex
  uint count;    // rays
  int level;     // the level a dispatch works on
  float eta;     // n_air / n_water
  uint options;  // kOptionFaceNormals | kOptionHitNormals
  uint pointCapacity;
  uint mode;     // request shader: 0 edge midpoints, 1 normal rings
  uint pad0;
  uint pad1;
} pc;

const uint kOptionFaceNormals = 1u;
const uint kOptionHitNormals = 2u;
const uint kEmptyKey = 0xFFFFFFFFu;  // latticeIndex: not requested
const uint kClaimed = 0xFFFFFFFEu;   // latticeIndex: requested, index being assigned
const float kPlaneEps = 1e-6;

// counters[]
const uint kCountPoints = 0u;
const uint kCountMissed = 1u;
const uint kCountInvalid = 2u;
const uint kCountFallback = 3u;
const uint kCountNonFiniteGrad = 4u;
const uint kCountLookupFailed = 5u;
const uint kCountDegenerate = 6u;
const uint kCountBackFacing = 7u;

vec2 latticePoint(int X, int Y) { return pc.origin + vec2(X, Y) * pc.spacing; }
bool isCoarsePoint(int X, int Y) {
  int m = (1 << pc.levels) - 1;
  return (X & m) == 0 && (Y & m) == 0;
}
// Index into gridHeights, or -1 outside the bordered coarse grid.
int coarseIndex(int X, int Y) {
  int i = X >> pc.levels, j = Y >> pc.levels;
  if (i < -1 || j < -1 || i > pc.cellsX + 1 || j > pc.cellsY + 1) return -1;
  return (j + 1) * (pc.cellsX + 3) + i + 1;
}
// Slot of finest-lattice point (X, Y) in latticeIndex, or -1 outside the bordered lattice.
int latticeSlot(int X, int Y) {
  int nx = (pc.cellsX << pc.levels) + 1, ny = (pc.cellsY << pc.levels) + 1;
  if (X < -1 || Y < -1 || X > nx || Y > ny) return -1;
  return (Y + 1) * int(pc.latticeStride) + X + 1;
}
// A ray's origin and unit direction with tmin/tmax rescaled to it; false for NaN/inf or
// zero-length input.
bool loadRay(vec4 originTmin, vec4 dirTmax, out vec3 o, out vec3 d, out float tmin, out float tmax) {
  o = originTmin.xyz;
  float len = length(dirTmax.xyz);
  d = dirTmax.xyz / len;
  tmin = originTmin.w * len;
  tmax = dirTmax.w * len;
  bool finite = !any(isnan(originTmin)) && !any(isinf(originTmin)) && !any(isnan(dirTmax)) && !any(isinf(dirTmax));
  return finite && len > 0.0 && !isinf(len) && tmin >= 0.0 && tmax >= tmin;
}
void unpackCell(uint cell, out int i, out int j) {
  i = int(cell & 0xFFFFu);
  j = int(cell >> 16);
}
uint packCell(int i, int j) { return uint(i) | (uint(j) << 16); }
// Finest-lattice coordinates of corner `corner` of triangle (i, j, side) of level `level`.
void finestCorner(int i, int j, int side, int corner, int level, out int X, out int Y) {
  int vi, vj;
  triangleCorner(i, j, side, corner, vi, vj);
  X = vi << (pc.levels - level);
  Y = vj << (pc.levels - level);
}

#ifdef SURFACE_LOOKUP
// Height at a finest-lattice point; false when it was never evaluated.
bool heightAt(int X, int Y, out float z) {
  z = 0.0;
  if (isCoarsePoint(X, Y)) {
    int c = coarseIndex(X, Y);
    if (c < 0) return false;
    z = gridHeights[c];
    return true;
  }
  int slot = latticeSlot(X, Y);
  if (slot < 0) return false;
  uint index = latticeIndex[slot];
  if (index >= kClaimed) return false;
  z = pointHeights[index];
  return true;
}
vec3 latticeVertex(int X, int Y, inout bool ok) {
  float z;
  ok = heightAt(X, Y, z) && ok;
  return vec3(latticePoint(X, Y), z);
}
// Raw vertex normal (vertexNormalRaw) of finest-lattice vertex (X, Y).
vec3 vertexNormalAt(int X, int Y, inout bool ok) {
  float z[6];
  for (int k = 0; k < 6; k++) {
    int di, dj;
    ringOffset(k, di, dj);
    bool found = heightAt(X + di, Y + dj, z[k]);
    ok = ok && found;
  }
  return vertexNormalRaw(z[0], z[1], z[2], z[3], z[4], z[5], pc.spacing.x, pc.spacing.y);
}
#endif

#ifdef SURFACE_INSERT
// Makes sure point (X, Y) has an index and is queued for evaluation (coarse points have
// their heights already).
void requestPoint(int X, int Y) {
  if (isCoarsePoint(X, Y)) return;
  int slot = latticeSlot(X, Y);
  if (slot < 0) return;
  if (latticeIndex[slot] != kEmptyKey) return;  // cheap early out; the swap decides
  if (atomicCompSwap(latticeIndex[slot], kEmptyKey, kClaimed) != kEmptyKey) return;
  uint index = atomicAdd(counters[kCountPoints], 1u);
  latticeIndex[slot] = index;  // read only by later dispatches
  if (index < pc.pointCapacity) points[index] = latticePoint(X, Y);
}
#endif

#endif
