#include "engine/train/train_session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>

#include "engine/dataset/ground_truth.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/surface/height_field_source.h"
#include "engine/dataset/view_image.h"
#include "engine/surface/surface_prior.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/train/init_gaussians.h"
#include "engine/vk/strided_copy.h"
#include "engine/train/plane_sweep.h"
#include "engine/train/sweep_loss.h"
#include "engine/run/train_views.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"

namespace refrax {
namespace {

// Rebuilding the proxies' tree order (median split) every this many steps keeps the BVH
// tight as Gaussians move; between, the tree is rebuilt in the same order.
constexpr int kProxyReorderInterval = 100;

// The batch's buffers for up to n rays (the model's own: growModelRayCapacity).
// The row of StepBuffers::lossLog that step `step` writes: its image loss, then its density loss.
VkDeviceSize lossLogOffset(int step) { return VkDeviceSize(uint32_t(step) % kLossLogRows) * 8; }

void allocateBatchBuffers(TrainSession& s, uint32_t n) {
  Context& ctx = *s.model.ctx;
  s.buffers.capacity = n;
  s.buffers.pixels = createBuffer(ctx, size_t(n) * 4);
  s.buffers.rendered = createBuffer(ctx, size_t(n) * 12);
  s.buffers.target = createBuffer(ctx, size_t(n) * 12);
  s.buffers.pixelWeights = createBuffer(ctx, size_t(n) * 4);
  s.buffers.lossGrad = createBuffer(ctx, size_t(n) * 12);
  s.buffers.dLoss = createBuffer(ctx, size_t(n) * 16);
  s.buffers.rayGrads = createBuffer(ctx, size_t(n) * sizeof(GpuRayGrad));
}

// The reference height-MLP schedule (5e-4 -> 5e-6) scaled to the configured start.
LearningRateSchedule surfaceLearningRate(const TrainConfig& c) {
  LearningRateSchedule lr = referenceLearningRate("height_mlp", c.extent);
  double scale = c.surfaceLearningRate / lr.initial;
  lr.initial *= scale;
  lr.final *= scale;
  lr.steps = c.schedule.lrSteps;
  return lr;
}

void shuffleViews(TrainSession& s) {
  size_t n = s.dataset.split("train").size();
  s.state.viewOrder.resize(n);
  for (size_t i = 0; i < n; i++) s.state.viewOrder[i] = uint32_t(i);
  std::shuffle(s.state.viewOrder.begin(), s.state.viewOrder.end(), s.state.rng);
  s.state.viewCursor = 0;
}

// Over the pixels that count (weight 1; every pixel without weights), rgb per pixel.
double batchPsnr(const std::vector<float>& a, const std::vector<float>& b, const std::vector<float>& weight) {
  double se = 0, counted = 0;
  for (size_t i = 0; i < a.size(); i++) {
    const double w = weight.empty() ? 1.0 : weight[i / 3];
    se += w * double(a[i] - b[i]) * double(a[i] - b[i]);
    counted += w;
  }
  double mse = se / std::max(1.0, counted);
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : INFINITY;
}

}  // namespace

namespace {
// The step's per-Gaussian buffers for the model's count: gradients, the densification
// statistic, the density regulariser's partial sums.
void allocateGaussianBatchBuffers(TrainSession& s) {
  size_t n = std::max<size_t>(1, s.model.gaussians.count());
  s.buffers.grads = createBuffer(*s.model.ctx, n * kGaussianFloats * 4);
  s.buffers.stats = createBuffer(*s.model.ctx, n * 2 * 4);
  s.buffers.densityPartials = createBuffer(*s.model.ctx, size_t(densityPartialCount(uint32_t(n))) * 8);
  if (!s.buffers.densityResult) s.buffers.densityResult = createBuffer(*s.model.ctx, 16);
}
}  // namespace

void allocateGaussianBuffers(TrainSession& s) {
  allocateGaussianBatchBuffers(s);
  if (gaussianStepsOnDevice(s.model.config))
    s.buffers.gaussianOptimiser = createGaussianDeviceOptimiser(*s.model.ctx, uint32_t(s.model.gaussians.count()), kGaussianFloats);
  s.buffers.gaussianCopies = StepBuffers::Copies::HostNewer;  // the host's optimiser state is the one to upload
}

bool gaussianStepsOnDevice(const TrainConfig& c) { return !c.gaussiansFixed && c.densifyStrategy != DensifyStrategy::Mcmc; }

void pullGaussians(TrainSession& s) {
  if (s.buffers.gaussianCopies != StepBuffers::Copies::DeviceNewer) return;
  Context& ctx = *s.model.ctx;
  s.model.gaussians.params = downloadVector<float>(ctx, s.model.device.params, s.model.gaussians.params.size());
  downloadGaussianOptimiser(ctx, *s.buffers.gaussianOptimiser, s.state.gaussianAdam, s.state.densifyStats);
  s.buffers.gaussianCopies = StepBuffers::Copies::Same;
  validateGaussians(s.model.gaussians, "training");
}

void pushGaussians(TrainSession& s) {
  if (s.buffers.gaussianCopies != StepBuffers::Copies::HostNewer) return;
  validateGaussians(s.model.gaussians, "training");
  updateGaussians(*s.model.ctx, s.model.device, s.model.gaussians);
  if (s.buffers.gaussianOptimiser) uploadGaussianOptimiser(*s.model.ctx, *s.buffers.gaussianOptimiser, s.state.gaussianAdam, s.state.densifyStats);
  s.buffers.gaussianCopies = StepBuffers::Copies::Same;
}

void ensureRayCapacity(TrainSession& s, uint32_t n) {
  if (n <= s.model.capacity && n <= s.buffers.capacity) return;
  pushWaterGradient(s);  // a larger model capacity creates the surface anew
  growModelRayCapacity(s.model, n);
  if (n > s.buffers.capacity) allocateBatchBuffers(s, n);
}

// Checkpoint steps reorder too, so a resumed run starts from the same proxy order.
bool proxyReorderAt(const TrainSession& s, int t) {
  return t % kProxyReorderInterval == 0 || (s.model.config.checkpointEvery > 0 && t % s.model.config.checkpointEvery == 0);
}

void syncGaussians(TrainSession& s, bool countChanged) {
  if (countChanged && s.buffers.gaussianCopies == StepBuffers::Copies::DeviceNewer) {
    // densified on the device (densifyOnDeviceStep): its rows are the run's, the host's stale
    allocateGaussianBatchBuffers(s);
    s.model.proxies = buildGaussianProxies(*s.model.ctx, s.model.tracer, s.model.device, s.model.proxyKind, true);
    return;
  }
  if (countChanged) {
    validateGaussians(s.model.gaussians, "training");
    uploadModelGaussians(s.model);
    allocateGaussianBuffers(s);
    pushGaussians(s);
    return;
  }
  pushGaussians(s);  // after a host step; a device step left the device's copy current
  if (proxyReorderAt(s, s.model.step))
    reorderGaussianProxies(*s.model.ctx, s.model.tracer, s.model.proxies, s.model.device);  // no pull of the optimiser's state
  else
    updateGaussianProxies(*s.model.ctx, s.model.tracer, s.model.proxies, s.model.device, false);
}

namespace {

// The views a check's or the sweep loss's plane sweep looks through at most: the sweep's time
// grows with views x pixels x planes; a capture of a hundred views checks through twelve (the
// synthetic rigs have 8 to 25).
constexpr size_t kMaxSweepViews = 12;

// The training views a sweep looks through: all, or `maxViews` > 0 of them spread evenly.
std::vector<size_t> sweepViewIndices(const TrainSession& s, size_t maxViews) {
  const size_t n = s.dataset.split("train").size();
  return spreadViewIndices(n, maxViews > 0 ? std::min(maxViews, n) : n);
}

// The camera's rays, one per pixel, into s.model.rays and (through the water) into
// s.model.refracted with their records; returns their count.
uint32_t traceCameraThroughWater(TrainSession& s, const HeightSource& heights, const Camera& camera) {
  const uint32_t n = uint32_t(camera.width * camera.height);
  ensureRayCapacity(s, n);
  submitAndWait(*s.model.ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, s.model.rayPipelines, camera, s.model.rays, 0.0f, 1e6f); });
  if (s.model.surface) traceSurface(*s.model.ctx, *s.model.surface, heights, s.model.rays, n, s.model.refracted, s.model.records);
  return n;
}

// Every training view's rays, one per pixel, as they leave the water as the surface is lifted
// now (straight for --no-refraction), for the plane sweep; `heights` is the source the surface
// was lifted from (its subdivision evaluates it).
// `maxViews` > 0: only that many, spread evenly over the training views (spreadViewIndices).
std::vector<SweepView> sweepViews(TrainSession& s, const HeightSource& heights, size_t maxViews = 0) {
  std::vector<SweepView> views;
  pushWaterGradient(s);  // whole images may not fit the surface's point cache beside the batch's points
  for (size_t k : sweepViewIndices(s, maxViews)) {
    const uint32_t n = traceCameraThroughWater(s, heights, s.dataset.split("train")[k].camera);
    views.push_back({downloadVector<GpuRay>(*s.model.ctx, s.model.surface ? s.model.refracted : s.model.rays, n), &s.dataset.split("train")[k].image});
  }
  return views;
}
std::vector<SweepView> sweepViews(TrainSession& s) { return s.model.surface ? sweepViews(s, currentHeightSource(s.model)) : sweepViews(s, HeightSource{}); }

// The plane sweep over the Gaussians' box.
PlaneSweepConfig boxSweepConfig(const TrainConfig& c) {
  PlaneSweepConfig pc;
  pc.xMin = c.boxMin[0];
  pc.yMin = c.boxMin[1];
  pc.zMin = c.boxMin[2];
  pc.xMax = c.boxMax[0];
  pc.yMax = c.boxMax[1];
  pc.zMax = c.boxMax[2];
  return pc;
}

// The Gaussians drawn uniformly in the box, with fresh Adam moments, learning-rate schedules
// and densification statistics: at step 0, and again at --restart-gaussians with the surface
// kept. Why the restart: the first Gaussians fit the views through the still-flat water and
// absorb most of its distortion as a warped scene, which stalls the surface at about half the
// true amplitude; fresh Gaussians under a surface that has learned leave the rest of the
// distortion to it (docs/experiments/2026-11-25-density-resets-and-restarts.md, measured on the strong-wave scene).
//
// --init-depth sweep draws their depths from a plane sweep of the training views through the
// water as it is now (flat at step 0, learned at a restart).
void drawGaussians(TrainSession& s) {
  const TrainConfig& c = s.model.config;
  if (!c.gaussiansFrom.empty()) {
    s.model.gaussians = readGaussiansPly(c.gaussiansFrom);
    if (s.model.gaussians.count() != c.initialGaussians)
      fail("--gaussians-from " + c.gaussiansFrom + " now holds " + std::to_string(s.model.gaussians.count()) + " Gaussians, the run started from " +
           std::to_string(c.initialGaussians));
    validateGaussians(s.model.gaussians, c.gaussiansFrom.c_str());
    s.log.gaussiansAtPoints = 0;
    s.state.gaussianAdam = createGaussianAdam(c.extent, c.schedule.lrSteps, s.model.gaussians.count());
    s.state.densifyStats.assign(s.model.gaussians.count() * 2, 0.0f);
    return;
  }
  GaussianSet atPoints;
  s.log.gaussiansAtPoints = 0;
  if (c.initPoints)
    atPoints = initialGaussiansAtPoints(s.state.rng, c.initialGaussians, s.dataset.points, c.waterHeight, c.ior, c.boxMin, c.boxMax,
                                        c.initialDensity, s.log.gaussiansAtPoints);
  const size_t rest = c.initialGaussians - s.log.gaussiansAtPoints;
  if (rest == 0) {
    s.model.gaussians = std::move(atPoints);
  } else if (c.initDepth == InitDepth::Sweep) {
    DepthMap depth = planeSweepDepth(sweepViews(s), boxSweepConfig(c));
    size_t known = 0;
    for (double z : depth.z) known += std::isfinite(z) ? 1 : 0;
    s.log.sweptCellFraction = double(known) / double(std::max<size_t>(1, depth.z.size()));
    s.model.gaussians = initialGaussiansOnDepth(s.state.rng, rest, c.boxMin, c.boxMax, c.initialDensity, depth);
  } else {
    s.model.gaussians = initialGaussians(s.state.rng, rest, c.boxMin, c.boxMax, c.initialDensity);
  }
  if (rest > 0) s.model.gaussians.params.insert(s.model.gaussians.params.begin(), atPoints.params.begin(), atPoints.params.end());
  s.state.gaussianAdam = createGaussianAdam(c.extent, c.schedule.lrSteps, s.model.gaussians.count());
  s.state.densifyStats.assign(s.model.gaussians.count() * 2, 0.0f);
}

// --surface-until N ends the water's learning with its last surface step at or before N, so
// no step after it adds to a sum that no surface step would apply (0: never ends); a refit
// ends it at the run's `steps` at the latest (its Gaussians learn under the water held).
int lastWaterStep(const TrainSession& s) {
  const TrainConfig& c = s.model.config;
  const int freeze = c.schedule.surfaceFreeze;
  int until = c.schedule.surfaceUntil;
  if (c.schedule.refitSteps > 0) until = until == 0 ? c.steps : std::min(until, c.steps);
  if (until == 0) return std::numeric_limits<int>::max();
  return freeze + (until - freeze) / surfaceBatchSteps(s) * surfaceBatchSteps(s);
}

}  // namespace

std::unique_ptr<TrainSession> createTrainSession(Context& ctx, const TrainConfig& config, Dataset dataset) {
  validateTrainConfig(config);
  auto s = std::make_unique<TrainSession>();
  // The model: tracer, ray buffers, the water in its initial state lifted into the surface.
  initModel(s->model, ctx, config, dataset);
  s->dataset = std::move(dataset);
  s->state.rng.seed(uint32_t(config.seed * 2654435761u + 17u));
  DensifyConfig& dc = s->densifyConfig;
  const ScheduleSteps& k = config.schedule;
  // 3DGS measures "large" against the cameras' spread; cameras close together over a wide
  // scene (the downward grids of the NeRFrac-like data: spread 0.3, scene 2 x 2) would make
  // every initial Gaussian "large" and prune it, so the scene box's half-diagonal bounds it too.
  double halfDiagonal = 0.5 * std::sqrt(std::pow(config.boxMax[0] - config.boxMin[0], 2) + std::pow(config.boxMax[1] - config.boxMin[1], 2) +
                                        std::pow(config.boxMax[2] - config.boxMin[2], 2));
  dc.sceneExtent = float(std::max(config.extent, halfDiagonal));
  dc.densifyFrom = uint32_t(k.densifyFrom);
  dc.densifyUntil = uint32_t(k.densifyUntil);
  dc.densifyInterval = uint32_t(std::max(1, k.densifyInterval));
  dc.gradThreshold = float(config.densifyGradThreshold);
  dc.pruneFrom = uint32_t(k.densifyFrom);
  dc.pruneUntil = uint32_t(k.densifyUntil);
  dc.pruneInterval = uint32_t(std::max(1, k.pruneInterval));
  dc.pruneLargeFromStep = uint32_t(k.pruneLargeFrom);
  dc.maxGaussians = config.maxGaussians;
  // Density decay every --density-decay-every steps, resets every --density-reset-every
  // steps before --density-reset-until (applyDensitySchedule); an interval of 0: never. As in
  // 3DGS, the reset belongs to the densification strategy (it lets pruning remove Gaussians
  // that do not regain density): without densification it only costs steps.
  constexpr uint32_t kNever = 0xFFFFFFFFu;
  dc.decayFactor = float(config.densityDecay);
  dc.decayFloor = 1e-6f;  // a density driven toward zero stays where Adam can bring it back
  dc.decayFrom = k.densityDecayInterval > 0 ? 0 : kNever;
  dc.decayInterval = uint32_t(std::max(1, k.densityDecayInterval));
  dc.resetDensity = float(config.densityResetValue);
  // MCMC keeps every Gaussian (it relocates the transparent ones), so it resets no density.
  const bool mcmc = config.densifyStrategy == DensifyStrategy::Mcmc;
  dc.resetFrom = config.densify && !mcmc && k.densityResetInterval > 0 ? 0 : kNever;
  dc.resetUntil = uint32_t(std::max(0, k.densityResetUntil - 1));
  dc.resetInterval = uint32_t(std::max(1, k.densityResetInterval));
  validateDensifyConfig(dc);
  s->mcmcConfig.maxGaussians = config.maxGaussians;
  validateMcmcConfig(s->mcmcConfig);
  if (s->model.surface && lastWaterStep(*s) <= k.surfaceFreeze)
    fail((k.surfaceUntil > 0 ? "--surface-until " + std::to_string(k.surfaceUntil) : "--steps " + std::to_string(config.steps) + " (--refit)") +
         " leaves the surface no step: it learns after --surface-freeze (" + std::to_string(k.surfaceFreeze) + ") once every " +
         std::to_string(surfaceBatchSteps(*s)) + " steps (--surface-batch)");

  allocateBatchBuffers(*s, s->model.capacity);
  s->buffers.lossPipelines = createLossPipelines(ctx);
  s->buffers.copyPipeline = createStridedCopyPipeline(ctx);
  s->buffers.lossResult = createBuffer(ctx, 16);
  s->buffers.stepScalars = createBuffer(ctx, 16, 0, MemoryUse::Readback);
  s->buffers.lossLog = createBuffer(ctx, VkDeviceSize(kLossLogRows) * 8, 0, MemoryUse::Readback);
  s->water.adamPipelines = createAdamPipelines(ctx);
  if (s->model.height) {
    // Lavapipe builds a pipeline at its first dispatch (a second or more for the MLP's
    // backward, even from Mesa's disk cache): here, not inside the first surface step.
    warmUpHeightField(*s->model.height);
    s->water.heightAdam = createAdamGroup(ctx, "height_mlp", surfaceLearningRate(config), 1, uint32_t(s->model.height->parameterCount));
    s->water.heightGrad = createBuffer(ctx, s->model.height->parameterCount * 4);
    fillBuffer(ctx, s->water.heightGrad, 0);
  }
  if (config.model == WaterModel::FlatWater) {
    AdamColumns height;
    height.name = "water_height";
    height.width = 1;
    height.lr = surfaceLearningRate(config);
    s->water.planeAdam = createTableAdam(1, {height}, 1);
  }
  // After the water: the plane sweep (--init-depth sweep) looks through it. Nothing above
  // draws from s->state.rng, so the box's draw is what it was before the sweep existed.
  drawGaussians(*s);
  uploadModelGaussians(s->model);
  allocateGaussianBuffers(*s);
  shuffleViews(*s);
  return s;
}

namespace {

// dL/d(plane height): every lattice height is the one plane height, so the derivative is
// the sum of dL/dheight over every lattice point the backward touched.
double planeHeightGradient(TrainSession& s) {
  WaterSurface& ws = *s.model.surface;
  if (ws.addedPending) submitAndWait(*s.model.ctx, [&](VkCommandBuffer cb) { cmdApplyAddedGradient(cb, ws); });
  SurfaceCounters c = readSurfaceCounters(*s.model.ctx, ws);
  double sum = 0;
  for (float g : downloadVector<float>(*s.model.ctx, ws.gridGrad, ws.gridPointCount))
    if (std::isfinite(g)) sum += g;
  for (float g : downloadVector<float>(*s.model.ctx, ws.pointGrad, c.points))
    if (std::isfinite(g)) sum += g;
  return sum;
}

// viewWeights over the training views, computed once per surface grid (the anchor, the level
// prior and the divergence check weigh the water by how many training views see it).
const std::vector<double>& trainViewWeights(TrainSession& s) {
  if (s.water.viewWeights.size() != s.model.surface->gridPointCount) s.water.viewWeights = viewWeights(s.model, s.dataset.split("train"));
  return s.water.viewWeights;
}

void planeAdamStep(TrainSession& s, double grad) {
  std::vector<float> height{float(s.model.planeHeight)};
  tableAdamStep(s.water.planeAdam, height, {float(grad)});
  s.model.planeHeight = height[0];
  s.model.plane.waves.base = height[0];
}

}  // namespace

// Records, after a lift of the surface in cb, the copy of its coarse grid's heights to where
// the host reads them (liftedHeights); call noteLiftedHeights after the submission's wait.
void cmdCopyLiftedHeights(VkCommandBuffer cb, TrainSession& s, Buffer* to) {
  WaterSurface& ws = *s.model.surface;
  const VkDeviceSize bytes = VkDeviceSize(ws.gridPointCount) * 4;
  for (Buffer* b : {&s.water.liftedHeights, to})
    if (b && (!b->buffer || b->size < bytes)) *b = createBuffer(*s.model.ctx, bytes, 0, MemoryUse::Readback);
  cmdBarrier(cb);
  cmdCopyToHost(cb, ws.gridHeights, 0, to ? *to : s.water.liftedHeights, 0, bytes);
}
void noteLiftedHeights(TrainSession& s) { s.water.liftedHeightsVersion = s.model.surface->heightsVersion; }

// The surface's coarse grid heights as lifted now: the copy its last lift left the host, or a
// download where that lift made none (a restart's sweep, a loaded checkpoint).
std::vector<float> liftedGridHeights(TrainSession& s) {
  WaterSurface& ws = *s.model.surface;
  if (s.water.liftedHeightsVersion != ws.heightsVersion) return downloadVector<float>(*s.model.ctx, ws.gridHeights, ws.gridPointCount);
  const float* mapped = static_cast<const float*>(s.water.liftedHeights.mapped);
  return std::vector<float>(mapped, mapped + ws.gridPointCount);
}

void anchorMeanHeight(TrainSession& s) {
  if (!s.model.config.anchorMeanHeight || !s.model.height || !s.model.surface) return;
  const double shift = meanHeightShift(s.model, liftedGridHeights(s), trainViewWeights(s));
  if (shift == 0) return;
  HeightField& hf = *s.model.height;
  hf.config.initialHeight = float(double(hf.config.initialHeight) + shift);
  submitAndWait(*s.model.ctx, [&](VkCommandBuffer cb) {
    cmdUpdateSurface(cb, *s.model.surface, hf);
    cmdCopyLiftedHeights(cb, s, nullptr);
  });
  noteLiftedHeights(s);
}

namespace {

// Where the surface's coarse grid vertices lie in its gridHeights.
GridLayout coarseGridLayout(const TrainSession& s) {
  const WaterSurface& ws = *s.model.surface;
  const Rect& d = s.model.config.domain;
  GridLayout g;
  g.cellsX = ws.cellsX;
  g.cellsY = ws.cellsY;
  g.rowLength = ws.cellsX + 3;  // the border ring
  g.first = g.rowLength + 1;
  g.spacingX = (d.xMax - d.xMin) / ws.cellsX;
  g.spacingY = (d.yMax - d.yMin) / ws.cellsY;
  return g;
}

// The priors (--surface-smoothness, --level-prior) of the surface as lifted now: their energy
// and dE/dheight at the coarse grid's vertices, kept in the session until the heights change.
void computeSurfacePrior(TrainSession& s) {
  WaterSurface& ws = *s.model.surface;
  const GridLayout g = coarseGridLayout(s);
  std::vector<float> heights = liftedGridHeights(s);
  s.water.priorGrad.assign(heights.size(), 0.0f);
  s.water.priorEnergy = 0;
  if (s.model.config.surfaceSmoothness > 0) s.water.priorEnergy += slopePrior(heights, g, s.model.config.surfaceSmoothness, &s.water.priorGrad);
  if (s.model.config.levelPrior > 0) {
    s.water.priorEnergy += levelPrior(heights, g, trainViewWeights(s), s.model.config.levelPrior, &s.water.priorGrad,
                                  s.model.config.levelPriorTiltOnly ? 1 : s.model.config.levelPriorDegree, s.model.config.levelPriorWarpShare);
  }
  s.water.priorHeightsVersion = ws.heightsVersion;
}

bool priorOn(const TrainSession& s) { return s.model.height && s.model.surface && (s.model.config.surfaceSmoothness > 0 || s.model.config.levelPrior > 0); }
// The priors of the surface as it is now (computed once per lift).
void ensureSurfacePrior(TrainSession& s) {
  if (s.water.priorHeightsVersion != s.model.surface->heightsVersion) computeSurfacePrior(s);
}

// The Gaussians' schedule counts from the refit's start in the refit (gaussianScheduleStep).
uint32_t gaussianStepAt(const TrainSession& s, int t) { return uint32_t(gaussianScheduleStep(s.model.config, t)); }

void applyDensitySchedule(TrainSession& s, int t) {
  if (densityDecayDue(s.densifyConfig, gaussianStepAt(s, t))) densityDecay(s.model.gaussians, s.densifyConfig);
  if (densityResetDue(s.densifyConfig, gaussianStepAt(s, t))) {
    densityReset(s.model.gaussians, s.densifyConfig);
    resetAdamColumns(s.state.gaussianAdam, "density");
  }
}

}  // namespace

int surfaceBatchSteps(const TrainSession& s) { return surfaceBatchSteps(s.model.config, s.dataset.split("train").size()); }

StepBatch nextStepBatch(TrainSession& s) {
  const auto& trainViews = s.dataset.split("train");
  if (s.state.viewCursor >= s.state.viewOrder.size()) shuffleViews(s);
  StepBatch b;
  b.view = s.state.viewOrder[s.state.viewCursor++];
  const Camera& cam = trainViews[b.view].camera;
  b.width = uint32_t(cam.width);
  b.height = uint32_t(cam.height);
  const uint32_t p = s.model.config.patch;
  b.patch = p > 0 && (p < b.width || p < b.height);
  if (b.patch) {
    b.width = std::min(p, b.width);
    b.height = std::min(p, b.height);
    b.x0 = uint32_t(s.state.rng() % (uint32_t(cam.width) - b.width + 1));
    b.y0 = uint32_t(s.state.rng() % (uint32_t(cam.height) - b.height + 1));
  }
  return b;
}

TraceOptions stepTraceOptions(TrainSession& s, const StepBatch& b, int t) {
  const TrainConfig& c = s.model.config;
  TraceOptions opt;
  for (int ch = 0; ch < 3; ch++) opt.background[ch] = float(c.datasetOptions.background[ch]);
  opt.shDegree = shDegreeAt(c, t);
  // Densification statistics from the camera, not from where refracted rays start (the water).
  opt.statisticsViewpoint = glm::vec3(s.dataset.split("train")[b.view].camera.cameraToWorld[3]);
  if (c.hitRecordsPerRay > 0) {
    // sized by the rays of a step (a patch, not the largest image): 8 bytes per record
    if (s.buffers.hitRecords.rays < b.rays()) s.buffers.hitRecords = createHitRecords(*s.model.ctx, b.rays(), c.hitRecordsPerRay);
    opt.hitRecords = &s.buffers.hitRecords;
  }
  if (s.model.surface) s.model.surface->config.faceNormals = t <= c.schedule.faceNormalsUntil;
  return opt;
}

// A deferred step is submitted into its slot and not waited for (submitWithoutWait); once it
// has run, its stages are added to the profile and the host's part of it runs (slot.finish).
using DeferredSubmitter = std::function<void(const std::function<void(VkCommandBuffer)>&)>;
DeferredSubmitter deferredSubmitter(TrainSession& s) {
  Context& ctx = *s.model.ctx;
  StepBuffers::StepSlot& slot = s.buffers.slots[size_t(s.deferredSlot)];
  if (!slot.submit.cb) slot.submit = createSubmitSlot(ctx);
  GpuProfiler* profiler = ctx.profiler;
  return [&ctx, &slot, profiler](const std::function<void(VkCommandBuffer)>& record) {
    submitWithoutWait(
        ctx, slot.submit,
        [&](VkCommandBuffer cb) {
          profileSubmitBegin(cb, ctx, slot.timer);
          record(cb);
        },
        [profiler, &slot] {
          if (profiler) profileSubmitDone(*profiler, slot.timer);
          if (slot.finish) std::exchange(slot.finish, nullptr)();
        });
  };
}

BatchForward forwardBatch(TrainSession& s, const StepBatch& b, const TraceOptions& opt,
                          const std::function<void(VkCommandBuffer, const BatchContext&)>& then, bool readRendered) {
  Context& ctx = *s.model.ctx;
  const View& view = s.dataset.split("train")[b.view];
  const Camera& cam = view.camera;
  const uint32_t n = b.rays();
  ensureRayCapacity(s, n);
  BatchForward f;
  f.context = {b, opt, &s.model.rays, s.model.surface ? &s.model.refracted : &s.model.rays, &s.model.results, &s.buffers.dLoss, s.model.surface ? &s.model.records : nullptr};
  f.target.resize(size_t(n) * 3);
  // A masked view: its target and its rendering both times the mask, and the loss's gradient
  // too (the SSIM window reaches across the mask's edge), so the pixels that do not count add
  // nothing to the loss's gradient, nor, in the backward, to the Gaussians, the water or
  // densification's statistics.
  const bool masked = !view.mask.pixels.empty();
  if (masked) f.weight.resize(n);
  std::vector<uint32_t> pixelList(b.patch ? n : 0);
  for (uint32_t y = 0; y < b.height; y++)
    for (uint32_t x = 0; x < b.width; x++) {
      uint32_t i = y * b.width + x;
      if (b.patch) pixelList[i] = (b.y0 + y) * uint32_t(cam.width) + b.x0 + x;
      const float w = masked ? view.mask.at(int(b.x0 + x), int(b.y0 + y), 0) : 1.0f;
      if (masked) f.weight[i] = w;
      for (int ch = 0; ch < 3; ch++) f.target[3 * i + ch] = w * view.image.at(int(b.x0 + x), int(b.y0 + y), ch);
    }
  // Copied at the head of the first submission below (cameraRays): no submission of their own.
  // A deferred step's go through its slot's area: the last step may still read the buffers.
  const bool deferred = s.deferredSlot >= 0;
  RecordedUploads& uploads = deferred ? s.buffers.slots[size_t(s.deferredSlot)].uploads : s.buffers.uploads;
  uploads.alwaysStaged = deferred;
  reserveUploads(ctx, uploads, {f.target.size() * 4, f.weight.size() * 4, pixelList.size() * 4});
  stageUpload(ctx, uploads, s.buffers.target, f.target.data(), f.target.size() * 4);
  if (masked) stageUpload(ctx, uploads, s.buffers.pixelWeights, f.weight.data(), f.weight.size() * 4);
  const Buffer* weights = masked ? &s.buffers.pixelWeights : nullptr;
  if (b.patch) stageUpload(ctx, uploads, s.buffers.pixels, pixelList.data(), pixelList.size() * 4);

  prepareImageLossScratch(ctx, s.buffers.lossScratch, b.width, b.height, 3);

  // One submission from the camera rays to the loss's gradient (and `then`), the surface
  // trace's level submissions in between: the stages hand their buffers on on the device.
  auto cameraRays = [&](VkCommandBuffer cb) {
    cmdFlushUploads(cb, uploads);
    if (b.patch)
      cmdCameraRaysForPixels(cb, s.model.rayPipelines, cam, s.buffers.pixels, n, s.model.rays, 0.0f, 1e6f);
    else
      cmdCameraRays(cb, s.model.rayPipelines, cam, s.model.rays, 0.0f, 1e6f);
    profileStage(cb, ctx, "camera rays");
  };
  auto gaussiansAndLoss = [&](VkCommandBuffer cb) {
    cmdBarrier(cb);
    cmdTraceForward(cb, s.model.tracer, s.model.proxies, s.model.device, s.model.surface ? s.model.refracted : s.model.rays, s.model.results, n, opt);
    profileStage(cb, ctx, "gaussian forward");
    cmdBarrier(cb);
    cmdCopyStrided(cb, s.buffers.copyPipeline, s.model.results, {kTraceResultFloats, 0}, s.buffers.rendered, {3, 0}, 3, n, weights);
    cmdImageLoss(cb, s.buffers.lossPipelines, s.buffers.lossScratch, s.buffers.rendered, s.buffers.target, s.buffers.lossGrad, s.buffers.lossResult);
    cmdBarrier(cb);
    cmdCopyToHost(cb, s.buffers.lossResult, 0, s.buffers.stepScalars, 0, 4);
    cmdCopyToHost(cb, s.buffers.lossResult, 0, s.buffers.lossLog, lossLogOffset(s.model.step), 4);
    // dL/d(rgb, opacity): the opacity's stays 0, the background is part of rgb
    cmdCopyStrided(cb, s.buffers.copyPipeline, s.buffers.lossGrad, {3, 0}, s.buffers.dLoss, {4, 0}, 3, n, weights);
    cmdBarrier(cb);
    profileStage(cb, ctx, "loss");
    if (then) then(cb, f.context);
  };
  const auto submitDeferred = deferred ? deferredSubmitter(s) : DeferredSubmitter{};
  if (s.model.surface) {
    if (!surfaceCacheHasRoom(*s.model.surface, n)) pushWaterGradient(s);
    SurfaceTraceHooks hooks{cameraRays, gaussiansAndLoss, submitDeferred};
    traceSurface(ctx, *s.model.surface, currentHeightSource(s.model), s.model.rays, n, s.model.refracted, s.model.records, nullptr, hooks);
  } else {
    const auto record = [&](VkCommandBuffer cb) {
      cameraRays(cb);
      gaussiansAndLoss(cb);
    };
    if (deferred) submitDeferred(record);
    else submitAndWait(ctx, record);
  }
  if (deferred) {  // nothing of it read now: readStepLosses, later
    f.imageLoss = NAN;
    return f;
  }
  if (readRendered) f.rendered = downloadVector<float>(ctx, s.buffers.rendered, size_t(n) * 3);
  f.imageLoss = static_cast<const float*>(s.buffers.stepScalars.mapped)[0];
  return f;
}

void cmdBackwardBatch(VkCommandBuffer cb, TrainSession& s, const BatchContext& f, bool surfaceLearns) {
  cmdTraceBackward(cb, s.model.tracer, s.model.proxies, s.model.device, *f.tracedRays, *f.results, *f.dLoss, s.buffers.grads, s.buffers.stats, s.buffers.rayGrads, f.rays(),
                   f.options);
  profileStage(cb, *s.model.ctx, "gaussian backward");
  if (surfaceLearns) {
    if (!f.surfaceRecords) fail("the water's backward of a batch traced without water");
    cmdBackwardSurfaceToHeights(cb, *s.model.surface, *f.cameraRays, *f.surfaceRecords, s.buffers.rayGrads, f.rays());
  }
}

namespace {

// Steps at which the water learns, and the steps that end a surface batch (one Adam step on
// the gradient summed over the batch).
bool waterLearnsAt(const TrainSession& s, int t) {
  return s.model.surface && s.model.config.model != WaterModel::KnownWater && t > s.model.config.schedule.surfaceFreeze && t <= lastWaterStep(s);
}
bool surfaceStepAt(const TrainSession& s, int t) {
  return waterLearnsAt(s, t) && (t - s.model.config.schedule.surfaceFreeze) % surfaceBatchSteps(s) == 0;
}

// Stops training (refrax::Error) when the water the training views see has left the scene:
// a height outside the span from the bottom of the Gaussians' box to the lowest training
// camera, or not finite. A diverged surface (too fast a learning rate) otherwise trains on
// with every ray missing it and ends as a normal run.
void requireSurfaceInScene(TrainSession& s, int t, const std::vector<float>& heights) {
  const std::vector<double>& weights = trainViewWeights(s);
  double low = INFINITY, high = -INFINITY;
  bool finite = true;
  for (size_t k = 0; k < heights.size(); k++)
    if (weights[k] > 0) {
      finite = finite && std::isfinite(heights[k]);
      low = std::min(low, double(heights[k]));
      high = std::max(high, double(heights[k]));
    }
  double lowestCamera = INFINITY;
  for (const View& v : s.dataset.split("train")) lowestCamera = std::min(lowestCamera, v.camera.position().z);
  const double bottom = s.model.config.boxMin[2];
  if (finite && low > bottom && high < lowestCamera) {
    s.log.surfaceShape = measureSurfaceShape(heights, coarseGridLayout(s), weights);
    s.log.surfaceShapeMeasured = true;
    return;
  }
  // The advice names only what the run does not already use.
  char remedy[160];
  if (s.model.config.surfaceBatch == 1)
    std::snprintf(remedy, sizeof remedy, "a lower --surface-lr (now %g) or --surface-batch views keeps the surface in the scene",
                  s.model.config.surfaceLearningRate);
  else
    std::snprintf(remedy, sizeof remedy, "a lower --surface-lr (now %g, with one surface step per %d steps) may keep the surface in the scene",
                  s.model.config.surfaceLearningRate, surfaceBatchSteps(s));
  char text[640];
  std::snprintf(text, sizeof text,
                "the water surface diverged at step %d: the heights the training views see run from %.3g to %.3g m%s, outside the scene "
                "between the Gaussians' box bottom (z = %.3g) and the lowest camera (z = %.3g); %s",
                t, low, high, finite ? "" : " (some not finite)", bottom, lowestCamera, remedy);
  fail(text);
}
void requireSurfaceInScene(TrainSession& s, int t) { requireSurfaceInScene(s, t, liftedGridHeights(s)); }

// The plane sweep through the water lifted from `heights` (sweepThroughWater, below).
DepthMap sweepThroughWater(TrainSession& s, const HeightSource& heights, PlaneSweepConfig& pc);
DepthMap sweepThroughFlatWater(TrainSession& s, PlaneSweepConfig& pc);

// Before the learned water is replaced (the gate's restart, the watch's rollback): its pending
// gradient is settled and dropped with the water it was for, and its Adam's first moments
// cleared (they point the way it ran); the second moments are kept, being blind to the
// direction.
void dropWaterMomentum(TrainSession& s) {
  pushWaterGradient(s);
  fillBuffer(*s.model.ctx, s.water.heightGrad, 0);
  fillBuffer(*s.model.ctx, s.water.heightAdam.m, 0);
}

// --sweep-loss: weight * the mean over the sweep views' rays of |I - T(x)|^2 (sweep_loss.h),
// its dL/d(refracted ray) taken by the surface's backward into the height field's gradient,
// one view at a time (a whole image's points beside another's may not fit the point cache).
// One pass: each view is traced once, its rays scored against the colours the views agreed on
// at the last application (T lags one surface step) and their colours gathered for the next;
// the depths come from a full plane sweep every kSweepDepthEvery applications (a sweep is one
// pass per plane: 128 where this is one). The views are traced at half their resolution, each
// ray a 2 x 2 block's mean colour (boxDownscaled): the strong wave's test PSNR and surface were
// within the seeds' spread of full resolution's (median 18.14 against 18.04 dB, seeds 1-3), its
// run about 0.7x as long; a quarter lost 0.9 dB (docs/experiments/2026-12-05-water-valley.md).
constexpr int kSweepLossDownscale = 2;
void addSweepLossGradient(TrainSession& s, int t, double weight) {
  constexpr int kSweepDepthEvery = 10;
  Context& ctx = *s.model.ctx;
  WaterLearning& w = s.water;
  const HeightSource heights = currentHeightSource(s.model);
  if (w.sweepMap.z.empty() || w.sweepApplications % kSweepDepthEvery == 0) {
    PlaneSweepConfig pc = boxSweepConfig(s.model.config);
    w.sweepMap = sweepThroughWater(s, heights, pc);
  }
  w.sweepApplications++;
  pushWaterGradient(s);  // the batch's pending gradient first: a whole image's points may not fit the cache beside it
  const std::vector<View>& train = s.dataset.split("train");
  if (w.sweepLossCameras.empty())
    for (size_t k : sweepViewIndices(s, kMaxSweepViews)) {
      w.sweepLossCameras.push_back(downscaledCamera(train[k].camera, kSweepLossDownscale));
      w.sweepLossImages.push_back(boxDownscaled(train[k].image, kSweepLossDownscale));
    }
  size_t total = 0;  // the rays of every view: the loss is their mean
  for (const Camera& c : w.sweepLossCameras) total += size_t(c.width) * size_t(c.height);
  AgreedColours colours;
  RunLog::SweepLossPoint point;
  point.step = t;
  double loss = 0;
  for (size_t v = 0; v < w.sweepLossCameras.size(); v++) {
    const uint32_t n = traceCameraThroughWater(s, heights, w.sweepLossCameras[v]);
    const SweepView view{downloadVector<GpuRay>(ctx, s.model.refracted, n), &w.sweepLossImages[v]};
    std::vector<GpuRayGrad> grads;
    size_t used = 0;
    loss += sweepTextureLoss(view, w.sweepMap, weight / double(std::max<size_t>(total, 1)), grads, used);
    addViewColours(view, w.sweepMap, colours);
    point.rays += used;
    if (used == 0) continue;
    upload(ctx, s.buffers.rayGrads, grads.data(), grads.size() * sizeof(GpuRayGrad));
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBackwardSurfaceToHeights(cb, *s.model.surface, s.model.rays, s.model.records, s.buffers.rayGrads, n); });
    pushWaterGradient(s);
  }
  setAgreedColours(w.sweepMap, colours, PlaneSweepConfig{}.minViews);
  point.perRay = point.rays > 0 ? loss / double(point.rays) : 0.0;
  s.log.sweepLosses.push_back(point);
}

// One surface step at step t: the priors' gradient for the batch's steps, the batch's
// dL/dheight into the parameters, one Adam step, and the surface lifted again (the next
// encoding window, the mean height anchored). The heights do not change between surface
// steps, so the batch's gradient is the sum of its steps' gradients at one surface.
// Its parts: the host's gradients (the sweep loss, the priors), the device's update (after the
// push), and the host's checks of the heights it lifted. A step whose surface step needs no
// tracing of its own (no sweep loss due) records the update into the batch's submission
// (surfaceStepInBatch, trainStep).
int surfaceBatchStepsAt(const TrainSession& s, int t) { return std::min(surfaceBatchSteps(s), t - s.model.config.schedule.surfaceFreeze); }

bool sweepLossAt(const TrainSession& s, int t) {
  const int surfaceSteps = (t - s.model.config.schedule.surfaceFreeze) / surfaceBatchSteps(s);
  return s.model.config.sweepLoss > 0 && s.model.height && surfaceSteps % s.model.config.sweepLossEvery == 0;
}

void addSurfacePriorGradient(TrainSession& s, int t) {
  if (!priorOn(s)) return;
  HostStage h(*s.model.ctx, "water prior (host)");
  ensureSurfacePrior(s);
  addGridGradient(*s.model.ctx, *s.model.surface, s.water.priorGrad, double(surfaceBatchStepsAt(s, t)));
}

// After the push: the water's Adam step, the next encoding window, the surface lifted and its
// coarse heights copied where the host reads them.
void cmdWaterAdamAndLift(VkCommandBuffer cb, TrainSession& s, int t, Buffer* liftedTo = nullptr) {
  AdamSettings settings;
  settings.agreementPower = s.model.config.surfaceAgreement;
  cmdBarrier(cb);
  cmdAdamStep(cb, s.water.adamPipelines, s.water.heightAdam, s.model.height->weights, s.water.heightGrad, 0, true, settings);
  cmdBarrier(cb);
  profileStage(cb, *s.model.ctx, "water adam");
  s.model.height->config.encodingWindow = encodingWindowAfterStep(s.model.config, t, surfaceBatchSteps(s));
  cmdUpdateSurface(cb, *s.model.surface, *s.model.height);
  cmdCopyLiftedHeights(cb, s, liftedTo);
}

// After the lift's wait: the mean height anchored and the heights checked.
void finishSurfaceStep(TrainSession& s, int t) {
  if (s.model.height) {
    noteLiftedHeights(s);
    HostStage h(*s.model.ctx, "water anchor (host)");
    anchorMeanHeight(s);
  }
  HostStage h(*s.model.ctx, "water divergence check (host)");
  requireSurfaceInScene(s, t);
}

void surfaceStep(TrainSession& s, int t) {
  if (sweepLossAt(s, t)) {
    HostStage h(*s.model.ctx, "sweep loss");
    addSweepLossGradient(s, t, s.model.config.sweepLoss * double(surfaceBatchStepsAt(s, t)));
  }
  addSurfacePriorGradient(s, t);
  if (s.model.height) {
    // the push, the water's Adam step and the surface update in one submission
    // (pushSurfaceGradients: two where the push's count must be read back)
    pushWaterGradient(s, [&](VkCommandBuffer cb) { cmdWaterAdamAndLift(cb, s, t); });
  } else {
    pushWaterGradient(s);
    planeAdamStep(s, s.water.planeGrad);
    s.water.planeGrad = 0;
    liftSurface(s.model);
  }
  finishSurfaceStep(s, t);
}

// Whether step t's surface step is recorded into its batch's submission: the height field
// learns (the flat plane's step is the host's), and no sweep loss traces views of its own first.
bool surfaceStepInBatch(const TrainSession& s, int t) {
  return s.surfaceStepInBatch && surfaceStepAt(s, t) && s.model.height && !sweepLossAt(s, t);
}

// The density regulariser (docs/method.md, the opacity term of the loss) on the device, after
// the backward: its gradient added to the table's dL/dlogit in place, its value left in
// densityResult for gaussianStep.
void cmdDensityLoss(VkCommandBuffer cb, TrainSession& s) {
  if (!(s.model.config.densityLossWeight > 0)) return;
  cmdDensityRegularizer(cb, s.buffers.lossPipelines, s.model.device.params, s.model.device.count, s.buffers.grads, s.buffers.densityPartials, s.buffers.densityResult,
                        float(s.model.config.densityLossWeight), kGaussianFloats, f32::kGaussLogitDensity);
  cmdBarrier(cb);
  cmdCopyToHost(cb, s.buffers.densityResult, 0, s.buffers.stepScalars, 4, 4);
  cmdCopyToHost(cb, s.buffers.densityResult, 0, s.buffers.lossLog, lossLogOffset(s.model.step) + 4, 4);
  profileStage(cb, *s.model.ctx, "density regulariser");
}

// The Gaussians' step after the backward (whose gradient holds the density regulariser's,
// cmdDensityLoss): Adam and the density schedule (host). Returns the regulariser's value.
// The batch's rays scale the densification statistic (densifyStatScale): the loss is a mean
// over the batch, so each ray's gradient shrinks as the batch grows.
double gaussianStep(TrainSession& s, int t, uint32_t batchRays) {
  Context& ctx = *s.model.ctx;
  const TrainConfig& c = s.model.config;
  if (s.buffers.gaussianOptimiser) {  // stepped in the batch's command buffer (cmdGaussianStep)
    s.buffers.gaussianCopies = StepBuffers::Copies::DeviceNewer;
    if (s.deferredSlot >= 0) return NAN;  // not run yet: readStepLosses
    return c.densityLossWeight > 0 ? static_cast<const float*>(s.buffers.stepScalars.mapped)[1] : 0.0;
  }
  pullGaussians(s);
  std::vector<float> grads = downloadVector<float>(ctx, s.buffers.grads, s.model.gaussians.params.size());
  std::vector<float> stats = downloadVector<float>(ctx, s.buffers.stats, s.model.gaussians.count() * 2);
  const double densityLoss = c.densityLossWeight > 0 ? static_cast<const float*>(s.buffers.stepScalars.mapped)[1] : 0.0;
  if (c.gaussiansFixed) return densityLoss;  // a study of the water alone: the Gaussians stay as read
  HostStage h(ctx, "gaussian adam (host)");
  const float statScale = densifyStatScale(batchRays);
  for (size_t i = 0; i < stats.size(); i += 2) {
    s.state.densifyStats[i] += stats[i] * statScale;  // the gradient statistic
    s.state.densifyStats[i + 1] += stats[i + 1];      // the count of rays
  }
  tableAdamStep(s.state.gaussianAdam, s.model.gaussians.params, grads);
  if (c.densify && c.densifyStrategy == DensifyStrategy::Mcmc)
    mcmcPositionNoise(s.model.gaussians, s.mcmcConfig, groupLearningRate(s.state.gaussianAdam, "position"), s.state.rng);
  applyDensitySchedule(s, t);
  s.buffers.gaussianCopies = StepBuffers::Copies::HostNewer;
  return densityLoss;
}

// The Gaussians' step in the batch's command buffer, after the backward (gaussianStep reads
// the density loss after it).
void cmdGaussianDeviceStep(VkCommandBuffer cb, TrainSession& s, int t, uint32_t batchRays) {
  GaussianStepEvents events;
  events.decay = densityDecayDue(s.densifyConfig, gaussianStepAt(s, t));
  events.reset = densityResetDue(s.densifyConfig, gaussianStepAt(s, t));
  events.statScale = densifyStatScale(batchRays);
  cmdBarrier(cb);
  cmdGaussianStep(cb, *s.buffers.gaussianOptimiser, s.state.gaussianAdam, s.model.device.params, s.buffers.grads, s.buffers.stats, events,
                  s.densifyConfig);
  profileStage(cb, *s.model.ctx, "gaussian adam");
}

// MCMC relocation and growth when due; true when rows were added or moved (relocated rows
// jump across the scene: the proxies are rebuilt rather than refitted).
bool mcmcStep(TrainSession& s, int t) {
  if (!densifyDue(s.densifyConfig, gaussianStepAt(s, t))) return false;
  HostStage h(*s.model.ctx, "densification (host)");
  std::vector<uint32_t> rowMap;
  s.log.lastMcmc = mcmcDensify(s.model.gaussians, s.mcmcConfig, s.state.rng, rowMap);
  remapTableAdamRows(s.state.gaussianAdam, rowMap);
  s.state.densifyStats.assign(rowMap.size() * 2, 0.0f);  // unused by MCMC; kept one pair per Gaussian
  return s.log.lastMcmc.after != s.log.lastMcmc.before || s.log.lastMcmc.relocated > 0;
}

// The schedule's events after step t, one test each for the step that acts on it and for
// hostGaussianEventAt.
bool cloneSplitAt(const TrainSession& s, int t) {
  const TrainConfig& c = s.model.config;
  return c.densify && c.schedule.densifyInterval > 0 && densifyDue(s.densifyConfig, gaussianStepAt(s, t));
}
bool pruneAt(const TrainSession& s, int t) {
  const TrainConfig& c = s.model.config;
  return c.densify && c.schedule.pruneInterval > 0 && pruneDue(s.densifyConfig, gaussianStepAt(s, t));
}
bool restartAt(const TrainSession& s, int t) {
  const std::vector<int>& restarts = s.model.config.schedule.gaussianRestarts;
  return std::find(restarts.begin(), restarts.end(), t) != restarts.end();
}

// Whether the host changes the Gaussians after step t (densification, a restart) or orders
// their proxies (on a CPU device): otherwise the step's command buffer refits or reorders the
// proxies itself.
bool hostGaussianEventAt(const TrainSession& s, int t) {
  return cloneSplitAt(s, t) || pruneAt(s, t) || restartAt(s, t) || (proxyReorderAt(s, t) && !s.model.tracer.orderOnDevice);
}

// Clone/split/prune on the device (densify_device.h), where the run steps the Gaussians there
// and orders their proxies there (a GPU): nothing is read back but the counts. The host's
// copies follow the count only (the device's values are pulled when the host needs them).
// True when the table's rows changed.
bool densifyOnDeviceStep(TrainSession& s, int t) {
  Context& ctx = *s.model.ctx;
  pushGaussians(s);  // what the host changed since, before the device densifies
  HostStage h(ctx, "densification (device)");
  if (!s.buffers.densifyPipelines) s.buffers.densifyPipelines = createDeviceDensifyPipelines(ctx);
  const DensifyStats& d = s.log.lastDensify = densifyOnDevice(ctx, *s.buffers.densifyPipelines, s.model.device, *s.buffers.gaussianOptimiser,
                                                              s.densifyConfig, gaussianStepAt(s, t), s.state.rng);
  const size_t n = d.after;
  s.model.gaussians.params.resize(n * kGaussianFloats);
  s.state.gaussianAdam.m.resize(n * kGaussianFloats);
  s.state.gaussianAdam.v.resize(n * kGaussianFloats);
  s.state.densifyStats.resize(2 * n);
  s.buffers.gaussianCopies = StepBuffers::Copies::DeviceNewer;
  return d.prunedLowDensity + d.prunedLarge + d.cloned + d.split > 0;
}

// Clone/split/prune when due (3DGS strategy), or MCMC's relocation and growth; true when the
// table's rows changed.
bool densifyStep(TrainSession& s, int t) {
  const TrainConfig& c = s.model.config;
  if (c.gaussiansFixed) return false;
  if (c.densifyStrategy == DensifyStrategy::Mcmc) return c.densify && c.schedule.densifyInterval > 0 && mcmcStep(s, t);
  const bool cloneSplit = cloneSplitAt(s, t), prune = pruneAt(s, t);
  if (!cloneSplit && !prune) return false;
  if (s.buffers.gaussianOptimiser && s.model.tracer.orderOnDevice) return densifyOnDeviceStep(s, t);
  pullGaussians(s);
  s.buffers.gaussianCopies = StepBuffers::Copies::HostNewer;  // the statistics restart, rows move
  HostStage h(*s.model.ctx, "densification (host)");
  size_t before = s.model.gaussians.count();
  std::vector<uint32_t> rowMap;
  s.log.lastDensify = densify(s.model.gaussians, s.state.densifyStats, s.densifyConfig, gaussianStepAt(s, t), s.state.rng, rowMap);
  remapTableAdamRows(s.state.gaussianAdam, rowMap);
  // The statistics restart after a clone/split (3DGS); a prune alone keeps the survivors'.
  std::vector<float> kept(rowMap.size() * 2, 0.0f);
  if (!cloneSplit)
    for (size_t i = 0; i < rowMap.size(); i++)
      if (rowMap[i] != kNewRow) {
        kept[2 * i] = s.state.densifyStats[2 * rowMap[i]];
        kept[2 * i + 1] = s.state.densifyStats[2 * rowMap[i] + 1];
      }
  s.state.densifyStats = std::move(kept);
  bool identity = rowMap.size() == before;
  for (size_t i = 0; identity && i < rowMap.size(); i++) identity = rowMap[i] == i;
  return !identity;  // new rows: re-upload and rebuild the proxies
}

// --water-sign-check: the learned water's mirror image kept when the views agree clearly more
// through it. The MLP's first Adam moments are zeroed (the old direction points back to the
// old sign); the second moments are kept, being blind to the sign and the gradients' scale.
void checkWaterSign(TrainSession& s, int t) {
  WaterSignCheck check;
  check.step = t;
  check.flat = agreementWithFlatWater(s);  // recorded: does the learned water already fit worse than flat water?
  check.agreement = agreementOfMirror(s);
  const SweepAgreement& a = check.agreement;
  check.mirrored = a.cells > 0 && a.cost < kMirrorBetter * a.reference;
  if (check.mirrored) {
    mirrorHeightField(*s.model.ctx, *s.model.height, s.model.config.waterHeight);
    fillBuffer(*s.model.ctx, s.water.heightAdam.m, 0);
    liftSurface(s.model);
    anchorMeanHeight(s);
  }
  s.log.signChecks.push_back(check);
}

// --water-scale-search: the learned relief scaled about the water height by the candidate the
// views agree best through. Adam's first moments are zeroed when the water changes, as the
// sign check does; the weights of each candidate are set from the learned ones, so a scale of
// 0 loses nothing.
void searchWaterScale(TrainSession& s, int t) {
  Context& ctx = *s.model.ctx;
  HeightField& hf = *s.model.height;
  const double level = s.model.config.waterHeight;
  const std::vector<float> learned = downloadWeights(ctx, hf);
  const float learnedInitial = hf.config.initialHeight;
  auto setScale = [&](double scale) {
    uploadWeights(ctx, hf, learned);
    hf.config.initialHeight = learnedInitial;
    if (scale != 1.0) scaleHeightField(ctx, hf, level, scale);
  };
  WaterScaleSearch search;
  search.step = t;
  PlaneSweepConfig pc = boxSweepConfig(s.model.config);
  const DepthMap reference = sweepThroughWater(s, currentHeightSource(s.model), pc);
  double best = 1.0, bestRatio = 1.0;
  search.cells = reference.z.size();
  for (double scale : kWaterScales) {
    double ratio = 1.0;
    if (scale != 1.0) {
      setScale(scale);
      const SweepAgreement a = compareSweepCosts(sweepThroughWater(s, currentHeightSource(s.model), pc), reference);
      ratio = a.cells > 0 && a.reference > 0 ? a.cost / a.reference : INFINITY;
      search.cells = std::min(search.cells, a.cells);
    }
    search.ratios.push_back(ratio);
    if (ratio < bestRatio) best = scale, bestRatio = ratio;
  }
  search.chosen = bestRatio < kWaterScaleBetter ? best : 1.0;
  setScale(search.chosen);
  if (search.chosen != 1.0) fillBuffer(ctx, s.water.heightAdam.m, 0);
  liftSurface(s.model);
  anchorMeanHeight(s);
  s.log.scaleSearches.push_back(search);
}

// --surface-gate: the learned water starts again from flat when the views agree less through
// it than through flat water (its momentum dropped: dropWaterMomentum).
void gateWater(TrainSession& s, int t) {
  SurfaceGateCheck check;
  check.step = t;
  check.agreement = agreementWithFlatWater(s);
  const SweepAgreement& a = check.agreement;
  check.reset = a.cells > 0 && a.cost > s.model.config.surfaceGate * a.reference;
  if (check.reset) {
    dropWaterMomentum(s);
    restartHeightField(s.model);
    anchorMeanHeight(s);
  }
  s.log.gateChecks.push_back(check);
}

// --sweep-watch: every config.sweepWatch steps while the water learns, and at its last step
// (the run's last without --surface-until), so the water a run ends with has been checked.
bool sweepWatchAt(const TrainSession& s, int t) {
  const int every = s.model.config.sweepWatch;
  const int last = std::min(lastWaterStep(s), s.model.config.steps);
  return every > 0 && s.model.height && waterLearnsAt(s, t) && ((t - s.model.config.schedule.surfaceFreeze) % every == 0 || t == last);
}

// --sweep-watch's check: the views swept through the learned water against flat water (whose
// sweep is made once: it does not change). A water they agree on less than on flat water goes
// back to the best water of the checks so far, or to flat water at the water height; its
// momentum is dropped (dropWaterMomentum) and its learning rate halved, so that a water that
// keeps running away stops moving.
void watchWater(TrainSession& s, int t) {
  Context& ctx = *s.model.ctx;
  WaterLearning& w = s.water;
  HeightField& hf = *s.model.height;
  if (w.watchFlat.z.empty()) {
    w.watchGrid = boxSweepConfig(s.model.config);
    w.watchFlat = sweepThroughFlatWater(s, w.watchGrid);
  }
  SweepWatchCheck check;
  check.step = t;
  check.agreement = compareSweepCosts(sweepThroughWater(s, currentHeightSource(s.model), w.watchGrid), w.watchFlat);
  const SweepAgreement& a = check.agreement;
  const double ratio = a.cells > 0 && a.reference > 0 ? a.cost / a.reference : INFINITY;
  const SweepWatchVerdict verdict = sweepWatchVerdict(ratio, w.watchBest);
  if (verdict == SweepWatchVerdict::Best) {
    check.best = true;
    w.watchBest = ratio;
    w.watchBestWeights = downloadWeights(ctx, hf);
    w.watchBestInitialHeight = hf.config.initialHeight;
  } else if (verdict == SweepWatchVerdict::RollBack) {
    check.rolledBack = true;
    dropWaterMomentum(s);
    if (w.watchBestWeights.empty()) {
      // flat at the water height: the initial weights' own relief (--mlp-init-range) read
      // 1.02-1.08x flat water's cost on dev 9, where every check found the learned water worse
      scaleHeightField(ctx, hf, s.model.config.waterHeight, 0.0);
    } else {
      uploadWeights(ctx, hf, w.watchBestWeights);
      hf.config.initialHeight = w.watchBestInitialHeight;
    }
    liftSurface(s.model);
    w.heightAdam.lr.initial *= 0.5;
    w.heightAdam.lr.final *= 0.5;
    anchorMeanHeight(s);
  }
  check.learningRateScale = w.heightAdam.lr.initial / surfaceLearningRate(s.model.config).initial;
  s.log.watchChecks.push_back(check);
}

// The Gaussians drawn afresh when the step is one of --restart-gaussians; true if so.
bool restartStep(TrainSession& s, int t) {
  if (!restartAt(s, t)) return false;
  HostStage h(*s.model.ctx, "restart and plane sweep");
  if (s.model.config.surfaceGate > 0 && s.model.height && waterLearnsAt(s, t)) gateWater(s, t);
  if (s.model.config.waterSignCheck && s.model.height && waterLearnsAt(s, t)) checkWaterSign(s, t);
  if (s.model.config.waterScaleSearch && s.model.height && waterLearnsAt(s, t)) searchWaterScale(s, t);
  if (s.model.config.restartGate > 0 && s.model.height) {
    RestartGateCheck check;
    check.step = t;
    check.agreement = agreementWithFlatWater(s);
    check.restarted = restartGatePasses(check.agreement, s.model.config.restartGate);
    s.log.restartGateChecks.push_back(check);
    if (!check.restarted) return false;
  }
  drawGaussians(s);
  s.buffers.gaussianCopies = StepBuffers::Copies::HostNewer;  // the fresh draw is the host's
  return true;
}

// The refit's start, before the first step after `steps`: the Gaussians drawn afresh under the
// water as learned (which no longer learns), their schedule counted from here. Before the
// step rather than after the last, so an evaluation or checkpoint at `steps` holds the
// run's own Gaussians.
void startRefit(TrainSession& s) {
  HostStage h(*s.model.ctx, "refit draw");  // no water gradient is pending: the water stopped at or before `steps`
  drawGaussians(s);
  s.buffers.gaussianCopies = StepBuffers::Copies::HostNewer;
  syncGaussians(s, true);
}

// The plane sweep through the water lifted from `heights` (left lifted from it), on pc's grid;
// a pc without a cell size gets these views' (so a second sweep compares on the same grid),
// through kMaxSweepViews views at most.
DepthMap sweepThroughWater(TrainSession& s, const HeightSource& heights, PlaneSweepConfig& pc) {
  pushWaterGradient(s);
  submitAndWait(*s.model.ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *s.model.surface, heights); });
  std::vector<SweepView> views = sweepViews(s, heights, kMaxSweepViews);
  if (!(pc.cellSize > 0)) pc.cellSize = sweepCellSize(views, 0.5 * (pc.zMin + pc.zMax));
  return planeSweepDepth(views, pc);
}

// The plane sweep through flat water at the configured water height, on pc's grid (set from
// these views when pc has no cell size): the reference the learned water is compared with.
DepthMap sweepThroughFlatWater(TrainSession& s, PlaneSweepConfig& pc) {
  AnalyticWaves level;
  level.base = float(s.model.config.waterHeight);
  AnalyticHeightField flat = createAnalyticHeightField(*s.model.ctx, level);
  return sweepThroughWater(s, heightSource(flat), pc);
}

}  // namespace

// How much more than flat water's sweep cost --sweep-watch lets pass: on dev 7 (whose water the
// views leave flat) seven checks read 1.0004-1.0042, the runs that ran away 1.03-1.17.
constexpr double kWatchTolerance = 1.01;

bool restartGatePasses(const SweepAgreement& a, double gate) { return a.cells == 0 || a.cost < gate * a.reference; }

SweepWatchVerdict sweepWatchVerdict(double ratio, double best) {
  if (ratio < best) return SweepWatchVerdict::Best;
  return ratio > kWatchTolerance ? SweepWatchVerdict::RollBack : SweepWatchVerdict::Keep;
}

SweepAgreement agreementWithFlatWater(TrainSession& s) {
  if (!s.model.surface) fail("agreementWithFlatWater: the model has no water");
  PlaneSweepConfig pc = boxSweepConfig(s.model.config);  // one grid for both: the flat water's cell size
  const DepthMap reference = sweepThroughFlatWater(s, pc);
  return compareSweepCosts(sweepThroughWater(s, currentHeightSource(s.model), pc), reference);
}

SweepAgreement agreementOfMirror(TrainSession& s) {
  if (!s.model.surface || !s.model.height) fail("agreementOfMirror: the model has no learned height field");
  PlaneSweepConfig pc = boxSweepConfig(s.model.config);
  const DepthMap learned = sweepThroughWater(s, currentHeightSource(s.model), pc);
  const float initialHeight = s.model.height->config.initialHeight;
  mirrorHeightField(*s.model.ctx, *s.model.height, s.model.config.waterHeight);
  const SweepAgreement a = compareSweepCosts(sweepThroughWater(s, currentHeightSource(s.model), pc), learned);
  mirrorHeightField(*s.model.ctx, *s.model.height, s.model.config.waterHeight);  // back: negation is exact,
  s.model.height->config.initialHeight = initialHeight;               // the reflected constant maybe not
  liftSurface(s.model);
  return a;
}

void pushWaterGradient(TrainSession& s, const std::function<void(VkCommandBuffer)>& then) {
  const bool pending = s.model.surface && s.model.surface->gradientPending;
  if (pending && s.model.height)
    return pushSurfaceGradients(*s.model.ctx, *s.model.surface, heightSource(*s.model.height, s.water.heightGrad), then);
  if (pending) {  // the flat plane: its one parameter's gradient is summed on the host
    s.water.planeGrad += planeHeightGradient(s);
    s.model.surface->gradientPending = false;
  }
  if (then) submitAndWait(*s.model.ctx, then);
}

// A deferred water step's lift: the lifted heights go to its slot's buffer (the next step's
// lift may be in flight when this one's are read), and the host's checks of them run once the
// step has run (slot.finish).
void cmdDeferredWaterAdamAndLift(VkCommandBuffer cb, TrainSession& s, int t) {
  StepBuffers::StepSlot& slot = s.buffers.slots[size_t(t % 2)];
  cmdWaterAdamAndLift(cb, s, t, &slot.liftedHeights);
  const uint64_t version = s.model.surface->heightsVersion;
  slot.finish = [&s, &slot, t, version] {
    const uint32_t n = s.model.surface->gridPointCount;
    const float* lifted = static_cast<const float*>(slot.liftedHeights.mapped);
    std::memcpy(s.water.liftedHeights.mapped, lifted, size_t(n) * 4);
    s.water.liftedHeightsVersion = version;
    HostStage h(*s.model.ctx, "water divergence check (host)");
    requireSurfaceInScene(s, t, std::vector<float>(lifted, lifted + n));
  };
}

// The rest of a water step recorded in the batch whose push was not: the count read back and
// the push (listed), or the Adam step alone (nothing was pending), then the host's checks.
void finishWaterStepAfterWait(TrainSession& s, int t, bool listed) {
  const auto adamAndLift = [&](VkCommandBuffer cb) { cmdWaterAdamAndLift(cb, s, t); };
  if (listed)
    pushListedSurfaceGradients(*s.model.ctx, *s.model.surface, heightSource(*s.model.height, s.water.heightGrad), adamAndLift);
  else
    pushWaterGradient(s, adamAndLift);
  finishSurfaceStep(s, t);
}

// Whether step t is submitted without waiting (TrainSession::deferSteps): nothing the host does
// after it at this step reads what it computes. Not where the host changes the Gaussians or
// checks or steps the water, reads the batch for the progress line, or a batch of a new size
// reallocates buffers; not where the water's trace takes several submissions or must empty a
// cache holding a gradient; and every syncEvery steps, so the surface watch's loss is whole.
bool deferredStepAt(const TrainSession& s, int t, const StepBatch& b, bool progressDue, bool proxiesInBatch) {
  const TrainConfig& c = s.model.config;
  if (!s.deferSteps || !proxiesInBatch || progressDue || t == totalSteps(c) || t % std::max(1, s.syncEvery) == 0) return false;
  if (refitStartsAt(c, t) || refitStartsAt(c, t + 1)) return false;  // the refit's draw, said at its first step, follows the last
  // A water step only in the batch's submission, and without the anchor's re-lift or the priors
  // (which read its lifted heights before the next step is recorded).
  const bool waterStep = surfaceStepAt(s, t);
  if (waterStep && !(surfaceStepInBatch(s, t) && !c.anchorMeanHeight && !priorOn(s))) return false;
  if (sweepWatchAt(s, t) || restartAt(s, t)) return false;
  if (b.width != s.lastBatchWidth || b.height != s.lastBatchHeight || b.rays() > s.model.capacity) return false;
  if (!s.model.surface) return true;
  const WaterSurface& ws = *s.model.surface;
  return traceIsOneSubmission(ws, currentHeightSource(s.model), b.rays()) && surfaceCacheHasRoom(ws, b.rays());
}

StepLosses readStepLosses(TrainSession& s, int step) {
  waitInFlight(*s.model.ctx);
  const float* row = static_cast<const float*>(s.buffers.lossLog.mapped) + 2 * (uint32_t(step) % kLossLogRows);
  return {row[0], s.model.config.densityLossWeight > 0 ? row[1] : 0.0f};
}

TrainSession::~TrainSession() {
  if (!model.ctx) return;
  // The steps in flight, waited for; what their host parts would say is dropped (a session goes
  // while an error of an earlier step unwinds, and a destructor must not throw a second).
  while (!model.ctx->inFlight.empty()) {
    try {
      waitInFlight(*model.ctx);
    } catch (const std::exception&) {
    }
  }
  for (StepBuffers::StepSlot& slot : buffers.slots) destroySubmitSlot(*model.ctx, slot.submit);
}

StepResult trainStep(TrainSession& s) {
  auto start = std::chrono::steady_clock::now();
  const int t = ++s.model.step;
  const bool refitStart = refitStartsAt(s.model.config, t);
  if (refitStart) startRefit(s);
  const StepBatch batch = nextStepBatch(s);
  const TraceOptions opt = stepTraceOptions(s, batch, t);
  pushGaussians(s);  // what the host changed (a loaded checkpoint) before the device steps on it
  // The batch's PSNR is read back for the progress line only (StepResult::psnr).
  const bool progressDue = t % s.model.config.progressEvery == 0 || t == totalSteps(s.model.config);
  // A device step with nothing for the host to change after it refits the proxies in its own
  // command buffer: one submission fewer (issue 48).
  const bool proxiesInBatch = s.buffers.gaussianOptimiser.has_value() && !hostGaussianEventAt(s, t);
  double priorEnergy = 0;  // of the surface this step traces
  if (waterLearnsAt(s, t) && priorOn(s)) {
    HostStage h(*s.model.ctx, "water prior (host)");
    ensureSurfacePrior(s);
    priorEnergy = s.water.priorEnergy;
  }
  // The water's surface step in the batch's submission, after its backward: one submission a
  // step instead of two (issue 48). Where the push needs its count read back, the rest of it
  // follows the wait (pushListedSurfaceGradients).
  const bool surfaceInBatch = surfaceStepInBatch(s, t);
  enum class InBatchPush { None, Listed, Pushed } surfacePush = InBatchPush::None;
  const bool deferred = deferredStepAt(s, t, batch, progressDue, proxiesInBatch);
  s.deferredSlot = deferred ? t % 2 : -1;
  s.lastBatchWidth = batch.width;
  s.lastBatchHeight = batch.height;
  const BatchForward forward = forwardBatch(s, batch, opt, [&](VkCommandBuffer cb, const BatchContext& context) {
    if (surfaceInBatch) addSurfacePriorGradient(s, t);  // written before the backward that adds it is recorded
    vkCmdFillBuffer(cb, s.buffers.grads.buffer, 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cb, s.buffers.stats.buffer, 0, VK_WHOLE_SIZE, 0);
    cmdBarrier(cb);
    cmdBackwardBatch(cb, s, context, waterLearnsAt(s, t) && !s.model.config.sweepLossOnly);
    if (surfaceInBatch && s.model.surface->gradientPending) {
      const bool pushed = cmdListAndPushSurfaceGradients(cb, *s.model.surface, heightSource(*s.model.height, s.water.heightGrad),
                                                         cachedPointsBoundAfterTrace(*s.model.surface, context.rays()));
      surfacePush = pushed ? InBatchPush::Pushed : InBatchPush::Listed;
      if (pushed && deferred) cmdDeferredWaterAdamAndLift(cb, s, t);
      else if (pushed) cmdWaterAdamAndLift(cb, s, t);
    }
    cmdDensityLoss(cb, s);
    if (s.buffers.gaussianOptimiser) cmdGaussianDeviceStep(cb, s, t, batch.rays());
    if (proxiesInBatch) {
      cmdBarrier(cb);
      if (proxyReorderAt(s, t))
        cmdReorderGaussianProxies(cb, s.model.tracer, s.model.proxies, s.model.device);
      else
        cmdUpdateGaussianProxies(cb, s.model.tracer, s.model.proxies, s.model.device, false);
      profileStage(cb, *s.model.ctx, "gaussian proxies");
    }
  }, progressDue);
  StepResult r;
  // A water step in the batch whose push must read its count back: the rest of it now (waited for).
  if (surfaceInBatch && surfacePush != InBatchPush::Pushed) finishWaterStepAfterWait(s, t, surfacePush == InBatchPush::Listed);
  else if (surfaceInBatch && !deferred) finishSurfaceStep(s, t);
  if (deferred) {
    // Nothing more for the host at this step: the device steps the Gaussians and refits their
    // proxies in the batch's submission. The last step is waited for now that this one is
    // queued behind it.
    s.buffers.gaussianCopies = StepBuffers::Copies::DeviceNewer;
    s.deferredSlot = -1;
    waitInFlight(*s.model.ctx, 1);
    r.pending = true;
    r.loss = r.imageLoss = r.psnr = NAN;
    r.gaussians = uint32_t(s.model.gaussians.count());
    s.model.trainingSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  }
  if (s.model.surface) r.missed = s.model.surface->lastCounters.missed;  // before a restart's plane sweep traces again
  if (!surfaceInBatch && surfaceStepAt(s, t)) surfaceStep(s, t);
  if (sweepWatchAt(s, t)) {
    HostStage h(*s.model.ctx, "sweep watch");
    watchWater(s, t);
  }
  const double densityLoss = gaussianStep(s, t, batch.rays());
  const bool countChanged = densifyStep(s, t);
  r.restarted = restartStep(s, t);
  r.refitStarted = refitStart;
  {
    HostStage h(*s.model.ctx, "gaussian upload and proxies");
    if (!proxiesInBatch) syncGaussians(s, countChanged || r.restarted);
  }
  r.imageLoss = forward.imageLoss;
  r.loss = r.imageLoss + densityLoss + priorEnergy;
  r.psnr = progressDue ? batchPsnr(forward.rendered, forward.target, forward.weight) : NAN;
  r.gaussians = uint32_t(s.model.gaussians.count());
  if (!std::isfinite(r.loss)) fail("training diverged at step " + std::to_string(t) + ": the loss is not finite");
  s.model.trainingSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace refrax
