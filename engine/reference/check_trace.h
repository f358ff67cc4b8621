#pragma once
// Compares GPU ray-query results with brute-force CPU double-precision references.
// Shared by the test suite and `refrax selftest`.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/trace/presort.h"
#include "engine/trace/rays.h"

namespace refrax::ref {

struct TriangleTraceReport {
  size_t rays = 0, cpuHits = 0, gpuHits = 0;
  size_t hitMissDisagree = 0;  // one hits, the other misses (excluding edge-ambiguous rays)
  size_t wrongTriangle = 0;    // both hit, different triangles, and the CPU's is not edge-ambiguous
  size_t edgeAmbiguous = 0;    // CPU hit within `edgeEps` (barycentric) of an edge: either answer is right
  double worstTRel = 0;        // max |t_gpu - t_cpu| / max(|t_cpu|, 1)
  double worstBary = 0;        // max |uv_gpu - uv_cpu| on rays hitting the same triangle
  // The same barycentric error as a distance: |du*(p1-p0) + dv*(p2-p0)| / max(t, 1). This is
  // the "relative" measure we hold to 1e-5: raw barycentrics of small triangles inherit the
  // float rounding of coordinates divided by the triangle's size.
  double worstBaryPoint = 0;
  std::string firstProblem;
  bool ok(double tol) const { return hitMissDisagree == 0 && wrongTriangle == 0 && worstTRel <= tol && worstBaryPoint <= tol; }
};

// `vertices` xyz, `indices` 3 per triangle (primitive index = triangle index).
TriangleTraceReport compareTriangleHits(const std::vector<float>& vertices, const std::vector<uint32_t>& indices,
                                        const std::vector<GpuRay>& rays, const std::vector<GpuTriangleHit>& gpu,
                                        double edgeEps = 1e-5);

struct CandidateReport {
  size_t rays = 0;
  size_t expectedPairs = 0;  // (ray, box) pairs the CPU slab test says overlap
  size_t missingPairs = 0;   // of those, not reported by the GPU (must be 0)
  size_t grazingPairs = 0;   // pairs that touch only within float reach of a face: either answer is right
  size_t overflowRays = 0;   // rays with more candidates than the capacity (not checkable)
  double meanCandidates = 0;
  std::string firstProblem;
};

// Boxes in the order submitted to the BLAS (primitive index = position in `boxes`). Every
// box the CPU slab test says a ray overlaps must be reported; a GPU may report more
// (BVH nodes are conservative), which is allowed. A ray that overlaps a box but misses it
// shrunk by `faceEps` (times the box's coordinate scale, at most half its extent) only grazes
// a face or an edge: a float slab test may decide that either way, so such pairs are counted
// as grazing, not expected.
CandidateReport compareCandidates(const std::vector<Box>& boxes, const std::vector<GpuRay>& rays,
                                  const std::vector<uint32_t>& counts, const std::vector<uint32_t>& candidates, uint32_t capacity,
                                  double faceEps = 1e-5);

}  // namespace refrax::ref
