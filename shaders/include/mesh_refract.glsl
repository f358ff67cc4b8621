// Refraction at a ray's closest hit on an arbitrary triangle mesh (a surface swapped in for
// the learned water, engine/surface/mesh_surface.h), shared GLSL/C++ (see shared_prelude.glsl).
// Needs snell.glsl. The hit normal is the barycentric interpolation of the triangle's unit
// vertex normals, renormalised (docs/method.md §1.3), then flipped to face the ray.
#if defined(__cplusplus) || !defined(REFRAX_MESH_REFRACT_GLSL)
#ifndef __cplusplus
#define REFRAX_MESH_REFRACT_GLSL
#endif

// Normal at barycentrics (u, v) of corners 1 and 2, not yet oriented. Where the three
// normals cancel (opposite vertex normals, possible on a user's mesh) the interpolation has
// no direction: the triangle's face normal cross(P1 - P0, P2 - P0) is used instead, so the
// result stays finite for every triangle a ray can hit (one of non-zero area).
SHARED_FN real3 meshHitNormal(real u, real v, real3 N0, real3 N1, real3 N2, real3 faceNormal) {
  real3 m = (real(1) - u - v) * N0 + u * N1 + v * N2;
  if (!(length(m) > real(1e-6))) m = faceNormal;
  return normalize(m);
}

// Unit normal n facing the unit ray direction d, refracted direction w (eta = n_air / n_water);
// backFacing tells whether the normal had to be flipped.
SHARED_FN void meshHitRefract(real3 d, real u, real v, real3 N0, real3 N1, real3 N2, real3 faceNormal, real eta, OUT(real3) n,
                              OUT(real3) w, OUT(bool) backFacing) {
  n = meshHitNormal(u, v, N0, N1, N2, faceNormal);
  real s = snellFacingSign(d, n);
  backFacing = s < real(0);
  n = s * n;
  w = snellRefract(d, n, eta);
}

#endif
