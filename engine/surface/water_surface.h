#pragma once
// The differentiable water surface (docs/method.md §1.2, 1.3, 1.5; paper Alg. 1): a proxy mesh
// lifted from a height field, one ray query per camera ray against it, K levels of
// recursive subdivision tracing, Phong-interpolated vertex normals, Snell's law; and the
// backward from dL/d(refracted ray) to dL/dheights and on to H's parameters.
//
// Per step:  cmdUpdateSurface (H at the coarse vertices, BLAS refit)
//            traceSurface     (refracted rays + per-ray records, H evaluated exactly once per
//                              unique new lattice point; one submission, each level's new
//                              points counted on the device and evaluated by an indirect
//                              dispatch, where the height source can run so; else K + 2
//                              submissions, each level's count read back in between)
//            cmdBackwardSurface (uses the records and lattice of the last traceSurface)
//
// The lattice points a trace evaluates stay in a cache until the heights change
// (cmdUpdateSurface): later traces of the same surface evaluate only the points it lacks.
// The backward can be split the same way: cmdBackwardSurfaceToHeights adds dL/dheight of
// each trace's rays into gridGrad and pointGrad (one entry per cached point), and
// cmdPushSurfaceGradients takes them into H's parameters once. Training sums the views of a
// surface batch this way and differentiates H once per surface step, over the union of
// their points, instead of once per view: the same sum, since H does not change in between.
// The lattice, its numbering, the normals and the child choice are described in
// shaders/include/surface_geometry.glsl.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "engine/height/height_source.h"
#include "engine/trace/rays.h"
#include "engine/surface/surface_record.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

struct SurfaceDomain {
  float x0 = -1, y0 = -1, x1 = 1, y1 = 1;
};

struct WaterSurfaceConfig {
  SurfaceDomain domain;
  uint32_t gridCells = 200;         // coarse cells per side (201 x 201 vertices)
  uint32_t subdivisionLevels = 2;   // K; 0 traces the coarse mesh only
  float ior = 1.33f;                // n_water (n_air = 1)
  bool faceNormals = false;         // flat face normals (ablation (b)) instead of interpolated vertex normals
  uint32_t maxRays = 392 * 392;     // the most rays one traceSurface call takes
  bool keepHitNormals = false;      // also write hit and vertex normals per ray (tests, viewer)
};

// What the last trace (and backward) counted.
struct SurfaceCounters {
  uint32_t points = 0;              // unique lattice points evaluated beyond the coarse grid
  uint32_t missed = 0;              // rays that missed the domain (continued unrefracted)
  uint32_t invalid = 0;             // NaN/inf or zero-length rays
  uint32_t fallback = 0;            // rays that kept a child by plane distance at some level
  uint32_t nonFiniteGradients = 0;  // rays whose incoming gradient was NaN/inf (skipped)
  uint32_t lookupFailures = 0;      // must stay 0
  uint32_t degenerate = 0;          // rays parallel to their triangle
  uint32_t backFacing = 0;          // rays whose normal had to be flipped
};

struct SurfacePipelines {
  ComputePipeline gridPoints, gridVertices, globalTrace, requestPoints, subdivide, refract, backward, compact, addGridGradient;
  ComputePipeline heightRange;  // compute trace backend: the proxy mesh's height range for the grid walk
  ComputePipeline pointRange, pointMove;  // the one-submission trace: a level's new points counted and moved on the device
};

struct WaterSurface {
  Context* ctx = nullptr;
  WaterSurfaceConfig config;
  uint32_t cellsX = 0, cellsY = 0;
  float spacingX = 0, spacingY = 0;  // finest-lattice spacing
  uint32_t gridPointCount = 0;       // (cellsX + 3) * (cellsY + 3): coarse vertices with a border ring

  Buffer gridPoints, gridHeights, gridGrad;  // coarse lattice incl. border: xy, H, dL/dH
  Buffer vertices, indices, cellOrder;       // the BLAS input (interior vertices), Morton cell order
  AccelStruct blas;                          // ray-query backend; the compute backend walks the grid's cells instead
  TopLevel top;
  Buffer heightRange;                        // compute backend: the vertices' lowest and highest z (ordered uints)

  // Lattice points beyond the coarse grid: latticeIndex (one uint per point of the bordered
  // finest lattice) gives each requested point its index into points/pointHeights/pointGrad.
  Buffer latticeIndex, points, pointHeights, pointGrad;
  Buffer evalPoints, evalHeights;  // one level's new points, handed to the height source
  Buffer pushPoints, pushGrads, pushCount;  // pushSurfaceGradients: the points with a gradient
  Buffer counters, hitNormals;
  // The one-submission trace: the range of a level's new points and its dispatches' group
  // counts (surface_point_range.comp), and the counters copied where the host reads them
  // without another submission.
  Buffer pointRange, countersReadback;
  uint32_t latticeStride = 0;  // (cellsX << K) + 3
  uint64_t latticePoints = 0;  // latticeStride * ((cellsY << K) + 3)
  uint32_t pointCapacity = 0;
  // Points in the cache (indices [0, cachedPoints) of points/pointHeights/pointGrad), all
  // evaluated at the current heights; 0 after cmdUpdateSurface.
  uint32_t cachedPoints = 0;
  bool cacheCleared = false;  // latticeIndex and the point count need clearing before the next trace
  // gridGrad/pointGrad hold dL/dheight that has not reached H's parameters yet
  // (cmdBackwardSurfaceToHeights since the last cmdPushSurfaceGradients).
  bool gradientPending = false;
  // addGridGradient: the scaled grid gradients the host wrote (host-visible, read by the shader
  // in place), added on the device at the head of the next submission that uses gridGrad;
  // addedStartsSum: gridGrad and pointGrad are cleared first (no gradient was pending).
  Buffer addedGrad;
  bool addedPending = false, addedStartsSum = false;
  uint64_t heightsVersion = 0;  // a new number (process-wide) at every cmdUpdateSurface

  SurfacePipelines pipelines;
  bool floatAtomics = false;  // the backward uses float atomicAdd (else a CAS loop)

  // State of the last traceSurface, used by cmdBackwardSurface.
  uint32_t lastRayCount = 0;
  SurfaceCounters lastCounters;
  bool updated = false;
};

// forceCasAtomics: use the compare-and-swap backward even where float atomics exist (tests).
WaterSurface createWaterSurface(Context& ctx, const WaterSurfaceConfig& config, bool forceCasAtomics = false);

// H at every coarse vertex, written into the BLAS vertices, BLAS/TLAS refit (built the first time).
void cmdUpdateSurface(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights);

// GPU milliseconds per stage of the last traceSurface (when asked for).
using SurfaceTimings = std::map<std::string, double>;

// Traces `count` camera rays (GpuRay) through the surface: refractedRays gets one GpuRay per
// ray (origin = hit point, direction = refracted; unchanged for rays that miss the domain;
// an empty ray for invalid input), records one SurfaceRecord per ray. Submits and waits:
// once where traceIsOneSubmission, else K + 2 times.
// Work recorded into the trace's first submission before the trace (what makes the rays) and
// into its last after it (what reads the refracted rays): a training step then submits no
// more often than the trace itself.
struct SurfaceTraceHooks {
  std::function<void(VkCommandBuffer)> before, after;
  // Where set, a one-submission trace (traceIsOneSubmission) hands its recording to `submit`
  // instead of submitting and waiting (a training step not waited for, issue 48): its counters
  // are not read, and the cache's count is taken at its bound (cachedPointsBoundAfterTrace)
  // until a trace that is waited for reads it again.
  std::function<void(const std::function<void(VkCommandBuffer)>&)> submit;
};
void traceSurface(Context& ctx, WaterSurface& ws, const HeightSource& heights, const Buffer& rays, uint32_t count,
                  Buffer& refractedRays, Buffer& records, SurfaceTimings* timings = nullptr, const SurfaceTraceHooks& hooks = {});

// From dLoss/d(refracted origin, direction) per ray (GpuRayGrad) to dLoss/dheight of every
// lattice point the last trace used (ws.gridGrad, ws.pointGrad), then through
// heights.accumulateGradients into H's parameters. Same rays/records/count as the trace.
// Equivalent to cmdBackwardSurfaceToHeights then cmdPushSurfaceGradients.
void cmdBackwardSurface(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights, const Buffer& rays, const Buffer& records,
                        const Buffer& rayGrads, uint32_t count);
// The first half: adds the last trace's dLoss/dheight into ws.gridGrad and ws.pointGrad (which
// are cleared first when no gradient is pending) and marks them pending.
void cmdBackwardSurfaceToHeights(VkCommandBuffer cb, WaterSurface& ws, const Buffer& rays, const Buffer& records, const Buffer& rayGrads,
                                 uint32_t count);
// The second half: the pending dLoss/dheight (coarse grid and every cached point) through
// heights.accumulateGradients into H's parameters; gridGrad/pointGrad keep their values
// (for tests and the flat plane) until the next backward starts a new sum.
void cmdPushSurfaceGradients(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights);
// cmdPushSurfaceGradients over only the points whose pending gradient is not zero, listed on
// the device first. The same sum in another order. One submission where heights.accumulateQueued
// runs on the count the device wrote; else the count is read back and the push is a second.
// `then` (the optimiser's step, say) is recorded into the last submission, after the push.
void pushSurfaceGradients(Context& ctx, WaterSurface& ws, const HeightSource& heights,
                          const std::function<void(VkCommandBuffer)>& then = {});
// pushSurfaceGradients' parts, for a push recorded into a submission of its own caller's (a
// training step's, after its backward; issue 48). Records the listing of the pending gradient
// (the coarse grid and the first `cachedBound` cache slots: any bound at or over the cache's
// count, which a trace in the same submission may still raise) and, where the source can run
// on the count the device wrote, the push; returns whether it recorded the push. Where it did
// not, pushListedSurfaceGradients after the submission's wait reads the count and pushes, with
// `then`, in a second submission.
bool cmdListAndPushSurfaceGradients(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights, uint32_t cachedBound);
void pushListedSurfaceGradients(Context& ctx, WaterSurface& ws, const HeightSource& heights, const std::function<void(VkCommandBuffer)>& then = {});
// The most points the cache may hold after a trace of `rays` rays: a bound for
// cmdListAndPushSurfaceGradients recorded after that trace.
uint32_t cachedPointsBoundAfterTrace(const WaterSurface& ws, uint32_t rays);
// Adds scale * g (one value per coarse grid slot, gridPointCount) to the pending dL/dheight
// (a prior's gradient), starting a new sum when none is pending. No submission of its own: g is
// written where the device reads it, and the add is recorded at the head of the next backward
// or push (cmdApplyAddedGradient); a second call before then adds to the first's.
void addGridGradient(Context& ctx, WaterSurface& ws, const std::vector<float>& g, double scale);
// Records the add addGridGradient left pending (nothing when none is).
void cmdApplyAddedGradient(VkCommandBuffer cb, WaterSurface& ws);
// Whether traceSurface of `rays` rays runs as one submission: the source evaluates heights on a
// count the device wrote (HeightSource::evaluateQueued), and every level's new points fit one
// dispatch of the device's group-count limit.
bool traceIsOneSubmission(const WaterSurface& ws, const HeightSource& heights, uint32_t rays);
// Whether a trace of `rays` rays fits the point cache as it is (else the trace empties the
// cache first, which needs no gradient to be pending).
bool surfaceCacheHasRoom(const WaterSurface& ws, uint32_t rays);

// Counters of the last trace and backward (reads them back; waits for nothing else).
SurfaceCounters readSurfaceCounters(Context& ctx, WaterSurface& ws);
inline uint32_t missedRayCount(Context& ctx, WaterSurface& ws) { return readSurfaceCounters(ctx, ws).missed; }

}  // namespace refrax
