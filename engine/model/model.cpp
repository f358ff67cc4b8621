#include "engine/model/model.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"
#include "engine/dataset/ground_truth.h"
#include "engine/surface/height_field_source.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {
namespace {

void allocateModelRays(Model& m, uint32_t n) {
  Context& ctx = *m.ctx;
  m.capacity = n;
  m.rays = createBuffer(ctx, size_t(n) * sizeof(GpuRay));
  m.refracted = createBuffer(ctx, size_t(n) * sizeof(GpuRay));
  m.records = createBuffer(ctx, size_t(n) * 32);  // a SurfaceRecord per ray
  m.results = createBuffer(ctx, size_t(n) * sizeof(GpuTraceResult));
}

void createSurface(Model& m) {
  m.surface.emplace(createWaterSurface(*m.ctx, surfaceConfigFor(m)));
  liftSurface(m);
}

HeightFieldConfig heightFieldConfig(const TrainConfig& c) {
  HeightFieldConfig hc;
  hc.octaves = c.mlpOctaves;
  hc.width = c.mlpWidth;
  hc.hiddenLayers = c.mlpHiddenLayers;
  hc.initialHeight = float(c.waterHeight);
  hc.lastLayerInitRange = float(c.mlpInitRange);
  hc.domainMin[0] = float(c.domain.xMin);
  hc.domainMin[1] = float(c.domain.yMin);
  hc.domainMax[0] = float(c.domain.xMax);
  hc.domainMax[1] = float(c.domain.yMax);
  hc.encodingWindow = encodingWindowAt(c, 0);
  return hc;
}

}  // namespace

uint32_t heightFieldSeed(const TrainConfig& c) { return uint32_t(c.seed * 7919u + 3u); }

void restartHeightField(Model& m) {
  HeightField& hf = *m.height;
  uploadWeights(*m.ctx, hf, initialHeightWeights(hf.config, heightFieldSeed(m.config)));
  hf.config.initialHeight = float(m.config.waterHeight);
  liftSurface(m);
}

void initModel(Model& m, Context& ctx, const TrainConfig& config, const Dataset& dataset) {
  m.ctx = &ctx;
  m.config = config;
  m.tracer = createGaussianTracer(ctx, config.kBuffer);
  m.proxyKind = proxyKindFor(config.proxy, ctx.caps);
  m.rayPipelines = createCameraRayPipelines(ctx);
  uint32_t most = 1;
  for (const auto& [name, views] : dataset.splits)
    for (const auto& v : views) most = std::max(most, uint32_t(v.camera.width * v.camera.height));
  allocateModelRays(m, most);
  if (config.model == WaterModel::Refraction)
    m.height.emplace(createHeightField(ctx, heightFieldConfig(config), heightFieldSeed(config)));
  if (config.model == WaterModel::FlatWater) {
    m.planeHeight = config.waterHeight;
    AnalyticWaves w;
    w.base = float(m.planeHeight);
    m.plane = createAnalyticHeightField(ctx, w);
  }
  if (config.model == WaterModel::KnownWater) {
    KnownWaterTruth truth = loadKnownWater(dataset);
    scaleKnownWater(truth, config.knownWaterScale);
    if (truth.grid) {
      const HeightGrid& g = *truth.grid;
      const double box[4] = {g.xMin, g.yMin, g.xMax, g.yMax};
      m.trueGrid.emplace(createGridHeightField(ctx, uint32_t(g.nx), uint32_t(g.ny), box, g.heights));
      m.trueGridHost = std::move(truth.grid);
      truth.waves = AnalyticWaves{};  // the plane unused, at height 0
    }
    m.plane = createAnalyticHeightField(ctx, *truth.waves);
    m.planeHeight = m.plane.waves.base;  // what a checkpoint stores and restores as the base
  }
  if (config.model != WaterModel::NoRefraction) createSurface(m);
}

void uploadModelGaussians(Model& m) {
  m.device = uploadGaussians(*m.ctx, m.gaussians);
  m.proxies = buildGaussianProxies(*m.ctx, m.tracer, m.device, m.gaussians, m.proxyKind, true);
}

HeightSource currentHeightSource(const Model& m) {
  if (m.height) return heightSource(*m.height);
  if (m.trueGrid) return heightSource(*m.trueGrid);
  return heightSource(m.plane);
}

void liftSurface(Model& m) {
  HeightSource src = currentHeightSource(m);
  submitAndWait(*m.ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *m.surface, src); });
}

WaterSurfaceConfig surfaceConfigFor(const Model& m) {
  WaterSurfaceConfig wc;
  const Rect& d = m.config.domain;
  wc.domain = SurfaceDomain{float(d.xMin), float(d.yMin), float(d.xMax), float(d.yMax)};
  wc.gridCells = m.config.gridCells;
  wc.subdivisionLevels = m.config.subdivisionLevels;
  wc.ior = float(m.config.ior);
  wc.maxRays = m.capacity;
  return wc;
}

void growModelRayCapacity(Model& m, uint32_t n) {
  if (n <= m.capacity) return;
  // A new surface would drop the gradient the old one holds (a training bug, not a user's).
  if (m.surface && m.surface->gradientPending) fail("growModelRayCapacity: the surface holds a gradient not yet pushed");
  allocateModelRays(m, n);
  if (m.surface) createSurface(m);
}

uint32_t shDegreeAt(const TrainConfig& c, int step) {
  if (c.gaussiansFixed) return c.maxShDegree;  // Gaussians read as trained: their colours need every degree
  return std::min<uint32_t>(c.maxShDegree, uint32_t(std::max(0, gaussianScheduleStep(c, step) - 1) / c.schedule.shDegreeInterval));
}

std::vector<double> viewWeights(const Model& m, const std::vector<View>& views) {
  const WaterSurface& ws = *m.surface;
  const Rect& d = m.config.domain;
  const uint32_t rowLength = ws.cellsX + 3;
  std::vector<double> w(ws.gridPointCount, 0.0);
  for (uint32_t j = 0; j <= ws.cellsY; j++)
    for (uint32_t i = 0; i <= ws.cellsX; i++) {
      glm::dvec3 p(d.xMin + (d.xMax - d.xMin) * i / ws.cellsX, d.yMin + (d.yMax - d.yMin) * j / ws.cellsY, m.config.waterHeight);
      for (const View& v : views)
        if (v.camera.sees(p)) w[size_t(j + 1) * rowLength + i + 1] += 1.0;
    }
  return w;
}

double meanHeightShift(const Model& m, const std::vector<float>& heights, const std::vector<double>& weights) {
  double sum = 0, total = 0;
  for (size_t k = 0; k < heights.size(); k++)
    if (weights[k] > 0 && std::isfinite(heights[k])) {
      sum += weights[k] * heights[k];
      total += weights[k];
    }
  return total == 0 ? 0.0 : m.config.waterHeight - sum / total;
}

void anchorMeanHeight(Model& m, const std::vector<double>& weights) {
  if (!m.config.anchorMeanHeight || !m.height || !m.surface) return;
  WaterSurface& ws = *m.surface;
  const double shift = meanHeightShift(m, downloadVector<float>(*m.ctx, ws.gridHeights, ws.gridPointCount), weights);
  if (shift == 0) return;
  m.height->config.initialHeight = float(double(m.height->config.initialHeight) + shift);
  submitAndWait(*m.ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, ws, *m.height); });
}

std::vector<double> sampleWaterHeights(Model& m, uint32_t nx, uint32_t ny) {
  const Rect& r = m.config.domain;
  std::vector<float> xy(size_t(nx) * ny * 2);
  for (uint32_t j = 0; j < ny; j++)
    for (uint32_t i = 0; i < nx; i++) {
      xy[2 * (j * nx + i)] = float(r.xMin + (r.xMax - r.xMin) * i / double(nx - 1));
      xy[2 * (j * nx + i) + 1] = float(r.yMin + (r.yMax - r.yMin) * j / double(ny - 1));
    }
  std::vector<double> out(size_t(nx) * ny, m.config.model == WaterModel::FlatWater ? m.planeHeight : m.config.waterHeight);
  if (m.config.model == WaterModel::KnownWater)
    for (size_t k = 0; k < out.size(); k++)
      out[k] = m.trueGridHost ? sampleHeight(*m.trueGridHost, xy[2 * k], xy[2 * k + 1]) : analyticHeightRef(m.plane.waves, xy[2 * k], xy[2 * k + 1]);
  if (m.height) {
    Context& ctx = *m.ctx;
    Buffer points = createBufferFrom(ctx, xy);
    Buffer heights = createBuffer(ctx, out.size() * 4);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdEvaluateHeights(cb, *m.height, points, uint32_t(out.size()), heights); });
    auto h = downloadVector<float>(ctx, heights, out.size());
    for (size_t k = 0; k < out.size(); k++) out[k] = h[k];
  }
  return out;
}

}  // namespace refrax
