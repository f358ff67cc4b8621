#include "engine/reference/mesh_refract_ref.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "engine/surface/surface_math.h"
#include "engine/surface/surface_record.h"

namespace refrax::ref {

namespace {

using glm::dvec3;

dvec3 at(const std::vector<float>& v, uint32_t i) { return dvec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]); }

double tReach(double t, const MeshRefractOptions& o) { return o.tRelEps * std::max(std::fabs(t), 1.0); }

bool finiteRay(const GpuRay& r) {
  for (int a = 0; a < 3; a++)
    if (!std::isfinite(r.origin[a]) || !std::isfinite(r.dir[a])) return false;
  return std::isfinite(r.tmin) && std::isfinite(r.tmax);
}

bool sameBits(const GpuRay& a, const GpuRay& b) { return std::memcmp(&a, &b, sizeof(GpuRay)) == 0; }

}  // namespace

MeshRayRef refractThroughMeshRef(const SurfaceMesh& mesh, const std::vector<float>& unitNormals, const GpuRay& ray,
                                 const MeshRefractOptions& opt) {
  MeshRayRef out;
  // As the shader's ray load: unit direction, tmin/tmax rescaled to it.
  dvec3 o(ray.origin[0], ray.origin[1], ray.origin[2]), d(ray.dir[0], ray.dir[1], ray.dir[2]);
  double len = glm::length(d);
  double tmin = double(ray.tmin) * len, tmax = double(ray.tmax) * len;
  if (!finiteRay(ray) || !(len > 0) || !(tmin >= 0) || !(tmax >= tmin)) {
    out.flags = kSurfaceInvalidRay;
    out.dir = dvec3(0, 0, -1);
    return out;
  }
  d /= len;
  out.rayTmax = tmax;
  const double eta = 1.0 / opt.ior;
  // The plane perpendicular to the ray, where the ray is the point (0, 0).
  dvec3 axis = std::fabs(d.x) < std::fabs(d.y) ? (std::fabs(d.x) < std::fabs(d.z) ? dvec3(1, 0, 0) : dvec3(0, 0, 1))
                                               : (std::fabs(d.y) < std::fabs(d.z) ? dvec3(0, 1, 0) : dvec3(0, 0, 1));
  dvec3 e1 = glm::normalize(glm::cross(d, axis)), e2 = glm::cross(d, e1);
  std::vector<MeshHitRef> near;  // candidates: within reach of the ray, and of [tmin, tmax]
  double tSolid = std::numeric_limits<double>::infinity();
  int closest = -1;
  for (uint32_t k = 0; k < mesh.triangleCount(); k++) {
    uint32_t i0 = mesh.indices[3 * k], i1 = mesh.indices[3 * k + 1], i2 = mesh.indices[3 * k + 2];
    dvec3 P[3] = {at(mesh.positions, i0), at(mesh.positions, i1), at(mesh.positions, i2)};
    dvec3 tuv;
    if (!f64::rayTrianglePlane(o, d, P[0], P[1], P[2], 0.0, tuv)) continue;  // seen edge-on
    glm::dvec2 q[3];
    double scale = 1;
    for (int c = 0; c < 3; c++) {
      q[c] = glm::dvec2(glm::dot(P[c] - o, e1), glm::dot(P[c] - o, e2));
      scale = std::max(scale, glm::length(P[c] - o));
    }
    double area = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[1].y - q[0].y) * (q[2].x - q[0].x);
    if (area == 0) continue;
    MeshHitRef h;
    h.edgeMargin = std::numeric_limits<double>::infinity();
    for (int c = 0; c < 3; c++) {
      glm::dvec2 a = q[c], e = q[(c + 1) % 3] - q[c];
      double el = glm::length(e);
      if (el == 0) continue;
      h.edgeMargin = std::min(h.edgeMargin, (area > 0 ? 1.0 : -1.0) * (e.x * -a.y - e.y * -a.x) / el);
    }
    const double reach2d = opt.edgeEps * scale;
    if (!(h.edgeMargin > -reach2d)) continue;
    h.triangle = k;
    h.t = tuv.x;
    h.u = tuv.y;
    h.v = tuv.z;
    dvec3 face = glm::cross(P[1] - P[0], P[2] - P[0]);
    double s = std::fabs(glm::dot(glm::normalize(face), d));
    h.tReach = tReach(h.t, opt) / std::max(s, 1e-12);
    if (h.t + h.tReach < tmin || h.t - h.tReach > tmax) continue;
    h.p = o + h.t * d;
    dvec3 N0 = at(unitNormals, i0), N1 = at(unitNormals, i1), N2 = at(unitNormals, i2);
    h.facing = glm::dot(f64::meshHitNormal(h.u, h.v, N0, N1, N2, face), d);
    f64::meshHitRefract(d, h.u, h.v, N0, N1, N2, face, eta, h.n, h.w, h.backFacing);
    if (h.edgeMargin >= reach2d && h.t - h.tReach >= tmin && h.t + h.tReach <= tmax) tSolid = std::min(tSolid, h.t + h.tReach);
    if (h.edgeMargin >= 0 && h.t >= tmin && h.t <= tmax && (closest < 0 || h.t < near[size_t(closest)].t)) closest = int(near.size());
    near.push_back(h);
  }
  if (closest >= 0) {
    const MeshHitRef& c = near[size_t(closest)];
    out.flags = kSurfaceHit | (c.backFacing ? kSurfaceBackFacing : 0u);
    out.origin = c.p;
    out.dir = c.w;
    out.tmin = 0;
    out.tmax = std::max(tmax - c.t, 0.0);
  } else {
    out.flags = kSurfaceMissed;
    out.origin = dvec3(ray.origin[0], ray.origin[1], ray.origin[2]);
    out.dir = dvec3(ray.dir[0], ray.dir[1], ray.dir[2]);
    out.tmin = ray.tmin;
    out.tmax = ray.tmax;
  }
  out.missAcceptable = std::isinf(tSolid);
  for (const MeshHitRef& h : near)
    if (h.t - h.tReach <= tSolid) out.acceptable.push_back(h);
  std::sort(out.acceptable.begin(), out.acceptable.end(), [](const MeshHitRef& a, const MeshHitRef& b) { return a.t < b.t; });
  return out;
}

GpuRay toGpuRay(const MeshRayRef& r) {
  GpuRay g;
  for (int a = 0; a < 3; a++) {
    g.origin[a] = float(r.origin[a]);
    g.dir[a] = float(r.dir[a]);
  }
  g.tmin = float(r.tmin);
  g.tmax = float(r.tmax);
  return g;
}

namespace {

// The GPU's hit against the reference's acceptable hits: the best match within the
// tolerances (the lowest combined error), or none.
struct GpuHitMatch {
  bool matched = false, excused = false, widened = false;
  double point = 0, dir = 0, tmax = 0;  // the match's errors
  dvec3 p{0}, w{0};                     // the GPU's refracted origin and direction
};
GpuHitMatch matchGpuHit(const SurfaceMesh& mesh, const std::vector<float>& unitNormals, const GpuRay& ray, const GpuRay& g, uint32_t flags,
                        const MeshRayRef& r, const MeshRefractOptions& opt, double pointTol, double dirTol, double facingEps) {
  dvec3 p(g.origin[0], g.origin[1], g.origin[2]), w(g.dir[0], g.dir[1], g.dir[2]);
  dvec3 o(ray.origin[0], ray.origin[1], ray.origin[2]), d = glm::normalize(dvec3(ray.dir[0], ray.dir[1], ray.dir[2]));
  double tg = glm::dot(p - o, d);  // the GPU's hit distance
  double offRay = glm::length(p - (o + tg * d)) / std::max(std::fabs(tg), 1.0);
  GpuHitMatch best;
  best.p = p, best.w = w;
  double bestScore = std::numeric_limits<double>::infinity();
  for (const MeshHitRef& h : r.acceptable) {
    // The reference at the GPU's point: its barycentrics on h's triangle (orthogonal projection).
    dvec3 P[3];
    for (int c = 0; c < 3; c++) P[c] = at(mesh.positions, mesh.indices[3 * h.triangle + c]);
    dvec3 face = glm::cross(P[1] - P[0], P[2] - P[0]), nf = glm::normalize(face);
    double s = std::fabs(glm::dot(nf, d));
    dvec3 onPlane = p - glm::dot(p - P[0], nf) * nf, tuv;
    f64::rayTrianglePlane(onPlane + nf, -nf, P[0], P[1], P[2], 0.0, tuv);
    dvec3 N[3];
    for (int c = 0; c < 3; c++) N[c] = at(unitNormals, mesh.indices[3 * h.triangle + c]);
    dvec3 n, wRef;
    bool backFacing;
    f64::meshHitRefract(d, tuv.y, tuv.z, N[0], N[1], N[2], face, 1.0 / opt.ior, n, wRef, backFacing);
    double facing = glm::dot(f64::meshHitNormal(tuv.y, tuv.z, N[0], N[1], N[2], face), d);
    double ep = std::fabs(tg - h.t) * std::max(s, 1e-12) / std::max(h.t, 1.0);  // |dt| relative to its conditioning
    double refTmax = std::max(r.rayTmax - tg, 0.0);
    double et = std::fabs(double(g.tmax) - refTmax) / std::max(refTmax, 1.0);
    // A ray nearly in the triangle's plane (s small) gets its barycentrics, and so its
    // interpolated normal, from a determinant proportional to s: in float they are good to
    // about eps |o - P0| / (s L) (L the triangle's size, o the origin the test runs from), and
    // the direction to that times how fast the normals turn across the triangle. With the
    // tests' meshes (|o - P0| up to ~0.3 from the box entry, L ~ 0.1, normals turning ~0.5
    // across a triangle) that is about 1e-7 / s: dirTol (1e-5) down to s = 0.01 (0.6
    // degrees), widening as 0.01 / s below it. The widening stops at s = kGrazingS, where the
    // tolerance has reached 100 dirTol (1e-3): below it no float tracer's direction is good
    // to any bound that would still catch an error, so such hits are excused from the
    // direction and facing comparison (their point and range still are compared) and
    // counted (MeshRefractReport::excused), for a caller to bound their share. So are hits
    // whose interpolated normal is within facingEps of the ray's plane (the flip is a float
    // decision there). Seen: s = 9e-4, |dw| 1.2e-5 on the compute backend's walk (seed 4092548225).
    const bool grazing = std::fabs(facing) < facingEps || s < kGrazingS;
    double ew = grazing ? 0.0 : glm::length(w - wRef);
    bool flagOk = grazing || ((flags & kSurfaceBackFacing) != 0) == backFacing;
    const double wTol = dirTol * std::max(1.0, 0.01 / std::max(s, kGrazingS));
    if (offRay <= pointTol && ep <= pointTol && et <= pointTol && ew <= wTol && flagOk) {
      double score = ep / pointTol + ew / wTol;
      if (score < bestScore) {
        bestScore = score;
        best.point = std::max(ep, offRay), best.dir = ew, best.tmax = et;
        best.excused = grazing;
        best.widened = ew > dirTol;
        best.matched = true;
      }
    }
  }
  return best;
}

}  // namespace

MeshRefractReport compareMeshRefraction(const SurfaceMesh& mesh, const std::vector<float>& unitNormals, const std::vector<GpuRay>& rays,
                                        const std::vector<GpuRay>& gpuRefracted, const std::vector<uint32_t>& gpuFlags,
                                        const MeshRefractOptions& opt, double pointTol, double dirTol, double facingEps) {
  MeshRefractReport rep;
  rep.rays = rays.size();
  auto problem = [&](size_t i, const std::string& what) {
    rep.mismatched++;
    if (rep.firstProblem.empty()) rep.firstProblem = "ray " + std::to_string(i) + ": " + what;
  };
  for (size_t i = 0; i < rays.size(); i++) {
    MeshRayRef r = refractThroughMeshRef(mesh, unitNormals, rays[i], opt);
    const GpuRay& g = gpuRefracted[i];
    const uint32_t flags = gpuFlags[i];
    rep.ambiguous += r.ambiguous();
    if (r.flags == kSurfaceInvalidRay) {
      rep.invalid++;
      GpuRay empty{{0, 0, 0}, 0, {0, 0, -1}, 0};
      if (flags != kSurfaceInvalidRay || !sameBits(g, empty)) problem(i, "invalid input, but not the empty ray and flag");
      continue;
    }
    if (!finiteRay(g)) {
      rep.nonFinite++;
      problem(i, "non-finite output (flags " + std::to_string(flags) + ")");
      continue;
    }
    if (flags == kSurfaceMissed) {
      rep.misses++;
      if (!r.missAcceptable) problem(i, "GPU missed; the reference hits triangle " + std::to_string(r.acceptable.front().triangle));
      else if (!sameBits(g, rays[i])) problem(i, "a missed ray was not copied unchanged");
      continue;
    }
    if ((flags & ~kSurfaceBackFacing) != kSurfaceHit) {
      problem(i, "unexpected flags " + std::to_string(flags));
      continue;
    }
    rep.hits++;
    rep.backFacing += (flags & kSurfaceBackFacing) != 0;
    if (g.tmin != 0.0f) {
      problem(i, "a refracted ray with tmin " + std::to_string(g.tmin));
      continue;
    }
    const GpuHitMatch m = matchGpuHit(mesh, unitNormals, rays[i], g, flags, r, opt, pointTol, dirTol, facingEps);
    const dvec3& p = m.p;
    const dvec3& w = m.w;
    if (!m.matched) {
      std::string what = "GPU hit matches none of " + std::to_string(r.acceptable.size()) + " acceptable hits";
      if (!r.acceptable.empty()) {
        const MeshHitRef& h = r.acceptable.front();
        what += " (nearest: triangle " + std::to_string(h.triangle) + ", |dp| " + std::to_string(glm::length(p - h.p)) + ", |dw| " +
                std::to_string(glm::length(w - h.w)) + ", back-facing " + std::to_string(h.backFacing) + " vs flags " +
                std::to_string(flags) + ")";
      }
      problem(i, what);
      continue;
    }
    rep.excused += m.excused;
    rep.widened += m.widened;
    rep.worstPoint = std::max(rep.worstPoint, m.point);
    rep.worstDir = std::max(rep.worstDir, m.dir);
    rep.worstTmax = std::max(rep.worstTmax, m.tmax);
  }
  return rep;
}

}  // namespace refrax::ref
