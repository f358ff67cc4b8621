#include "engine/frame/view_scene.h"

#include <algorithm>
#include <cstdio>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/model/open_model.h"
#include "engine/run/checkpoint_files.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace fs = std::filesystem;

namespace {

void collectCameras(ViewScene& scene) {
  scene.cameras.clear();
  for (const auto& [split, views] : scene.dataset.splits)
    for (size_t i = 0; i < views.size(); i++) {
      char name[64];
      std::snprintf(name, sizeof name, "%s %03zu", split.c_str(), i);
      scene.cameras.push_back({name, views[i].camera});
    }
}

}  // namespace

std::unique_ptr<ViewScene> openRunScene(Context& ctx, const std::string& runDir, uint32_t K) {
  if (!fs::is_directory(runDir)) fail(runDir + " is not a folder (expected a training run or --ply FILE)");
  TrainConfig config = readRunConfig(runDir);
  if (!fs::exists(config.dataset))
    fail("the dataset of run " + runDir + " (" + config.dataset + ") is missing: the run's checkpoints need it; its Gaussians alone are " +
         (fs::path(runDir) / "point_cloud.ply").string() + " (refrax-view --ply, refrax render-gaussians)");
  auto scene = std::make_unique<ViewScene>();
  scene->ctx = &ctx;
  scene->source = runDir;
  scene->runDir = runDir;
  scene->watch.runDir = runDir;
  markTaken(scene->watch, latestCheckpoint(runDir));
  scene->dataset = loadRunDataset(config);
  scene->model = openModel(ctx, runDir, scene->dataset);
  scene->generation = 1;
  scene->status = "loaded step " + std::to_string(scene->model->step);
  scene->lastPoll = std::chrono::steady_clock::now();
  const TrainConfig& c = scene->model->config;
  scene->domain = {float(c.domain.xMin), float(c.domain.yMin), float(c.domain.xMax), float(c.domain.yMax)};
  scene->waterHeight = float(c.waterHeight);
  scene->ior = float(c.ior);
  for (int ch = 0; ch < 3; ch++) scene->background[ch] = float(c.datasetOptions.background[ch]);
  scene->maxShDegree = c.maxShDegree;
  scene->proxyKind = scene->model->proxyKind;
  scene->tracer = createGaussianTracer(ctx, K);
  collectCameras(*scene);
  return scene;
}

std::unique_ptr<ViewScene> openPlyScene(Context& ctx, const std::string& plyPath, GaussianSet gaussians, uint32_t K, std::optional<SurfaceDomain> domain,
                                        float waterHeight, float ior) {
  auto scene = std::make_unique<ViewScene>();
  scene->ctx = &ctx;
  scene->source = plyPath;
  scene->plyGaussians = std::move(gaussians);
  if (scene->plyGaussians.count() == 0) fail(plyPath + " holds no Gaussians");
  validateGaussians(scene->plyGaussians, plyPath.c_str());
  scene->tracer = createGaussianTracer(ctx, K);
  scene->proxyKind = proxyKindFor("auto", ctx.caps);
  scene->plyDevice = uploadGaussians(ctx, scene->plyGaussians);
  scene->plyProxies = buildGaussianProxies(ctx, scene->tracer, scene->plyDevice, scene->plyGaussians, scene->proxyKind, false);
  scene->generation = 1;
  scene->status = "loaded " + std::to_string(scene->plyGaussians.count()) + " Gaussians";
  if (domain) {
    scene->domain = *domain;
  } else {
    float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
    for (size_t i = 0; i < scene->plyGaussians.count(); i++)
      for (int a = 0; a < 2; a++) {
        lo[a] = std::min(lo[a], scene->plyGaussians.at(i)[f32::kGaussMean + a]);
        hi[a] = std::max(hi[a], scene->plyGaussians.at(i)[f32::kGaussMean + a]);
      }
    float px = std::max(0.1f * (hi[0] - lo[0]), 1e-3f), py = std::max(0.1f * (hi[1] - lo[1]), 1e-3f);
    scene->domain = {lo[0] - px, lo[1] - py, hi[0] + px, hi[1] + py};
  }
  if (!(scene->domain.x1 > scene->domain.x0 && scene->domain.y1 > scene->domain.y0)) fail("--domain must be x0,y0,x1,y1 with x0 < x1, y0 < y1");
  scene->waterHeight = waterHeight;
  scene->ior = ior;
  return scene;
}

bool pollRunCheckpoint(ViewScene& scene, std::chrono::milliseconds interval) {
  if (!scene.model) return false;
  auto now = std::chrono::steady_clock::now();
  if (now - scene.lastPoll < interval) return false;
  scene.lastPoll = now;
  std::string newest = newerCheckpoint(scene.watch);
  if (newest.empty()) return false;
  try {
    loadModelCheckpoint(*scene.model, newest, scene.dataset);
  } catch (const Error& e) {
    scene.status = std::string("reload failed (retrying): ") + e.what();
    return false;
  }
  markTaken(scene.watch, newest);
  scene.generation++;
  scene.status = "loaded step " + std::to_string(scene.model->step);
  std::printf("refrax-view: loaded step %d (%s)\n", scene.model->step, newest.c_str());
  std::fflush(stdout);
  return true;
}

const DeviceGaussians& sceneGaussians(const ViewScene& s) { return s.model ? s.model->device : s.plyDevice; }
const GaussianProxies& sceneProxies(const ViewScene& s) { return s.model ? s.model->proxies : s.plyProxies; }
uint32_t sceneGaussianCount(const ViewScene& s) { return sceneGaussians(s).count; }

std::optional<HeightSource> learnedWater(const ViewScene& s) {
  if (!s.model || s.model->config.model == WaterModel::NoRefraction) return std::nullopt;
  return currentHeightSource(*s.model);
}

int sceneStep(const ViewScene& s) { return s.model ? s.model->step : -1; }

void setTracerK(ViewScene& s, uint32_t K) {
  if (K == s.tracer.K) return;
  if (K < 1 || K > 64) fail("K must be between 1 and 64");
  s.tracer = createGaussianTracer(*s.ctx, K);
}

}  // namespace refrax
