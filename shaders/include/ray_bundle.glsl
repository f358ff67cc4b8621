// Culling for a bundle of rays (the tiled Gaussian forward, engine/gaussian/tiled_trace.h), shared
// GLSL/C++ (see shared_prelude.glsl).
//
// A bundle is described by an axis ray (origin, unit dir) and two radii: every point
// o_i + s d_i of a member ray (unit d_i, s in [sMin, sMax]) satisfies
//   |o_i + s d_i - (origin + s dir)| <= |o_i - origin| + s |d_i - dir| <= originRadius + s dirRadius,
// so the bundle lies inside a cone around the axis whose radius grows linearly with s. The
// camera rays of an 8x8 pixel tile (one origin, directions a fraction of a degree apart) and
// the same rays refracted at a water patch (origins a few millimetres apart) both give thin
// cones. Any point a member ray reaches lies in the cone: a sphere the cone misses is reached
// by no member ray.
#if defined(__cplusplus) || !defined(REFRAX_RAY_BUNDLE_GLSL)
#ifndef __cplusplus
#define REFRAX_RAY_BUNDLE_GLSL
#endif

// Whether some point of the cone may lie inside the sphere (centre, radius); conservative:
// false only when none can. The distance from the axis point at s to the centre minus the
// cone's radius there, f(s) = |p - s dir| - s dirRadius - originRadius (p = centre - origin),
// is convex in s, so its minimum over [sMin, sMax] is at the clamped stationary point
// s* = a + h dirRadius / sqrt(1 - dirRadius^2) (a, h: the centre's distance along and from
// the axis). A cone opening at 90 degrees or more (dirRadius >= 1) is never culled.
SHARED_FN bool bundleMayReachSphere(real3 origin, real3 dir, real originRadius, real dirRadius, real sMin, real sMax, real3 centre,
                                    real radius) {
  if (dirRadius >= real(1)) return true;
  real3 p = centre - origin;
  real a = dot(p, dir);
  real h = length(p - a * dir);  // not sqrt(|p|^2 - a^2), which cancels near the axis
  real s = clamp(a + h * dirRadius / sqrt(real(1) - dirRadius * dirRadius), sMin, sMax);
  real gap = length(p - s * dir) - s * dirRadius;
  // relative slack for rounding (the tracer's own test decides; this may only keep more)
  real slack = real(1e-4) * (length(p) + s + radius);
  return gap <= radius + originRadius + slack;
}

#endif
