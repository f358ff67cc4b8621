#pragma once
// CPU double-precision reference of the surface swap (engine/surface/mesh_surface.h,
// shaders/surface/mesh_refract.comp): brute-force closest triangle over the whole mesh, the same
// normal interpolation and Snell's law (shaders/include/mesh_refract.glsl in refrax::f64),
// and the comparison of GPU results with it.
//
// Ambiguity. A float ray query may rightly return another triangle than the double closest
// hit: one the ray passes within float reach of (a neighbour across a shared edge, a triangle
// the double test just misses), or one behind a closest hit that the ray itself only grazes.
// Reach is measured where ray-triangle tests decide, in the plane perpendicular to the ray:
// the signed distance of the ray from the triangle's projected edges (`edgeMargin`, positive
// inside); a triangle within `edgeEps` (relative to the scene's scale seen from the origin) is
// a candidate, one inside by more is solid. Along the ray, a hit is known to tReach(t) / s,
// s = |cos| between the ray and the triangle's plane (a grazing hit's t is ill-conditioned).
// The reference lists every candidate not beyond the first solid hit's reach (`acceptable`);
// a miss is acceptable only when no solid hit exists. A GPU result must match one of them.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/surface/gltf_surface.h"
#include "engine/trace/rays.h"

namespace refrax::ref {

struct MeshHitRef {
  uint32_t triangle = 0;
  double t = 0, u = 0, v = 0;  // distance along the unit direction, barycentrics of corners 1 and 2
  double edgeMargin = 0;       // signed distance of the ray from the projected edges (> 0 inside)
  double tReach = 0;           // how far along the ray a float tracer may place this hit
  double facing = 0;           // n.d before the flip (near 0: either orientation is right)
  bool backFacing = false;
  glm::dvec3 p{0}, n{0}, w{0};  // hit point, normal facing the ray, refracted direction
};

struct MeshRayRef {
  uint32_t flags = 0;  // of the closest hit: kSurfaceHit (| kSurfaceBackFacing), kSurfaceMissed or kSurfaceInvalidRay
  // The output ray in double: the refracted ray of the closest hit, the input ray on a miss,
  // the empty ray on invalid input.
  glm::dvec3 origin{0}, dir{0};
  double tmin = 0, tmax = 0;
  double rayTmax = 0;                  // the input's tmax along the unit direction (refracted tmax = rayTmax - t)
  std::vector<MeshHitRef> acceptable;  // hits a float tracer may return (closest solid hit first when there is one)
  bool missAcceptable = false;
  bool ambiguous() const { return acceptable.size() + (missAcceptable ? 1 : 0) > 1; }
};

struct MeshRefractOptions {
  double ior = 1.33;
  double edgeEps = 1e-5;  // reach of float triangle tests, relative to max(1, farthest vertex from the origin)
  double tRelEps = 1e-5;  // relative reach of float hit distances (of a hit square to the ray)
};

// `unitNormals` as the device holds them (meshUnitNormals in engine/surface/mesh_surface.h).
MeshRayRef refractThroughMeshRef(const SurfaceMesh& mesh, const std::vector<float>& unitNormals, const GpuRay& ray,
                                 const MeshRefractOptions& options = {});

// A reference ray as the GPU would store it (float).
GpuRay toGpuRay(const MeshRayRef& r);

struct MeshRefractReport {
  size_t rays = 0, hits = 0, misses = 0, invalid = 0, backFacing = 0;
  size_t ambiguous = 0;    // rays with more than one acceptable answer
  size_t mismatched = 0;   // GPU result matching no acceptable answer (flags, point, direction, range)
  size_t nonFinite = 0;    // GPU output with NaN/inf where the reference is finite (incl. poison left unwritten)
  size_t excused = 0;       // matched hits whose direction and facing were not compared (s < kGrazingS, or |n.d| < facingEps)
  size_t widened = 0;       // matched hits whose direction was off by more than dirTol: passed on the widened tolerance
  double worstPoint = 0;   // max |t_gpu - t_ref| s / max(t, 1) (or p's distance off the ray) over matched hits
  double worstDir = 0;     // max |w_gpu - w_ref at the GPU's point| over matched hits
  double worstTmax = 0;    // max |tmax_gpu - tmax_ref| / max(tmax_ref, 1) over matched hits
  std::string firstProblem;
};

// Below this |cos| between the ray and the triangle's plane the direction's tolerance stops
// widening (at 100 dirTol) and the hit's direction is not compared, only counted (see the .cpp).
constexpr double kGrazingS = 1e-4;

// A GPU hit p matches an acceptable hit when p lies on the ray to pointTol * max(t, 1), its
// distance along the ray is the reference's to pointTol * max(t, 1) / s (s as above: exact for
// a square hit, conditioned for a grazing one), tmax is the rest of the range to the same
// tolerance, and at p's barycentrics on that triangle the reference normal and Snell give
// the GPU's direction to dirTol (widened as 0.01 / s below s = 0.01, to at most 100 dirTol) and
// its back-facing flag (neither is compared where |n.d| < facingEps, the flip being a float
// decision there, nor where s < kGrazingS: counted in `excused`). Misses must be the input ray bit
// for bit, invalid rays the empty ray.
MeshRefractReport compareMeshRefraction(const SurfaceMesh& mesh, const std::vector<float>& unitNormals, const std::vector<GpuRay>& rays,
                                        const std::vector<GpuRay>& gpuRefracted, const std::vector<uint32_t>& gpuFlags,
                                        const MeshRefractOptions& options, double pointTol, double dirTol, double facingEps = 1e-5);

}  // namespace refrax::ref
