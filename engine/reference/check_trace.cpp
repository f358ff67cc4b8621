#include "engine/reference/check_trace.h"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "engine/reference/ray_intersect.h"

namespace refrax::ref {

namespace {
glm::dvec3 vertexAt(const std::vector<float>& v, uint32_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }
glm::dvec3 originOf(const GpuRay& r) { return {r.origin[0], r.origin[1], r.origin[2]}; }
glm::dvec3 dirOf(const GpuRay& r) { return {r.dir[0], r.dir[1], r.dir[2]}; }

// The box pulled in by eps times its coordinate scale on every side, never past its centre.
void shrunkBox(const Box& x, double eps, glm::dvec3& lo, glm::dvec3& hi) {
  lo = {x.minX, x.minY, x.minZ};
  hi = {x.maxX, x.maxY, x.maxZ};
  double scale = std::max({1.0, glm::length(lo), glm::length(hi)});
  for (int a = 0; a < 3; a++) {
    double in = std::min(eps * scale, 0.5 * (hi[a] - lo[a]));
    lo[a] += in;
    hi[a] -= in;
  }
}
}  // namespace

TriangleTraceReport compareTriangleHits(const std::vector<float>& vertices, const std::vector<uint32_t>& indices,
                                        const std::vector<GpuRay>& rays, const std::vector<GpuTriangleHit>& gpu, double edgeEps) {
  TriangleTraceReport rep;
  rep.rays = rays.size();
  const size_t nt = indices.size() / 3;
  for (size_t r = 0; r < rays.size(); r++) {
    glm::dvec3 o = originOf(rays[r]), d = dirOf(rays[r]);
    TriangleHitD best;
    size_t bestTri = 0;
    for (size_t k = 0; k < nt; k++) {
      TriangleHitD h = intersectTriangle(o, d, vertexAt(vertices, indices[3 * k]), vertexAt(vertices, indices[3 * k + 1]),
                                         vertexAt(vertices, indices[3 * k + 2]), rays[r].tmin, rays[r].tmax);
      if (h.hit && (!best.hit || h.t < best.t)) {
        best = h;
        bestTri = k;
      }
    }
    const GpuTriangleHit& g = gpu[r];
    bool gpuHit = g.primitive != kNoHit;
    rep.cpuHits += best.hit;
    rep.gpuHits += gpuHit;
    bool ambiguous = best.hit && std::min({best.u, best.v, 1.0 - best.u - best.v}) < edgeEps;
    if (!best.hit && gpuHit && g.primitive < nt) {  // a GPU hit within float reach of an outer edge
      double u, v;
      uint32_t k = g.primitive;
      if (planeBarycentrics(o, d, vertexAt(vertices, indices[3 * k]), vertexAt(vertices, indices[3 * k + 1]),
                            vertexAt(vertices, indices[3 * k + 2]), u, v))
        ambiguous = std::min({u, v, 1.0 - u - v}) > -edgeEps;
    }
    rep.edgeAmbiguous += ambiguous;
    if (best.hit != gpuHit) {
      if (!ambiguous) {
        rep.hitMissDisagree++;
        if (rep.firstProblem.empty())
          rep.firstProblem = "ray " + std::to_string(r) + ": cpu " + (best.hit ? "hit" : "miss") + ", gpu " + (gpuHit ? "hit" : "miss");
      }
      continue;
    }
    if (!best.hit) continue;
    rep.worstTRel = std::max(rep.worstTRel, std::fabs(g.t - best.t) / std::max(std::fabs(best.t), 1.0));
    if (g.primitive != bestTri) {
      if (!ambiguous) {
        rep.wrongTriangle++;
        if (rep.firstProblem.empty())
          rep.firstProblem = "ray " + std::to_string(r) + ": cpu triangle " + std::to_string(bestTri) + ", gpu " +
                             std::to_string(g.primitive);
      }
      continue;
    }
    rep.worstBary = std::max({rep.worstBary, std::fabs(g.u - best.u), std::fabs(g.v - best.v)});
    glm::dvec3 p0 = vertexAt(vertices, indices[3 * bestTri]);
    glm::dvec3 shift = (g.u - best.u) * (vertexAt(vertices, indices[3 * bestTri + 1]) - p0) +
                       (g.v - best.v) * (vertexAt(vertices, indices[3 * bestTri + 2]) - p0);
    rep.worstBaryPoint = std::max(rep.worstBaryPoint, glm::length(shift) / std::max(std::fabs(best.t), 1.0));
  }
  return rep;
}

CandidateReport compareCandidates(const std::vector<Box>& boxes, const std::vector<GpuRay>& rays,
                                  const std::vector<uint32_t>& counts, const std::vector<uint32_t>& candidates, uint32_t capacity,
                                  double faceEps) {
  CandidateReport rep;
  rep.rays = rays.size();
  double total = 0;
  for (size_t r = 0; r < rays.size(); r++) {
    total += counts[r];
    if (counts[r] > capacity) {
      rep.overflowRays++;
      continue;
    }
    std::vector<uint32_t> got(candidates.begin() + r * capacity, candidates.begin() + r * capacity + counts[r]);
    std::sort(got.begin(), got.end());
    glm::dvec3 o = originOf(rays[r]), d = dirOf(rays[r]);
    for (size_t b = 0; b < boxes.size(); b++) {
      const Box& x = boxes[b];
      if (!overlapsBox(o, d, {x.minX, x.minY, x.minZ}, {x.maxX, x.maxY, x.maxZ}, rays[r].tmin, rays[r].tmax)) continue;
      glm::dvec3 lo, hi;
      shrunkBox(x, faceEps, lo, hi);
      if (!overlapsBox(o, d, lo, hi, rays[r].tmin, rays[r].tmax)) {
        rep.grazingPairs++;
        continue;
      }
      rep.expectedPairs++;
      if (!std::binary_search(got.begin(), got.end(), uint32_t(b))) {
        rep.missingPairs++;
        if (rep.firstProblem.empty())
          rep.firstProblem = "ray " + std::to_string(r) + " overlaps box " + std::to_string(b) + " but the GPU did not report it";
      }
    }
  }
  rep.meanCandidates = rays.empty() ? 0 : total / double(rays.size());
  return rep;
}

}  // namespace refrax::ref
