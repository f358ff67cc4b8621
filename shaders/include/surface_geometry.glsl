// Geometry of the subdivided proxy mesh of the water surface, shared GLSL/C++.
//
// Lattice. The coarse grid has cellsX x cellsY cells; level k halves the spacing k times.
// Every vertex of every level is named by integer coordinates (X, Y) on the finest lattice
// (level K): a level-k vertex (i, j) is (i, j) * 2^(K-k). Its position is
// (x0 + X hx, y0 + Y hy, H(...)) with (hx, hy) the finest spacing, so a point shared by
// several levels or triangles has one height.
//
// Triangles. Cell (i, j) of a level is split along its (0,0)-(1,1) diagonal into side 0 =
// corners (0,0),(1,0),(1,1) and side 1 = (0,0),(1,1),(0,1) (engine/surface/grid_mesh.h's (a,b,d) and
// (a,d,c)). Splitting a triangle at its edge midpoints gives four triangles of the next
// level's lattice with the same diagonal direction, so every level is the same regular
// triangulation at half the spacing and a triangle is (level, i, j, side).
//
// Vertex normals. The normal of a vertex at level k is the normalised area-weighted sum of
// the face normals of its full 6-triangle fan in the level-k lattice, neighbours in CCW
// order (1,0),(1,1),(0,1),(-1,0),(-1,-1),(0,-1). Heights are evaluated at these neighbours
// even outside the domain (H is defined everywhere), so boundary vertices are not special.
// The sum of the fan's cross products is (hy sum a_k z_k, hx sum b_k z_k, 6 hx hy): linear in
// the neighbour heights (the centre height cancels), with a = (-2,-1,1,2,1,-1) and
// b = (1,-1,-2,-1,1,2). A vertex normal depends only on these 6 heights and the spacing, so
// every triangle and ray that asks for it gets the same bits, and the Phong-interpolated
// normal is continuous across triangle edges.
#if defined(__cplusplus) || !defined(REFRAX_SURFACE_GEOMETRY_GLSL)
#ifndef __cplusplus
#define REFRAX_SURFACE_GEOMETRY_GLSL
#endif

// Corner `corner` (0..2) of triangle (i, j, side), on that triangle's own lattice.
SHARED_FN void triangleCorner(int i, int j, int side, int corner, OUT(int) vi, OUT(int) vj) {
  vi = i + ((corner == 1 || (corner == 2 && side == 0)) ? 1 : 0);
  vj = j + ((corner == 2 || (corner == 1 && side == 1)) ? 1 : 0);
}

// Child `child` (0..3) of triangle (i, j, side), on the next level's lattice.
SHARED_FN void childTriangle(int i, int j, int side, int child, OUT(int) ci, OUT(int) cj, OUT(int) cside) {
  ci = 2 * i;
  cj = 2 * j;
  cside = side;
  if (side == 0) {
    // (0,0)(1,0)(1,1) | (1,0)(2,0)(2,1) | (1,1)(2,1)(2,2) | middle (1,0)(2,1)(1,1)
    if (child == 1 || child == 3) ci += 1;
    if (child == 2) { ci += 1; cj += 1; }
    if (child == 3) cside = 1;
  } else {
    // (0,0)(1,1)(0,1) | (1,1)(2,2)(1,2) | (0,1)(1,2)(0,2) | middle (0,1)(1,1)(1,2)
    if (child == 1) { ci += 1; cj += 1; }
    if (child == 2 || child == 3) cj += 1;
    if (child == 3) cside = 0;
  }
}

// Midpoint `m` (0..2) of the edges of triangle (i, j, side), on the next level's lattice:
// the vertices a subdivision adds.
SHARED_FN void edgeMidpoint(int i, int j, int side, int m, OUT(int) vi, OUT(int) vj) {
  // side 0: (1,0) (2,1) (1,1); side 1: (1,1) (1,2) (0,1)
  int di = side == 0 ? (m == 1 ? 2 : 1) : (m == 2 ? 0 : 1);
  int dj = side == 0 ? (m == 0 ? 0 : 1) : (m == 1 ? 2 : 1);
  vi = 2 * i + di;
  vj = 2 * j + dj;
}

// Neighbour k (0..5) of a vertex, CCW, and its weights in the fan normal.
SHARED_FN void ringOffset(int k, OUT(int) di, OUT(int) dj) {
  di = (k == 0 || k == 1) ? 1 : ((k == 3 || k == 4) ? -1 : 0);
  dj = (k == 1 || k == 2) ? 1 : ((k == 4 || k == 5) ? -1 : 0);
}
SHARED_FN real ringWeightX(int k) {
  return k == 0 ? real(-2) : (k == 1 ? real(-1) : (k == 2 ? real(1) : (k == 3 ? real(2) : (k == 4 ? real(1) : real(-1)))));
}
SHARED_FN real ringWeightY(int k) {
  return k == 0 ? real(1) : (k == 1 ? real(-1) : (k == 2 ? real(-2) : (k == 3 ? real(-1) : (k == 4 ? real(1) : real(2)))));
}

// Unnormalised vertex normal (the fan's area-weighted sum divided by hx hy, which keeps it
// O(1) whatever the spacing) from the 6 neighbour heights in ringOffset order.
SHARED_FN real3 vertexNormalRaw(real z0, real z1, real z2, real z3, real z4, real z5, real hx, real hy) {
  real sx = ringWeightX(0) * z0 + ringWeightX(1) * z1 + ringWeightX(2) * z2 + ringWeightX(3) * z3 + ringWeightX(4) * z4 +
            ringWeightX(5) * z5;
  real sy = ringWeightY(0) * z0 + ringWeightY(1) * z1 + ringWeightY(2) * z2 + ringWeightY(3) * z3 + ringWeightY(4) * z4 +
            ringWeightY(5) * z5;
  return real3(sx / hx, sy / hy, real(6));
}

// The ray o + t d against the plane of triangle (P0, P1, P2): tuv = (t, u, v) with u, v the
// barycentrics of P1 and P2, valid anywhere on the plane (inside the triangle when u, v >= 0
// and u + v <= 1). This is Moller-Trumbore written as the inverse of M = [e1 e2 -d], whose
// rows (the three vectors below over det) the backward reuses. False when the ray is
// parallel to the plane (to `relEps` of the triangle's scale).
SHARED_FN bool rayTrianglePlane(real3 o, real3 d, real3 P0, real3 P1, real3 P2, real relEps, OUT(real3) tuv) {
  real3 e1 = P1 - P0;
  real3 e2 = P2 - P0;
  real3 pv = cross(d, e2);
  real det = dot(e1, pv);
  tuv = real3(0);
  if (!(abs(det) > relEps * length(cross(e1, e2)) * length(d))) return false;
  real3 tv = o - P0;
  real3 qv = cross(tv, e1);
  tuv = real3(dot(e2, qv), dot(tv, pv), dot(d, qv)) / det;
  return true;
}

// Backward of rayTrianglePlane for the vertices: from g = dL/d(t, u, v) to dL/dP0..2.
// With x = (u, v, t) = M^-1 (o - P0), dx = -M^-1 (w0 dP0 + u dP1 + v dP2), w0 = 1 - u - v.
SHARED_FN void rayTrianglePlaneBackward(real3 d, real3 P0, real3 P1, real3 P2, real3 tuv, real3 g, OUT(real3) gP0, OUT(real3) gP1,
                                        OUT(real3) gP2) {
  real3 e1 = P1 - P0;
  real3 e2 = P2 - P0;
  real3 pv = cross(d, e2);
  real det = dot(e1, pv);
  real3 q = -(g.y * pv + g.z * cross(e1, d) + g.x * cross(e1, e2)) / det;
  gP0 = (real(1) - tuv.y - tuv.z) * q;
  gP1 = tuv.y * q;
  gP2 = tuv.z * q;
}

// Keeps the best of a triangle's children seen so far: the nearest hit inside a child in
// [tmin, tmax]; failing any, the child whose plane point lies least outside it (how far the
// barycentrics leave [0, 1]), the paper's "nearest child by plane distance".
SHARED_FN void considerChild(int child, bool planeOk, real3 tuv, real tmin, real tmax, INOUT(int) bestInside, INOUT(real) bestT,
                             INOUT(int) bestOutside, INOUT(real) bestOut) {
  if (!planeOk) return;
  real outside = max(max(-tuv.y, -tuv.z), tuv.y + tuv.z - real(1));
  if (outside <= real(0) && tuv.x >= tmin && tuv.x <= tmax) {
    if (bestInside < 0 || tuv.x < bestT) {
      bestInside = child;
      bestT = tuv.x;
    }
  } else if (bestOutside < 0 || outside < bestOut) {
    bestOutside = child;
    bestOut = outside;
  }
}

// The refracting hit on one triangle: intersection p, normal n facing the ray, refracted
// direction w. Vertex normals N0..2 are raw (vertexNormalRaw); with faceNormals the flat
// normal of the triangle is used instead (ablation (b)). Returns false when the ray is
// parallel to the triangle's plane. backFacing tells whether n had to be flipped.
SHARED_FN bool surfaceHitForward(real3 o, real3 d, real3 P0, real3 P1, real3 P2, real3 N0, real3 N1, real3 N2, bool faceNormals,
                                 real eta, OUT(real3) tuv, OUT(real3) p, OUT(real3) n, OUT(real3) w, OUT(bool) backFacing) {
  bool ok = rayTrianglePlane(o, d, P0, P1, P2, real(1e-6), tuv);
  p = o + tuv.x * d;
  real3 m = faceNormals ? cross(P1 - P0, P2 - P0)
                        : (real(1) - tuv.y - tuv.z) * normalize(N0) + tuv.y * normalize(N1) + tuv.z * normalize(N2);
  n = normalize(m);
  real s = snellFacingSign(d, n);
  backFacing = s < real(0);
  n = s * n;
  w = snellRefract(d, n, eta);
  return ok;
}

// Backward of surfaceHitForward for the geometry: from dL/dp and dL/dw to dL/dP0..2 and
// dL/dN0..2 (raw vertex normals). The orientation flip and the triangle are held fixed.
SHARED_FN void surfaceHitBackward(real3 o, real3 d, real3 P0, real3 P1, real3 P2, real3 N0, real3 N1, real3 N2, bool faceNormals,
                                  real eta, real3 gp, real3 gw, OUT(real3) gP0, OUT(real3) gP1, OUT(real3) gP2, OUT(real3) gN0,
                                  OUT(real3) gN1, OUT(real3) gN2) {
  real3 tuv;
  rayTrianglePlane(o, d, P0, P1, P2, real(0), tuv);
  real u = tuv.y;
  real v = tuv.z;
  real w0 = real(1) - u - v;
  real3 n0 = normalize(N0);
  real3 n1 = normalize(N1);
  real3 n2 = normalize(N2);
  real3 e1 = P1 - P0;
  real3 e2 = P2 - P0;
  real3 m = faceNormals ? cross(e1, e2) : w0 * n0 + u * n1 + v * n2;
  real lm = length(m);
  real3 n = m / lm;
  real s = snellFacingSign(d, n);
  real3 gd;
  real3 gns;
  snellRefractBackward(d, s * n, eta, gw, gd, gns);
  real3 gn = s * gns;
  real3 gm = (gn - n * dot(n, gn)) / lm;  // through the normalisation
  real3 gtuv = real3(dot(gp, d), real(0), real(0));  // p = o + t d
  gP0 = real3(0);
  gP1 = real3(0);
  gP2 = real3(0);
  gN0 = real3(0);
  gN1 = real3(0);
  gN2 = real3(0);
  if (faceNormals) {
    real3 ge1 = cross(e2, gm);
    real3 ge2 = cross(gm, e1);
    gP1 = ge1;
    gP2 = ge2;
    gP0 = -ge1 - ge2;
  } else {
    gtuv.y = dot(gm, n1 - n0);
    gtuv.z = dot(gm, n2 - n0);
    // through each vertex normal's normalisation
    gN0 = (w0 * gm - n0 * dot(n0, w0 * gm)) / length(N0);
    gN1 = (u * gm - n1 * dot(n1, u * gm)) / length(N1);
    gN2 = (v * gm - n2 * dot(n2, v * gm)) / length(N2);
  }
  real3 hP0;
  real3 hP1;
  real3 hP2;
  rayTrianglePlaneBackward(d, P0, P1, P2, tuv, gtuv, hP0, hP1, hP2);
  gP0 += hP0;
  gP1 += hP1;
  gP2 += hP2;
}

#endif
