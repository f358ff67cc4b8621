#include "engine/surface/water_surface.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include "engine/base/error.h"
#include "engine/surface/grid_mesh.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"
#include "engine/vk/vk_timer.h"

namespace refrax {

namespace {

// Mirror of the push block in shaders/include/surface_lattice.glsl.
struct SurfacePush {
  float origin[2];
  float spacing[2];
  int32_t cellsX, cellsY, levels;
  uint32_t latticeStride;
  uint32_t count;
  int32_t level;
  float eta;
  uint32_t options;
  uint32_t pointCapacity;
  uint32_t mode;
  uint32_t pad0, pad1;
};
static_assert(sizeof(SurfacePush) == 64, "SurfacePush must match the GLSL push block");

constexpr uint32_t kOptionFaceNormals = 1u;
constexpr uint32_t kOptionHitNormals = 2u;
constexpr uint32_t kCounterCount = 8;
// surface_point_range.comp's output: the range, then two VkDispatchIndirectCommands.
constexpr uint32_t kPointRangeWords = 12;
constexpr VkDeviceSize kMoveGroupsOffset = 16, kHeightGroupsOffset = 32;

SurfaceCounters countersFrom(const uint32_t* c) {
  SurfaceCounters s;
  s.points = c[0];
  s.missed = c[1];
  s.invalid = c[2];
  s.fallback = c[3];
  s.nonFiniteGradients = c[4];
  s.lookupFailures = c[5];
  s.degenerate = c[6];
  s.backFacing = c[7];
  return s;
}

// Points one ray can ask for: 3 edge midpoints per level, then its finest triangle's 3
// corners with their 6 neighbours each.
uint32_t insertsPerRay(uint32_t levels) { return levels == 0 ? 0 : 3 * levels + 21; }

SurfacePush basePush(const WaterSurface& ws) {
  SurfacePush p{};
  p.origin[0] = ws.config.domain.x0;
  p.origin[1] = ws.config.domain.y0;
  p.spacing[0] = ws.spacingX;
  p.spacing[1] = ws.spacingY;
  p.cellsX = int32_t(ws.cellsX);
  p.cellsY = int32_t(ws.cellsY);
  p.levels = int32_t(ws.config.subdivisionLevels);
  p.eta = 1.0f / ws.config.ior;
  p.options = (ws.config.faceNormals ? kOptionFaceNormals : 0u) | (ws.config.keepHitNormals ? kOptionHitNormals : 0u);
  p.pointCapacity = ws.pointCapacity;
  p.latticeStride = ws.latticeStride;
  return p;
}

void checkBuffer(const Buffer& b, VkDeviceSize bytes, const char* what) {
  if (!b || b.size < bytes)
    fail(std::string("water surface: the ") + what + " buffer holds " + std::to_string(b ? b.size : 0) + " bytes, " +
         std::to_string(bytes) + " needed");
}

}  // namespace

WaterSurface createWaterSurface(Context& ctx, const WaterSurfaceConfig& config, bool forceCasAtomics) {
  const SurfaceDomain& d = config.domain;
  if (!std::isfinite(d.x0) || !std::isfinite(d.y0) || !std::isfinite(d.x1) || !std::isfinite(d.y1) || !(d.x1 > d.x0) ||
      !(d.y1 > d.y0))
    fail("water surface domain [" + std::to_string(d.x0) + ", " + std::to_string(d.x1) + "] x [" + std::to_string(d.y0) + ", " +
         std::to_string(d.y1) + "] is empty or inverted");
  if (config.gridCells == 0) fail("water surface needs at least one grid cell");
  if (config.subdivisionLevels > 12) fail("water surface subdivision levels must be at most 12");
  if ((uint64_t(config.gridCells) << config.subdivisionLevels) + 3 >= 65535)
    fail("water surface: grid cells x 2^levels must stay below 65532 (the finest lattice is addressed with 16 bits)");
  if (!(config.ior > 0.0f) || !std::isfinite(config.ior)) fail("water surface IOR must be a positive number");
  if (config.maxRays == 0) fail("water surface maxRays must be positive");

  WaterSurface ws;
  ws.ctx = &ctx;
  ws.config = config;
  ws.cellsX = ws.cellsY = config.gridCells;
  const uint32_t K = config.subdivisionLevels;
  ws.spacingX = (d.x1 - d.x0) / float(ws.cellsX << K);
  ws.spacingY = (d.y1 - d.y0) / float(ws.cellsY << K);
  ws.gridPointCount = (ws.cellsX + 3) * (ws.cellsY + 3);

  ws.gridPoints = createBuffer(ctx, VkDeviceSize(ws.gridPointCount) * 8);
  ws.gridHeights = createBuffer(ctx, VkDeviceSize(ws.gridPointCount) * 4);
  ws.gridGrad = createBuffer(ctx, VkDeviceSize(ws.gridPointCount) * 4);

  // Topology from the grid mesh (Morton cell order); xy and z are written on the GPU.
  GridMesh mesh = makeGridMesh(ws.cellsX, ws.cellsY, d.x0, d.y0, d.x1, d.y1);
  ws.vertices = createBufferFrom(ctx, mesh.vertices, kAccelInput);
  ws.indices = createBufferFrom(ctx, mesh.indices, kAccelInput);
  ws.cellOrder = createBufferFrom(ctx, mesh.cellOrder);
  const bool compute = ctx.trace == TraceBackend::Compute;
  if (compute) {
    ws.heightRange = createBuffer(ctx, 8);
  } else {
    ws.blas = createTriangleBlas(ctx, ws.vertices, mesh.vertexCount(), 12, ws.indices, mesh.triangleCount(), {true});
    ws.top = createTopLevel(ctx, {makeInstance(ws.blas, 0)}, {true});
  }

  ws.latticeStride = (ws.cellsX << K) + 3;
  ws.latticePoints = uint64_t(ws.latticeStride) * uint64_t((ws.cellsY << K) + 3);
  if (K > 0 && ws.latticePoints > (uint64_t(1) << 27))
    fail("water surface: the finest lattice ((cells << levels) + 3)^2 = " + std::to_string(ws.latticePoints) +
         " points exceeds 2^27; use fewer cells or levels");
  // Room for one trace of maxRays rays, and for the whole lattice where that is no more than
  // 4M points (112 MB of tables): the cache then never has to be emptied within a surface step.
  uint64_t inserts = std::min<uint64_t>(std::max<uint64_t>(uint64_t(config.maxRays) * insertsPerRay(K), uint64_t(1) << 22), ws.latticePoints);
  ws.pointCapacity = uint32_t(std::max<uint64_t>(inserts, 1));
  ws.latticeIndex = createBuffer(ctx, K > 0 ? ws.latticePoints * 4 : 4);
  ws.points = createBuffer(ctx, VkDeviceSize(ws.pointCapacity) * 8);
  ws.pointHeights = createBuffer(ctx, VkDeviceSize(ws.pointCapacity) * 4);
  ws.pointGrad = createBuffer(ctx, VkDeviceSize(ws.pointCapacity) * 4);
  ws.evalPoints = createBuffer(ctx, VkDeviceSize(ws.pointCapacity) * 8);
  ws.evalHeights = createBuffer(ctx, VkDeviceSize(ws.pointCapacity) * 4);
  ws.counters = createBuffer(ctx, kCounterCount * 4);
  ws.countersReadback = createBuffer(ctx, kCounterCount * 4, 0, MemoryUse::Readback);
  ws.pointRange = createBuffer(ctx, kPointRangeWords * 4, kIndirectArgs);
  ws.pushPoints = createBuffer(ctx, (VkDeviceSize(ws.gridPointCount) + ws.pointCapacity) * 8);
  ws.pushGrads = createBuffer(ctx, (VkDeviceSize(ws.gridPointCount) + ws.pointCapacity) * 4);
  ws.pushCount = createBuffer(ctx, 4);
  ws.hitNormals = createBuffer(ctx, config.keepHitNormals ? VkDeviceSize(config.maxRays) * 64 : 64);

  SurfacePipelines& p = ws.pipelines;
  const uint32_t push = sizeof(SurfacePush);
  auto B = kStorageBuffer;
  p.gridPoints = createComputePipeline(ctx, "surface_grid_points", {B}, push);
  p.gridVertices = createComputePipeline(ctx, "surface_grid_vertices", {B, B}, push);
  if (compute) {
    p.globalTrace = createComputePipeline(ctx, "surface_global_trace_compute", {B, B, B, B, B, B}, push);
    p.heightRange = createComputePipeline(ctx, "surface_height_range", {B, B}, 4);
  } else {
    p.globalTrace = createComputePipeline(ctx, "surface_global_trace", {kAccelStruct, B, B, B, B}, push);
  }
  p.requestPoints = createComputePipeline(ctx, "surface_request_points", {B, B, B, B}, push);
  p.subdivide = createComputePipeline(ctx, "surface_subdivide", {B, B, B, B, B, B}, push);
  p.refract = createComputePipeline(ctx, "surface_refract", {B, B, B, B, B, B, B, B}, push);
  ws.floatAtomics = ctx.caps.floatAtomicAdd && !forceCasAtomics;
  p.backward = createComputePipeline(ctx, ws.floatAtomics ? "surface_backward" : "surface_backward_cas", {B, B, B, B, B, B, B, B, B}, push);
  p.compact = createComputePipeline(ctx, "surface_compact_gradients", {B, B, B, B, B}, 4);
  p.addGridGradient = createComputePipeline(ctx, "surface_add_grid_gradient", {B, B}, 4);
  p.pointRange = createComputePipeline(ctx, "surface_point_range", {B, B}, 8);
  p.pointMove = createComputePipeline(ctx, "surface_point_move", {B, B, B, B, B}, 4);

  SurfacePush pc = basePush(ws);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdDispatch(cb, p.gridPoints, {bind(ws.gridPoints)}, &pc, groupsFor(ws.gridPointCount, 64));
    vkCmdFillBuffer(cb, ws.counters.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cb, ws.latticeIndex.buffer, 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  });
  return ws;
}

namespace {
// Empties the point cache: every lattice point unrequested, none counted.
void cmdClearPointCache(VkCommandBuffer cb, WaterSurface& ws) {
  vkCmdFillBuffer(cb, ws.latticeIndex.buffer, 0, VK_WHOLE_SIZE, 0xFFFFFFFFu);
  vkCmdFillBuffer(cb, ws.counters.buffer, 0, 4, 0);
  ws.cachedPoints = 0;
}
}  // namespace

uint32_t cachedPointsBoundAfterTrace(const WaterSurface& ws, uint32_t rays) {
  return uint32_t(std::min<uint64_t>(ws.pointCapacity, uint64_t(ws.cachedPoints) + uint64_t(rays) * insertsPerRay(ws.config.subdivisionLevels)));
}

bool surfaceCacheHasRoom(const WaterSurface& ws, uint32_t rays) {
  // A table the size of the lattice holds every point there is.
  return ws.pointCapacity >= ws.latticePoints ||
         uint64_t(ws.cachedPoints) + uint64_t(rays) * insertsPerRay(ws.config.subdivisionLevels) <= ws.pointCapacity;
}

void cmdUpdateSurface(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights) {
  // The cached points' heights and the pending gradient belong to the heights being replaced.
  if (ws.gradientPending)
    fail("water surface: cmdUpdateSurface with a pending height gradient (cmdPushSurfaceGradients first)");
  static std::atomic<uint64_t> versions{0};
  ws.heightsVersion = ++versions;
  cmdClearPointCache(cb, ws);
  cmdBarrier(cb);
  SurfacePush pc = basePush(ws);
  heights.evaluate(cb, ws.gridPoints, ws.gridPointCount, ws.gridHeights);
  cmdBarrier(cb);
  uint32_t vertexCount = (ws.cellsX + 1) * (ws.cellsY + 1);
  cmdDispatch(cb, ws.pipelines.gridVertices, {bind(ws.gridHeights), bind(ws.vertices)}, &pc, groupsFor(vertexCount, 64));
  cmdBarrier(cb);
  if (ws.heightRange) {  // compute backend: the walk's height slab instead of a BVH
    const uint32_t range[2] = {0xFFFFFFFFu, 0u};
    vkCmdUpdateBuffer(cb, ws.heightRange.buffer, 0, sizeof(range), range);
    cmdBarrier(cb);
    cmdDispatch(cb, ws.pipelines.heightRange, {bind(ws.vertices), bind(ws.heightRange)}, &vertexCount, groupsFor(vertexCount, 64));
    cmdBarrier(cb);
  } else {
    if (ws.blas.built) cmdRefit(cb, ws.blas);
    else cmdBuild(cb, ws.blas);
    cmdBarrier(cb);
    if (ws.top.tlas.built) cmdRefit(cb, ws.top.tlas);
    else cmdBuild(cb, ws.top.tlas);
    cmdBarrier(cb);
  }
  profileStage(cb, *ws.ctx, "water update (heights, refit)");
  ws.updated = true;
}

namespace {

// One traceSurface call: what its submissions share (the rays, the push constants, the
// timer when timings are asked for).
struct SurfaceTracePass {
  Context& ctx;
  WaterSurface& ws;
  const HeightSource& heights;
  const Buffer& rays;
  Buffer& records;
  SurfacePush pc;
  uint32_t groups = 0;
  std::unique_ptr<GpuTimer> timer;
  SurfaceTimings* timings = nullptr;
};

// Records into one submission (waited for), the timer started first; its stages added to timings.
void submitPass(SurfaceTracePass& t, const std::function<void(VkCommandBuffer)>& record) {
  submitAndWait(t.ctx, [&](VkCommandBuffer cb) {
    if (t.timer) cmdTimerStart(cb, *t.timer);
    record(cb);
  });
  if (t.timer)
    for (auto& [stage, ms] : readTimer(*t.timer)) (*t.timings)[stage] += ms;
}

void stampPass(SurfaceTracePass& t, VkCommandBuffer cb, const std::string& stage) {
  if (t.timer) cmdTimerStamp(cb, *t.timer, stage);
  profileStage(cb, t.ctx, "water trace: " + stage);
}

// Queues the lattice points the rays' level `level` needs (mode 1: the normals' points).
void requestPoints(SurfaceTracePass& t, VkCommandBuffer cb, int level, uint32_t mode) {
  SurfacePush q = t.pc;
  q.level = level;
  q.mode = mode;
  cmdDispatch(cb, t.ws.pipelines.requestPoints, {bind(t.records), bind(t.ws.latticeIndex), bind(t.ws.points), bind(t.ws.counters)}, &q,
              t.groups);
  cmdBarrier(cb);
}

// H at the points queued since `base` (they end at `end`), into pointHeights[base, end).
void evaluateNewPoints(SurfaceTracePass& t, VkCommandBuffer cb, uint32_t base, uint32_t end) {
  WaterSurface& ws = t.ws;
  uint32_t n = end - base;
  if (n == 0) return;
  if (base == 0) {
    t.heights.evaluate(cb, ws.points, n, ws.pointHeights);
    cmdBarrier(cb);
    return;
  }
  VkBufferCopy c{VkDeviceSize(base) * 8, 0, VkDeviceSize(n) * 8};
  vkCmdCopyBuffer(cb, ws.points.buffer, ws.evalPoints.buffer, 1, &c);
  cmdBarrier(cb);
  t.heights.evaluate(cb, ws.evalPoints, n, ws.evalHeights);
  cmdBarrier(cb);
  VkBufferCopy h{0, VkDeviceSize(base) * 4, VkDeviceSize(n) * 4};
  vkCmdCopyBuffer(cb, ws.evalHeights.buffer, ws.pointHeights.buffer, 1, &h);
  cmdBarrier(cb);
}

// The same for the points queued since the last call, counted on the device: their range
// (surface_point_range.comp), gathered into evalPoints, H by an indirect dispatch, and
// scattered into pointHeights. bound: the most points one level can queue.
void evaluateQueuedPoints(SurfaceTracePass& t, VkCommandBuffer cb, uint32_t bound) {
  WaterSurface& ws = t.ws;
  const uint32_t rangePush[2] = {t.heights.queuedGroup, ws.pointCapacity};
  cmdDispatch(cb, ws.pipelines.pointRange, {bind(ws.counters), bind(ws.pointRange)}, rangePush, 1);
  cmdBarrier(cb);
  const uint32_t gather = 0, scatter = 1;
  cmdDispatchIndirect(cb, ws.pipelines.pointMove, {bind(ws.pointRange), bind(ws.points), bind(ws.evalPoints), bind(ws.evalHeights), bind(ws.pointHeights)},
                      &gather, ws.pointRange, kMoveGroupsOffset);
  cmdBarrier(cb);
  t.heights.evaluateQueued(cb, ws.evalPoints, ws.evalHeights, ws.pointRange, kHeightGroupsOffset, bound);
  cmdBarrier(cb);
  cmdDispatchIndirect(cb, ws.pipelines.pointMove, {bind(ws.pointRange), bind(ws.points), bind(ws.evalPoints), bind(ws.evalHeights), bind(ws.pointHeights)},
                      &scatter, ws.pointRange, kMoveGroupsOffset);
  cmdBarrier(cb);
}

uint32_t readPointCount(SurfaceTracePass& t) {
  uint32_t n = 0;
  download(t.ctx, t.ws.counters, &n, 4);
  if (n > t.ws.pointCapacity) fail("water surface: lattice point table overflow (" + std::to_string(n) + " points)");
  return n;
}

// The global trace against the coarse mesh, then the midpoints level 1 needs.
void recordGlobalTrace(SurfaceTracePass& t, VkCommandBuffer cb, bool emptyCache, const SurfaceTraceHooks& hooks) {
  WaterSurface& ws = t.ws;
  const SurfacePipelines& p = ws.pipelines;
  if (hooks.before) {
    hooks.before(cb);
    cmdBarrier(cb);
  }
  if (emptyCache) cmdClearPointCache(cb, ws);
  vkCmdFillBuffer(cb, ws.counters.buffer, 4, VK_WHOLE_SIZE, 0);  // this trace's counts; 0 is the cache's
  cmdBarrier(cb);
  // The cache's points are evaluated: the device's count is where the new ones start
  // (surface_point_range.comp), so recording a trace needs no count read back from the last.
  const VkBufferCopy cached{0, 0, 4};
  vkCmdCopyBuffer(cb, ws.counters.buffer, ws.pointRange.buffer, 1, &cached);
  cmdBarrier(cb);
  stampPass(t, cb, "clear");
  if (ws.heightRange)
    cmdDispatch(cb, p.globalTrace, {bind(ws.vertices), bind(t.rays), bind(ws.cellOrder), bind(t.records), bind(ws.counters), bind(ws.heightRange)},
                &t.pc, t.groups);
  else
    cmdDispatch(cb, p.globalTrace, {bind(ws.top.tlas), bind(t.rays), bind(ws.cellOrder), bind(t.records), bind(ws.counters)}, &t.pc, t.groups);
  cmdBarrier(cb);
  stampPass(t, cb, "global trace");
  if (ws.config.subdivisionLevels > 0) {
    requestPoints(t, cb, 1, 0);
    stampPass(t, cb, "level 1 points");
  }
}

using EvaluateStep = std::function<void(VkCommandBuffer)>;

// Level k of the subdivision: the heights of its new points, the test against its triangles,
// and the points the next level (or, at the last, the normals) needs.
void recordSubdivisionLevel(SurfaceTracePass& t, VkCommandBuffer cb, uint32_t k, const EvaluateStep& evaluate) {
  WaterSurface& ws = t.ws;
  const std::string level = "level " + std::to_string(k);
  evaluate(cb);
  stampPass(t, cb, level + " heights");
  SurfacePush q = t.pc;
  q.level = int32_t(k);
  cmdDispatch(cb, ws.pipelines.subdivide,
              {bind(t.rays), bind(t.records), bind(ws.gridHeights), bind(ws.latticeIndex), bind(ws.pointHeights), bind(ws.counters)}, &q,
              t.groups);
  cmdBarrier(cb);
  stampPass(t, cb, level + " test");
  if (k < ws.config.subdivisionLevels) {
    requestPoints(t, cb, int(k) + 1, 0);
    stampPass(t, cb, "level " + std::to_string(k + 1) + " points");
  } else {
    requestPoints(t, cb, int(k), 1);
    stampPass(t, cb, "normal points");
  }
}

// The normals' heights and the refraction at each hit.
void recordRefraction(SurfaceTracePass& t, VkCommandBuffer cb, const EvaluateStep& evaluate, Buffer& refractedRays,
                      const SurfaceTraceHooks& hooks) {
  WaterSurface& ws = t.ws;
  evaluate(cb);
  stampPass(t, cb, "normal heights");
  cmdDispatch(cb, ws.pipelines.refract,
              {bind(t.rays), bind(t.records), bind(ws.gridHeights), bind(ws.latticeIndex), bind(ws.pointHeights), bind(refractedRays),
               bind(ws.hitNormals), bind(ws.counters)},
              &t.pc, t.groups);
  cmdBarrier(cb);
  stampPass(t, cb, "refract");
  if (hooks.after) hooks.after(cb);
}

}  // namespace

void traceSurface(Context& ctx, WaterSurface& ws, const HeightSource& heights, const Buffer& rays, uint32_t count,
                  Buffer& refractedRays, Buffer& records, SurfaceTimings* timings, const SurfaceTraceHooks& hooks) {
  if (!ws.updated) fail("traceSurface before cmdUpdateSurface: the surface has no heights yet");
  if (count > ws.config.maxRays)
    fail("traceSurface with " + std::to_string(count) + " rays; the surface was created for at most " + std::to_string(ws.config.maxRays));
  ws.lastRayCount = count;
  ws.lastCounters = {};
  ws.lastCounters.points = ws.cachedPoints;
  if (count == 0) {
    if (hooks.before || hooks.after)
      submitAndWait(ctx, [&](VkCommandBuffer cb) {
        if (hooks.before) hooks.before(cb);
        cmdBarrier(cb);
        if (hooks.after) hooks.after(cb);
      });
    return;
  }
  const bool emptyCache = !surfaceCacheHasRoom(ws, count);
  if (emptyCache && ws.gradientPending)
    fail("water surface: the point cache is full while a height gradient is pending (cmdPushSurfaceGradients first)");
  checkBuffer(rays, VkDeviceSize(count) * sizeof(GpuRay), "rays");
  checkBuffer(refractedRays, VkDeviceSize(count) * sizeof(GpuRay), "refracted rays");
  checkBuffer(records, VkDeviceSize(count) * sizeof(SurfaceRecord), "records");

  SurfaceTracePass t{ctx, ws, heights, rays, records, basePush(ws)};
  t.pc.count = count;
  t.groups = groupsFor(count, 64);
  if (timings) {
    timings->clear();
    t.timings = timings;
    t.timer = std::make_unique<GpuTimer>();
    createTimer(ctx, *t.timer, 8 + 3 * ws.config.subdivisionLevels);  // every stamp of a one-submission trace
  }
  const uint32_t K = ws.config.subdivisionLevels;
  if (traceIsOneSubmission(ws, heights, count)) {
    const uint32_t bound = uint32_t(std::min<uint64_t>(ws.pointCapacity, uint64_t(count) * insertsPerRay(K)));
    const EvaluateStep evaluate = [&](VkCommandBuffer cb) { evaluateQueuedPoints(t, cb, bound); };
    const auto record = [&](VkCommandBuffer cb) {
      recordGlobalTrace(t, cb, emptyCache, hooks);
      for (uint32_t k = 1; k <= K; k++) recordSubdivisionLevel(t, cb, k, evaluate);
      recordRefraction(t, cb, evaluate, refractedRays, hooks);
      // the counters where the host reads them after the wait, with no submission of their own
      cmdBarrier(cb);
      cmdCopyToHost(cb, ws.counters, 0, ws.countersReadback, 0, kCounterCount * 4);
    };
    if (hooks.submit) {
      hooks.submit(record);  // which emptied the host's count with the cache, if it did
      ws.cachedPoints = ws.lastCounters.points = cachedPointsBoundAfterTrace(ws, count);
      return;
    }
    submitPass(t, record);
    ws.lastCounters = countersFrom(static_cast<const uint32_t*>(ws.countersReadback.mapped));
    if (ws.lastCounters.points > ws.pointCapacity)
      fail("water surface: lattice point table overflow (" + std::to_string(ws.lastCounters.points) + " points)");
    ws.cachedPoints = ws.lastCounters.points;
    return;
  }
  submitPass(t, [&](VkCommandBuffer cb) { recordGlobalTrace(t, cb, emptyCache, hooks); });
  uint32_t evaluated = ws.cachedPoints;
  for (uint32_t k = 1; k <= K; k++) {
    uint32_t queued = readPointCount(t);
    submitPass(t, [&](VkCommandBuffer cb) {
      recordSubdivisionLevel(t, cb, k, [&, evaluated, queued](VkCommandBuffer c) { evaluateNewPoints(t, c, evaluated, queued); });
    });
    evaluated = queued;
  }
  uint32_t queued = K > 0 ? readPointCount(t) : 0;
  submitPass(t, [&](VkCommandBuffer cb) {
    recordRefraction(t, cb, [&, evaluated, queued](VkCommandBuffer c) { evaluateNewPoints(t, c, evaluated, queued); }, refractedRays, hooks);
  });
  ws.lastCounters = readSurfaceCounters(ctx, ws);
  ws.cachedPoints = ws.lastCounters.points;
}

bool traceIsOneSubmission(const WaterSurface& ws, const HeightSource& heights, uint32_t rays) {
  const uint32_t K = ws.config.subdivisionLevels;
  if (K == 0 || !heights.evaluateQueued || heights.queuedGroup == 0) return false;
  const uint64_t bound = std::min<uint64_t>(ws.pointCapacity, uint64_t(rays) * insertsPerRay(K));
  const uint64_t maxGroups = ws.ctx->properties.limits.maxComputeWorkGroupCount[0];
  return (bound + 63) / 64 <= maxGroups && (bound + heights.queuedGroup - 1) / heights.queuedGroup <= maxGroups;
}

void cmdBackwardSurfaceToHeights(VkCommandBuffer cb, WaterSurface& ws, const Buffer& rays, const Buffer& records, const Buffer& rayGrads,
                                 uint32_t count) {
  if (count != ws.lastRayCount)
    fail("cmdBackwardSurface for " + std::to_string(count) + " rays after a trace of " + std::to_string(ws.lastRayCount));
  if (count == 0) return;
  checkBuffer(rayGrads, VkDeviceSize(count) * sizeof(GpuRayGrad), "ray gradients");
  SurfacePush pc = basePush(ws);
  pc.count = count;
  cmdApplyAddedGradient(cb, ws);
  if (!ws.gradientPending) {
    vkCmdFillBuffer(cb, ws.gridGrad.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cb, ws.pointGrad.buffer, 0, VK_WHOLE_SIZE, 0);
  }
  cmdBarrier(cb);
  cmdDispatch(cb, ws.pipelines.backward,
              {bind(rays), bind(records), bind(rayGrads), bind(ws.gridHeights), bind(ws.latticeIndex),
               bind(ws.pointHeights), bind(ws.gridGrad), bind(ws.pointGrad), bind(ws.counters)},
              &pc, groupsFor(count, 64));
  cmdBarrier(cb);
  profileStage(cb, *ws.ctx, "water backward: to heights");
  ws.gradientPending = true;
}

void cmdPushSurfaceGradients(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights) {
  if (!ws.gradientPending) return;
  cmdApplyAddedGradient(cb, ws);
  if (heights.accumulateGradients) {
    heights.accumulateGradients(cb, ws.gridPoints, ws.gridGrad, ws.gridPointCount);
    if (ws.cachedPoints) heights.accumulateGradients(cb, ws.points, ws.pointGrad, ws.cachedPoints);
    cmdBarrier(cb);
    profileStage(cb, *ws.ctx, "water backward: to weights");
  }
  ws.gradientPending = false;
}

void addGridGradient(Context& ctx, WaterSurface& ws, const std::vector<float>& g, double scale) {
  if (g.size() != ws.gridPointCount)
    fail("water surface: a grid gradient of " + std::to_string(g.size()) + " values for " + std::to_string(ws.gridPointCount) + " grid points");
  const VkDeviceSize bytes = VkDeviceSize(ws.gridPointCount) * 4;
  if (!ws.addedGrad.buffer) ws.addedGrad = createBuffer(ctx, bytes, 0, MemoryUse::Readback);
  float* added = static_cast<float*>(ws.addedGrad.mapped);
  if (!ws.addedPending) {
    std::fill(added, added + g.size(), 0.0f);
    ws.addedStartsSum = !ws.gradientPending;
    ws.addedPending = true;
  }
  for (size_t k = 0; k < g.size(); k++) added[k] = float(double(added[k]) + scale * double(g[k]));
  ws.gradientPending = true;
}

void cmdApplyAddedGradient(VkCommandBuffer cb, WaterSurface& ws) {
  if (!ws.addedPending) return;
  if (ws.addedStartsSum) {
    vkCmdFillBuffer(cb, ws.gridGrad.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cb, ws.pointGrad.buffer, 0, VK_WHOLE_SIZE, 0);
  }
  cmdBarrier(cb);
  const uint32_t n = ws.gridPointCount;
  cmdDispatch(cb, ws.pipelines.addGridGradient, {bind(ws.addedGrad), bind(ws.gridGrad)}, &n, groupsFor(n, 64));
  cmdBarrier(cb);
  ws.addedPending = ws.addedStartsSum = false;
}

bool cmdListAndPushSurfaceGradients(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights, uint32_t cachedBound) {
  if (!heights.accumulateGradients) fail("water surface: a gradient push into a height source without parameters");
  // The points with a gradient listed on the device: the coarse grid's, then the cache's up to
  // the bound (slots past the cache's count hold a zero gradient: a sum starts by clearing them
  // all, and the cache only grows while a sum is pending), so a bound over the count lists the
  // same points.
  cachedBound = std::min(cachedBound, ws.pointCapacity);
  ws.gradientPending = false;  // taken by this push (what follows may update the surface)
  cmdApplyAddedGradient(cb, ws);
  vkCmdFillBuffer(cb, ws.pushCount.buffer, 0, VK_WHOLE_SIZE, 0);
  cmdBarrier(cb);
  uint32_t n = ws.gridPointCount;
  cmdDispatch(cb, ws.pipelines.compact, {bind(ws.gridPoints), bind(ws.gridGrad), bind(ws.pushPoints), bind(ws.pushGrads), bind(ws.pushCount)}, &n,
              groupsFor(n, 64));
  n = cachedBound;
  if (n) {
    cmdBarrier(cb);
    cmdDispatch(cb, ws.pipelines.compact, {bind(ws.points), bind(ws.pointGrad), bind(ws.pushPoints), bind(ws.pushGrads), bind(ws.pushCount)}, &n,
                groupsFor(n, 64));
  }
  cmdBarrier(cb);
  profileStage(cb, *ws.ctx, "water backward: points with a gradient");
  if (!heights.accumulateQueued || !heights.accumulateQueued(cb, ws.pushPoints, ws.pushGrads, ws.pushCount, ws.gridPointCount + cachedBound))
    return false;
  cmdBarrier(cb);
  profileStage(cb, *ws.ctx, "water backward: to weights");
  return true;
}

void pushListedSurfaceGradients(Context& ctx, WaterSurface& ws, const HeightSource& heights, const std::function<void(VkCommandBuffer)>& then) {
  uint32_t listed = 0;
  download(ctx, ws.pushCount, &listed, 4);
  if (!listed && !then) return;
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    if (listed) {
      heights.accumulateGradients(cb, ws.pushPoints, ws.pushGrads, listed);
      cmdBarrier(cb);
      profileStage(cb, ctx, "water backward: to weights");
    }
    if (then) then(cb);
  });
}

void pushSurfaceGradients(Context& ctx, WaterSurface& ws, const HeightSource& heights, const std::function<void(VkCommandBuffer)>& then) {
  auto thenAlone = [&] {
    if (then) submitAndWait(ctx, then);
  };
  if (!ws.gradientPending) return thenAlone();
  if (!heights.accumulateGradients) {
    ws.gradientPending = ws.addedPending = false;
    return thenAlone();
  }
  // Where the source can run on the count the device wrote, the push (and `then`) follow the
  // listing in the same submission, else the count is read back and the push is a second one.
  bool queued = false;
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    queued = cmdListAndPushSurfaceGradients(cb, ws, heights, ws.cachedPoints);
    if (queued && then) then(cb);
  });
  if (!queued) pushListedSurfaceGradients(ctx, ws, heights, then);
}

void cmdBackwardSurface(VkCommandBuffer cb, WaterSurface& ws, const HeightSource& heights, const Buffer& rays, const Buffer& records,
                        const Buffer& rayGrads, uint32_t count) {
  cmdBackwardSurfaceToHeights(cb, ws, rays, records, rayGrads, count);
  cmdPushSurfaceGradients(cb, ws, heights);
}

SurfaceCounters readSurfaceCounters(Context& ctx, WaterSurface& ws) {
  uint32_t c[kCounterCount] = {};
  download(ctx, ws.counters, c, sizeof(c));
  return countersFrom(c);
}


}  // namespace refrax
