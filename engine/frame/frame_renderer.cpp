#include "engine/frame/frame_renderer.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>

#include "engine/surface/builtin_surface_spec.h"
#include "engine/base/error.h"
#include "engine/surface/grid_mesh.h"
#include "engine/surface/surface_preview.h"
#include "engine/surface/gltf_surface.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

std::string describe(const BuiltinSurface& b) {
  char text[160];
  std::snprintf(text, sizeof text, "%s %.9g %.9g %.9g %.9g", b.kind.c_str(), b.height, b.amplitude, b.wavelength, b.directionDeg);
  return text;
}

void ensureCapacity(FrameRenderer& r, uint32_t n) {
  if (n <= r.capacity) return;
  vkDeviceWaitIdle(r.ctx->device);
  r.capacity = n;
  r.rays = createBuffer(*r.ctx, VkDeviceSize(n) * sizeof(GpuRay));
  r.refracted = createBuffer(*r.ctx, VkDeviceSize(n) * sizeof(GpuRay));
  r.records = createBuffer(*r.ctx, VkDeviceSize(n) * sizeof(SurfaceRecord));
  r.flags = createBuffer(*r.ctx, VkDeviceSize(n) * 4);
  r.results = createBuffer(*r.ctx, VkDeviceSize(n) * sizeof(GpuTraceResult));
  r.pixels = createBuffer(*r.ctx, VkDeviceSize(n) * 4);
}

}  // namespace

FrameRenderer createFrameRenderer(Context& ctx) {
  FrameRenderer r;
  r.ctx = &ctx;
  r.rayPipelines = createCameraRayPipelines(ctx);
  r.compose = createViewComposePipeline(ctx);
  return r;
}

WaterMode effectiveWater(const ViewScene& scene, const RenderSettings& s) {
  if (s.water == WaterMode::Kept && !learnedWater(scene)) return WaterMode::Removed;
  return s.water;
}

namespace {

// The water as a mesh: rebuilt when what it is made of changes.
void ensureMesh(FrameRenderer& r, ViewScene& scene, WaterMode water, const RenderSettings& s) {
  Context& ctx = *r.ctx;
  const SurfaceDomain& d = scene.domain;
  char grid[160];
  std::snprintf(grid, sizeof grid, " | %u cells over %.9g %.9g %.9g %.9g", s.bakeCells, d.x0, d.y0, d.x1, d.y1);
  std::string key = std::string(s.walkGrid ? "walk | " : "bvh | ") +
                    (water == WaterMode::Kept ? "learned " + std::to_string(scene.generation) + grid
                    : !s.swapMesh.empty()   ? "gltf " + s.swapMesh
                                            : "builtin " + describe(s.swap) + grid);
  if (r.mesh && r.meshKey == key) return;
  SurfaceMesh mesh;
  if (water == WaterMode::Kept) {
    mesh = bakeHeightMesh(ctx, *learnedWater(scene), d, s.bakeCells, s.bakeCells);
  } else if (!s.swapMesh.empty()) {
    mesh = readSurfaceGltf(s.swapMesh);
  } else {
    mesh = surfaceMeshFromGrid(makeGridMesh(s.bakeCells, s.bakeCells, d.x0, d.y0, d.x1, d.y1, surfaceHeightFunction(s.swap)));
  }
  // the learned and built-in surfaces are height grids: walked cell by cell, not through the BVH
  HeightGridLayout layout{s.bakeCells, s.bakeCells, d.x0, d.y0, d.x1, d.y1};
  bool isGrid = s.swapMesh.empty() || water == WaterMode::Kept;
  vkDeviceWaitIdle(ctx.device);
  r.mesh.reset();
  r.mesh.emplace(createMeshSurface(ctx, mesh, isGrid && s.walkGrid ? &layout : nullptr));
  r.meshKey = key;
}

}  // namespace

void prepareFrame(FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& s) {
  Context& ctx = *r.ctx;
  uint32_t n = uint32_t(camera.width) * uint32_t(camera.height);
  ensureCapacity(r, n);
  // tile lists kept while the image shrinks or grows within them (the automatic resolution scale)
  if (s.tiledTrace && !(r.tiles && reshapeTileCandidates(*r.tiles, uint32_t(camera.width), uint32_t(camera.height)))) {
    vkDeviceWaitIdle(ctx.device);
    r.tiles.reset();
    r.tiles.emplace(createTileCandidates(ctx, uint32_t(camera.width), uint32_t(camera.height)));
  }
  WaterMode water = effectiveWater(scene, s);
  r.surfaceMs.clear();
  bool closedForm = water == WaterMode::Kept || (s.swapMesh.empty() && s.swap.kind != "triangle");
  r.path = water == WaterMode::Removed              ? FrameRenderer::Path::Straight
           : s.exactWater && closedForm             ? FrameRenderer::Path::Subdivided
                                                    : FrameRenderer::Path::Mesh;
  if (r.path == FrameRenderer::Path::Straight) return;
  if (r.path == FrameRenderer::Path::Mesh) {
    ensureMesh(r, scene, water, s);
    return;
  }

  WaterSurfaceConfig wc;
  wc.domain = scene.domain;
  wc.gridCells = s.gridCells;
  wc.subdivisionLevels = s.subdivisionLevels;
  wc.ior = s.ior;
  wc.maxRays = r.capacity;
  char shape[160];
  std::snprintf(shape, sizeof shape, "%.9g %.9g %.9g %.9g %u %u %u", wc.domain.x0, wc.domain.y0, wc.domain.x1, wc.domain.y1, wc.gridCells,
                wc.subdivisionLevels, wc.maxRays);
  if (!r.surface || r.surfaceShape != shape) {
    vkDeviceWaitIdle(ctx.device);
    r.surface.reset();
    r.surface.emplace(createWaterSurface(ctx, wc));
    r.surfaceShape = shape;
    r.surfaceHeights.clear();
  }
  r.surface->config.ior = s.ior;
  // As renderView: the learned surface with the normals of its training phase, a swapped-in one smooth.
  r.surface->config.faceNormals = water == WaterMode::Kept && scene.model && scene.model->step <= scene.model->config.schedule.faceNormalsUntil;

  HeightSource source;
  std::string heights;
  if (water == WaterMode::Kept) {
    source = *learnedWater(scene);
    heights = "learned " + std::to_string(scene.generation);
  } else {
    heights = "swap " + describe(s.swap);
    if (r.surfaceHeights != heights) r.swapField.emplace(createAnalyticHeightField(ctx, builtinSurfaceWaves(s.swap)));
    source = heightSource(*r.swapField);
  }
  if (r.surfaceHeights != heights) {
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *r.surface, source); });
    r.surfaceHeights = heights;
  }
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, r.rayPipelines, camera, r.rays, 0.0f, 1e6f); });
  SurfaceTimings timings;
  traceSurface(ctx, *r.surface, source, r.rays, n, r.refracted, r.records, ctx.caps.timestamps ? &timings : nullptr);
  double total = 0;
  for (auto& [stage, ms] : timings) total += ms;
  if (!timings.empty()) r.surfaceMs.push_back({"surface", total});
}

namespace {

// The frame's Gaussian stage on the rays the water left (tiles culled, then traced; or a BVH
// traversal per ray) into r.results.
void cmdFrameGaussians(VkCommandBuffer cb, FrameRenderer& r, ViewScene& scene, uint32_t n, const RenderSettings& s, GpuTimer& timer) {
  TraceOptions opt;
  for (int ch = 0; ch < 3; ch++) opt.background[ch] = scene.background[ch];
  opt.shDegree = std::min(s.shDegree, 3u);
  opt.minTransmittance = s.minTransmittance;
  cmdBarrier(cb);
  const Buffer& rays = r.path != FrameRenderer::Path::Straight ? r.refracted : r.rays;
  if (s.tiledTrace) {
    if (!r.tiles || r.tiles->width * r.tiles->height != n) fail("cmdRenderFrame: the tiles were sized for another image");
    cmdCullTiles(cb, scene.tracer, sceneProxies(scene), rays, *r.tiles);
    cmdTimerStamp(cb, timer, "cull");
    cmdBarrier(cb);
    cmdTraceForwardTiled(cb, scene.tracer, sceneProxies(scene), rays, r.results, *r.tiles, opt);
  } else {
    cmdTraceForward(cb, scene.tracer, sceneProxies(scene), sceneGaussians(scene), rays, r.results, n, opt);
  }
  cmdTimerStamp(cb, timer, "gaussians");
}

}  // namespace

void cmdRenderFrame(VkCommandBuffer cb, FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& s,
                    GpuTimer& timer) {
  uint32_t n = uint32_t(camera.width) * uint32_t(camera.height);
  if (n > r.capacity) fail("cmdRenderFrame before prepareFrame for this size");
  if (r.path != FrameRenderer::Path::Subdivided) {
    cmdCameraRays(cb, r.rayPipelines, camera, r.rays, 0.0f, 1e6f);
    cmdTimerStamp(cb, timer, "rays");
  }
  if (r.path == FrameRenderer::Path::Mesh) {
    cmdRefractThroughMesh(cb, *r.mesh, r.rays, n, s.ior, r.refracted, r.flags);
    cmdTimerStamp(cb, timer, "water");
  }
  cmdFrameGaussians(cb, r, scene, n, s, timer);
  cmdComposeView(cb, r.compose, r.results, r.pixels, n, s.compose);
  cmdTimerStamp(cb, timer, "compose");
}

bool isMeshPath(const std::string& path) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  auto endsWith = [&](const std::string& ext) { return lower.size() > ext.size() && lower.compare(lower.size() - ext.size(), ext.size(), ext) == 0; };
  return endsWith(".gltf") || endsWith(".glb");
}

void applyWaterSpec(const std::string& spec, float level, RenderSettings& rs) {
  if (spec == "keep") return void(rs.water = WaterMode::Kept);
  if (spec == "remove") return void(rs.water = WaterMode::Removed);
  if (isMeshPath(spec)) {
    rs.swapMesh = spec;
  } else {
    rs.swap = parseBuiltinSurface(spec, level);
    rs.swapMesh.clear();
  }
  rs.water = WaterMode::Swapped;
}

RenderSettings sceneRenderSettings(const ViewScene& scene) {
  RenderSettings rs;
  rs.swap = BuiltinSurface{"flat", scene.waterHeight, 0.02f, 0.5f, 0.0f};
  rs.ior = scene.ior;
  rs.shDegree = scene.model ? shDegreeAt(scene.model->config, std::max(1, scene.model->step)) : scene.maxShDegree;
  if (scene.model) {
    rs.gridCells = scene.model->config.gridCells;
    rs.subdivisionLevels = scene.model->config.subdivisionLevels;
    // The baked mesh's vertices on the finest lattice the trainer's subdivision evaluates H at.
    rs.bakeCells = scene.model->config.gridCells << scene.model->config.subdivisionLevels;
  }
  rs.water = learnedWater(scene) ? WaterMode::Kept : WaterMode::Removed;
  return rs;
}

Image renderFrameImage(FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& s,
                       std::vector<std::pair<std::string, double>>* stageMs) {
  Context& ctx = *r.ctx;
  prepareFrame(r, scene, camera, s);
  const uint32_t n = uint32_t(camera.width) * uint32_t(camera.height);
  const VkDeviceSize bytes = VkDeviceSize(n) * 4;
  if (!r.readback.buffer || r.readback.size < bytes) r.readback = createBuffer(ctx, bytes, 0, MemoryUse::Readback);
  GpuTimer timer;
  if (stageMs) createTimer(ctx, timer, 16);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdTimerStart(cb, timer);
    cmdRenderFrame(cb, r, scene, camera, s, timer);
    cmdBarrier(cb);
    cmdCopyToHost(cb, r.pixels, 0, r.readback, 0, bytes);
    cmdTimerStamp(cb, timer, "image readback");
  });
  const auto hostStart = std::chrono::steady_clock::now();
  const uint32_t* pixels = static_cast<const uint32_t*>(r.readback.mapped);
  Image image = rgba8ToImage(std::vector<uint32_t>(pixels, pixels + n), uint32_t(camera.width), uint32_t(camera.height));
  if (stageMs) {
    for (const auto& [stage, ms] : r.surfaceMs) addStageMs(*stageMs, stage, ms);
    for (const auto& [stage, ms] : readTimer(timer)) addStageMs(*stageMs, stage, ms);
    addStageMs(*stageMs, "image (host)", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - hostStart).count());
  }
  return image;
}

double frameTraceMs(FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& s, int repeats) {
  renderFrameImage(r, scene, camera, s);  // the frame's rays, refracted where there is water, in place
  const uint32_t n = uint32_t(camera.width) * uint32_t(camera.height);
  GpuTimer unstamped;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < repeats; k++) submitAndWait(*r.ctx, [&](VkCommandBuffer cb) { cmdFrameGaussians(cb, r, scene, n, s, unstamped); });
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / std::max(1, repeats);
}

}  // namespace refrax
