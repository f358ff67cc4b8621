#include "engine/model/render_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include "engine/dataset/ground_truth.h"
#include "engine/base/error.h"
#include "engine/surface/surface_record.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_timer.h"

namespace refrax {

Camera lookAtCamera(const glm::dvec3& position, const glm::dvec3& target, int width, int height, double fovY) {
  if (width <= 0 || height <= 0) fail("camera: the image size must be positive");
  if (!(fovY > 0 && fovY < M_PI)) fail("camera: the field of view must be in (0, 180) degrees");
  glm::dvec3 back = position - target;
  if (!(glm::length(back) > 0)) fail("camera: the position and the target coincide");
  back = glm::normalize(back);
  glm::dvec3 worldUp(0, 0, 1);
  if (std::abs(glm::dot(worldUp, back)) > 0.999) worldUp = glm::dvec3(0, 1, 0);  // looking straight down: image up is +y
  glm::dvec3 right = glm::normalize(glm::cross(worldUp, back));
  glm::dvec3 up = glm::cross(back, right);
  Camera c;
  c.cameraToWorld = glm::dmat4(glm::dvec4(right, 0), glm::dvec4(up, 0), glm::dvec4(back, 0), glm::dvec4(position, 1));
  c.width = width;
  c.height = height;
  c.fy = 0.5 * height / std::tan(fovY / 2);
  c.fx = c.fy;
  c.cx = 0.5 * width;
  c.cy = 0.5 * height;
  return c;
}

namespace {

// How a view of the model blends the Gaussians: the scene's background, the SH degree of its step.
TraceOptions viewTraceOptions(const Model& m) {
  TraceOptions opt;
  for (int ch = 0; ch < 3; ch++) opt.background[ch] = float(m.config.datasetOptions.background[ch]);
  opt.shDegree = shDegreeAt(m.config, std::max(1, m.step));
  return opt;
}

// The hits' points on the surface and, for the same pixels, on the initial flat water plane.
void collectSurfacePoints(const Model& m, const std::vector<GpuRay>& rays, const std::vector<GpuRay>& refracted,
                          const std::vector<uint32_t>& flags, RenderedView& out) {
  double h = m.config.waterHeight;
  for (size_t i = 0; i < rays.size(); i++) {
    if (!(flags[i] & kSurfaceHit)) continue;
    out.surfacePoints.emplace_back(refracted[i].origin[0], refracted[i].origin[1], refracted[i].origin[2]);
    const GpuRay& r = rays[i];
    double t = (h - r.origin[2]) / r.dir[2];
    out.planePoints.emplace_back(r.origin[0] + t * r.dir[0], r.origin[1] + t * r.dir[1], h);
  }
}

}  // namespace

namespace {

using StageTimes = std::vector<std::pair<std::string, double>>;

// Adds the wall time since the last call to `stage` (when timing).
struct StageClock {
  StageTimes* stages;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  void lap(const char* stage) {
    if (!stages) return;
    const auto now = std::chrono::steady_clock::now();
    addStageMs(*stages, stage, std::chrono::duration<double, std::milli>(now - last).count());
    last = now;
  }
};

// The camera's image from its rays' results (one a pixel, row by row): their colours clamped to [0, 1].
Image imageOfResults(const GpuTraceResult* results, const Camera& camera) {
  Image image;
  image.width = camera.width;
  image.height = camera.height;
  image.channels = 3;
  const size_t n = size_t(camera.width) * size_t(camera.height);
  image.pixels.resize(n * 3);
  for (size_t i = 0; i < n; i++)
    for (int ch = 0; ch < 3; ch++) image.pixels[3 * i + ch] = std::clamp(results[i].rgb[ch], 0.0f, 1.0f);
  return image;
}

// An image alone, the learned or a closed-form water kept or the water removed, in one
// submission where the surface's trace is one (issue 48): the camera rays before the water's
// trace, the Gaussians and the copy of their results to where the host reads them after it, no
// wait between. Stage milliseconds from the device's timestamps (where it has them) and the
// host's clamp.
RenderedView renderImage(Model& m, const Camera& camera, WaterSurface* surface, const HeightSource& source, const RenderOptions& options) {
  Context& ctx = *m.ctx;
  const uint32_t n = uint32_t(camera.width) * uint32_t(camera.height);
  const VkDeviceSize bytes = VkDeviceSize(n) * sizeof(GpuTraceResult);
  if (!m.resultsReadback.buffer || m.resultsReadback.size < bytes) m.resultsReadback = createBuffer(ctx, bytes, 0, MemoryUse::Readback);
  GpuTimer timer;
  const bool stamped = options.stageMs && ctx.caps.timestamps;
  if (stamped) createTimer(ctx, timer, 8);
  const TraceOptions opt = viewTraceOptions(m);
  const Buffer& traced = surface ? m.refracted : m.rays;
  auto cameraRays = [&](VkCommandBuffer cb) {
    if (stamped) cmdTimerStart(cb, timer);
    cmdCameraRays(cb, m.rayPipelines, camera, m.rays, 0.0f, 1e6f);
    if (stamped) cmdTimerStamp(cb, timer, "camera rays");
  };
  auto gaussians = [&](VkCommandBuffer cb) {
    if (stamped && surface) cmdTimerStamp(cb, timer, "water");
    cmdBarrier(cb);
    cmdTraceForward(cb, m.tracer, m.proxies, m.device, traced, m.results, n, opt);
    if (stamped) cmdTimerStamp(cb, timer, "gaussians");
    cmdBarrier(cb);
    cmdCopyToHost(cb, m.results, 0, m.resultsReadback, 0, bytes);
    if (stamped) cmdTimerStamp(cb, timer, "image readback");
  };
  RenderedView out;
  if (surface) {
    traceSurface(ctx, *surface, source, m.rays, n, m.refracted, m.records, nullptr, {cameraRays, gaussians});
    out.missed = surface->lastCounters.missed;
  } else {
    submitAndWait(ctx, [&](VkCommandBuffer cb) {
      cameraRays(cb);
      gaussians(cb);
    });
  }
  const auto clampStart = std::chrono::steady_clock::now();
  out.image = imageOfResults(static_cast<const GpuTraceResult*>(m.resultsReadback.mapped), camera);
  if (options.stageMs) {
    if (stamped)
      for (const auto& [stage, ms] : readTimer(timer)) addStageMs(*options.stageMs, stage, ms);
    addStageMs(*options.stageMs, "image (host)", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - clampStart).count());
  }
  return out;
}

}  // namespace

RenderedView renderView(Model& m, const Camera& camera, WaterView water, const SwapSurface& swap, const RenderOptions& options) {
  Context& ctx = *m.ctx;
  StageClock clock{options.stageMs};
  uint32_t n = uint32_t(camera.width) * uint32_t(camera.height);
  if (water == WaterView::Swap && (swap.analytic != nullptr) == (swap.mesh != nullptr))
    fail(swap.analytic ? "render: two surfaces to swap in (a closed-form one and a mesh)" : "render: no surface to swap in");
  growModelRayCapacity(m, n);
  RenderedView out;
  const Buffer* traced = &m.rays;
  std::optional<WaterSurface> swapped;
  WaterSurface* surface = nullptr;
  HeightSource source;
  if (water == WaterView::Keep && m.surface) {
    surface = &*m.surface;
    surface->config.faceNormals = m.step <= m.config.schedule.faceNormalsUntil;
    source = currentHeightSource(m);
  } else if (water == WaterView::Swap && swap.analytic) {
    swapped.emplace(createWaterSurface(ctx, surfaceConfigFor(m)));
    surface = &*swapped;
    source = heightSource(*swap.analytic);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *surface, source); });
  }
  if (!options.surfacePoints && !(water == WaterView::Swap && swap.mesh)) return renderImage(m, camera, surface, source, options);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, m.rayPipelines, camera, m.rays, 0.0f, 1e6f); });
  clock.lap("camera rays");
  if (water == WaterView::Swap && !swap.analytic) {
    // The mesh's flags (one uint per ray) go into the records buffer (room for n SurfaceRecords).
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdRefractThroughMesh(cb, *swap.mesh, m.rays, n, surfaceConfigFor(m).ior, m.refracted, m.records); });
    traced = &m.refracted;
    clock.lap("water");
    auto flags = downloadVector<uint32_t>(ctx, m.records, n);
    for (uint32_t f : flags) out.missed += (f & kSurfaceMissed) != 0;
    if (options.surfacePoints)
      collectSurfacePoints(m, downloadVector<GpuRay>(ctx, m.rays, n), downloadVector<GpuRay>(ctx, m.refracted, n), flags, out);
    clock.lap("surface points");
  }
  if (surface) {
    traceSurface(ctx, *surface, source, m.rays, n, m.refracted, m.records);
    traced = &m.refracted;
    out.missed = surface->lastCounters.missed;
    clock.lap("water");
    if (options.surfacePoints) {
      auto records = downloadVector<SurfaceRecord>(ctx, m.records, n);
      std::vector<uint32_t> flags(n);
      for (uint32_t i = 0; i < n; i++) flags[i] = surfaceRecordFlags(records[i]);
      collectSurfacePoints(m, downloadVector<GpuRay>(ctx, m.rays, n), downloadVector<GpuRay>(ctx, m.refracted, n), flags, out);
      clock.lap("surface points");
    }
  }
  const TraceOptions opt = viewTraceOptions(m);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, m.tracer, m.proxies, m.device, *traced, m.results, n, opt); });
  clock.lap("gaussians");
  out.image = imageOfResults(downloadVector<GpuTraceResult>(ctx, m.results, n).data(), camera);
  clock.lap("image");
  return out;
}

std::vector<GpuTraceResult> traceModelRays(Model& m, const std::vector<GpuRay>& rays, WaterView water, float depthAtOpacity,
                                           std::vector<uint8_t>* hitWater) {
  if (water == WaterView::Swap) fail("traceModelRays: the learned water kept or removed only");
  Context& ctx = *m.ctx;
  const bool refract = water == WaterView::Keep && m.surface;
  const uint32_t chunk = refract ? std::min(m.surface->config.maxRays, 1u << 17) : 1u << 17;
  growModelRayCapacity(m, std::min<uint32_t>(chunk, uint32_t(std::max<size_t>(rays.size(), 1))));
  TraceOptions opt = viewTraceOptions(m);
  opt.depthAtOpacity = depthAtOpacity;
  std::vector<GpuTraceResult> out(rays.size());
  if (hitWater) hitWater->assign(rays.size(), 0);
  for (size_t first = 0; first < rays.size(); first += std::min<size_t>(chunk, m.capacity)) {
    const uint32_t n = uint32_t(std::min<size_t>({rays.size() - first, chunk, m.capacity}));
    upload(ctx, m.rays, &rays[first], VkDeviceSize(n) * sizeof(GpuRay));
    const Buffer* traced = &m.rays;
    if (refract) {
      m.surface->config.faceNormals = m.step <= m.config.schedule.faceNormalsUntil;
      traceSurface(ctx, *m.surface, currentHeightSource(m), m.rays, n, m.refracted, m.records);
      traced = &m.refracted;
      if (hitWater) {
        auto records = downloadVector<SurfaceRecord>(ctx, m.records, n);
        for (uint32_t i = 0; i < n; i++) (*hitWater)[first + i] = (surfaceRecordFlags(records[i]) & kSurfaceHit) != 0;
      }
    }
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, m.tracer, m.proxies, m.device, *traced, m.results, n, opt); });
    download(ctx, m.results, &out[first], VkDeviceSize(n) * sizeof(GpuTraceResult));
  }
  return out;
}

namespace {

std::string indexed(const std::string& dir, size_t i, const char* suffix) {
  char name[48];
  std::snprintf(name, sizeof name, "test_%03zu%s.png", i, suffix);
  return (std::filesystem::path(dir) / name).string();
}



// The flat start's error where the test rays met its plane in the domain, else why it is absent.
void putFlatStartRmse(nlohmann::json& metrics, const std::optional<double>& rmse) {
  if (rmse) metrics["initial_flat_surface_rmse"] = *rmse;
  else metrics["initial_flat_surface_rmse_missing"] = "no test ray met the flat start's plane inside the water's domain";
}
}  // namespace

nlohmann::json evaluateModel(Model& m, const Dataset& data, const std::string& rendersDir) {
  const auto& test = data.split("test");
  std::optional<HeightGrid> truth = loadGroundTruthSurface(data);
  nlohmann::json views = nlohmann::json::array();
  double psnrSum = 0, ssimSum = 0;
  std::vector<glm::dvec3> points, planePoints;
  uint32_t missed = 0;
  for (size_t i = 0; i < test.size(); i++) {
    RenderedView r = renderView(m, test[i].camera, WaterView::Keep);
    double p = psnr(r.image, test[i].image, test[i].mask), q = ssim(r.image, test[i].image, test[i].mask);  // the pixels that count
    psnrSum += p;
    ssimSum += q;
    missed += r.missed;
    points.insert(points.end(), r.surfacePoints.begin(), r.surfacePoints.end());
    planePoints.insert(planePoints.end(), r.planePoints.begin(), r.planePoints.end());
    views.push_back({{"name", test[i].name}, {"psnr", p}, {"ssim", q}});
    if (!rendersDir.empty()) {
      writePng(indexed(rendersDir, i, ""), r.image);
      writePng(indexed(rendersDir, i, "_air"), renderView(m, test[i].camera, WaterView::Remove, SwapSurface{}, kImageOnly).image);
    }
  }
  nlohmann::json metrics;
  metrics["model"] = waterModelName(m.config.model);
  metrics["step"] = m.step;
  metrics["test_views"] = views;
  metrics["psnr"] = psnrSum / double(test.size());
  metrics["ssim"] = ssimSum / double(test.size());
  metrics["missed_rays"] = missed;
  if (truth && !points.empty()) {
    metrics["surface_rmse"] = *surfaceRmse(*truth, points);  // points: some
    // The RMSE alone reads the same for noisy and for upside-down waves; the correlation tells.
    const double correlation = surfaceCorrelation(*truth, points);
    if (std::isfinite(correlation)) metrics["surface_correlation"] = correlation;
    metrics["surface_points"] = points.size();
    putFlatStartRmse(metrics, surfaceRmse(*truth, planePoints));
  } else if (truth && m.surface) {
    // Measured where the test rays meet the water: none did, so there is no error to give.
    metrics["surface_rmse_missing"] = "no test ray met the water surface inside its domain (" + std::to_string(missed) + " missed it)";
  } else if (truth && m.config.model == WaterModel::NoRefraction) {
    // No surface is modelled: its surface is the initial flat plane (reported for comparison).
    std::vector<glm::dvec3> plane;
    for (const auto& v : test) {
      Camera c = v.camera;
      for (int y = 0; y < c.height; y++)
        for (int x = 0; x < c.width; x++) {
          glm::dvec3 d = c.rayDirection(x + 0.5, y + 0.5);
          double t = (m.config.waterHeight - c.position().z) / d.z;
          glm::dvec3 q = c.position() + t * d;
          if (t > 0 && q.x >= m.config.domain.xMin && q.x <= m.config.domain.xMax && q.y >= m.config.domain.yMin && q.y <= m.config.domain.yMax)
            plane.push_back(q);
        }
    }
    putFlatStartRmse(metrics, surfaceRmse(*truth, plane));
  }
  if (data.splits.count("between")) {
    // More test views where a dataset has them (refrax synth's 3 x 3 rigs: between the training
    // cameras), reported apart so the test split's own views keep their protocol.
    const auto& between = data.split("between");
    double p = 0, q = 0;
    for (const auto& v : between) {
      const Image image = renderView(m, v.camera, WaterView::Keep, SwapSurface{}, kImageOnly).image;
      p += psnr(image, v.image, v.mask), q += ssim(image, v.image, v.mask);
    }
    metrics["between_psnr"] = p / double(between.size());
    metrics["between_ssim"] = q / double(between.size());
    metrics["between_views"] = between.size();
  }
  if (data.splits.count("air")) {
    const auto& air = data.split("air");
    double sum = 0;
    for (const auto& v : air) sum += psnr(renderView(m, v.camera, WaterView::Remove, SwapSurface{}, kImageOnly).image, v.image);
    metrics["water_removal_psnr"] = sum / double(air.size());
  }
  metrics["gaussians"] = m.gaussians.count();
  uint64_t bytes = uint64_t(m.gaussians.params.size()) * 4 + (m.height ? m.height->parameterCount * 4 : 0) +
                   (m.config.model == WaterModel::FlatWater ? 4 : 0);
  metrics["model_bytes"] = bytes;
  metrics["training_seconds"] = m.trainingSeconds;
  return metrics;
}

}  // namespace refrax
