#include "engine/train/train_config.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"

namespace refrax {

const char* waterModelName(WaterModel model) {
  switch (model) {
    case WaterModel::Refraction: return "refraction";
    case WaterModel::NoRefraction: return "no-refraction";
    case WaterModel::FlatWater: return "flat-water";
    case WaterModel::KnownWater: return "known-water";
  }
  return "?";
}

WaterModel parseWaterModel(const std::string& name) {
  if (name == "refraction") return WaterModel::Refraction;
  if (name == "no-refraction") return WaterModel::NoRefraction;
  if (name == "flat-water") return WaterModel::FlatWater;
  if (name == "known-water") return WaterModel::KnownWater;
  fail("unknown water model '" + name + "' (refraction, no-refraction, flat-water)");
}

namespace {

void scaled(int& value, int reference, double scale, int minimum) {
  if (value < 0) value = std::max(minimum, int(std::lround(reference * scale)));
}

}  // namespace

void resolveSchedule(TrainConfig& c) {
  double s = double(c.steps) / 15000.0;
  ScheduleSteps& k = c.schedule;
  scaled(k.surfaceFreeze, 1000, s, 0);
  scaled(k.faceNormalsUntil, 7500, s, 0);
  scaled(k.octavesOpenUntil, 7500, s, 0);
  scaled(k.shDegreeInterval, 1000, s, 1);
  // Density events act through per-step learning rates (a Gaussian needs on the order of a
  // thousand steps to regain density after a reset at lr 0.05), so their intervals do not
  // shrink below what that recovery needs: decay and prune keep the reference intervals,
  // resets come at least 1,000 and clone/split at least 100 steps apart.
  scaled(k.densityResetInterval, 3000, s, 1000);
  scaled(k.densityResetUntil, 12000, s, 0);
  scaled(k.densityDecayInterval, 50, 1.0, 1);
  scaled(k.densifyFrom, 500, s, 0);
  scaled(k.densifyInterval, 300, s, 100);
  scaled(k.densifyUntil, 12000, s, 0);
  scaled(k.lrSteps, 30000, s, 1);
  scaled(k.pruneInterval, 100, 1.0, 1);
  scaled(k.pruneLargeFrom, 3000, s, 0);
}

float encodingWindowAt(const TrainConfig& c, int t) {
  if (c.mlpOctaves == 0 || c.mlpCoarseOctaves >= c.mlpOctaves) return 1.0f;
  int from = c.schedule.surfaceFreeze, until = c.schedule.octavesOpenUntil;
  double ramp = until > from ? std::clamp(double(t - from) / double(until - from), 0.0, 1.0) : (t >= until ? 1.0 : 0.0);
  double open = double(c.mlpCoarseOctaves) + ramp * double(c.mlpOctaves - c.mlpCoarseOctaves);
  return float(std::min(1.0, open / double(c.mlpOctaves)));
}

float encodingWindowAfterStep(const TrainConfig& c, int t, int surfaceBatchSteps) {
  // The window moves with the surface steps: the last one at or before t (none: the coarse window).
  const int freeze = c.schedule.surfaceFreeze, n = std::max(1, surfaceBatchSteps);
  const int lastSurfaceStep = t > freeze ? freeze + (t - freeze) / n * n : freeze;
  return encodingWindowAt(c, lastSurfaceStep > freeze ? lastSurfaceStep + 1 : 0);
}

void validateTrainConfig(const TrainConfig& c) {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) fail("training configuration: " + what);
  };
  need(c.steps >= 1, "--steps must be at least 1");
  need(c.initialGaussians >= 1, "--gaussians must be at least 1");
  need(c.maxGaussians >= c.initialGaussians, "--max-gaussians must be at least the initial count");
  need(c.initDepth == "box" || c.initDepth == "sweep", "--init-depth must be box or sweep, got " + c.initDepth);
  need(c.initialDensity > 0 && c.initialDensity < 1, "--initial-density must be in (0, 1)");
  need(c.maxShDegree <= 3, "--sh-degree must be 0..3");
  need(c.kBuffer >= 1 && c.kBuffer <= 64, "--k-buffer must be 1..64");
  need(c.hitRecordsPerRay <= 1024, "--hit-records must be 0..1024");
  need(c.mlpWidth >= 1 && c.mlpHiddenLayers >= 1 && c.mlpOctaves <= 16, "height field sizes (--mlp-width, --mlp-layers >= 1, --mlp-octaves <= 16)");
  need(std::isfinite(c.mlpInitRange) && c.mlpInitRange >= 0, "--mlp-init-range must be >= 0");
  need(std::isfinite(c.surfaceLearningRate) && c.surfaceLearningRate > 0 && c.surfaceLearningRate < 1, "--surface-lr must be in (0, 1)");
  need(c.surfaceBatch >= 0 && c.surfaceBatch <= 100000, "--surface-batch must be views or in [1, 100000]");
  need(std::isfinite(c.surfaceSmoothness) && c.surfaceSmoothness >= 0, "--surface-smoothness must be finite and >= 0");
  need(std::isfinite(c.levelPrior) && c.levelPrior >= 0, "--level-prior must be finite and >= 0");
  need(c.gridCells >= 1 && c.gridCells <= 4096, "--grid-cells must be 1..4096");
  need(c.subdivisionLevels <= 6, "--subdivision must be 0..6");
  need(std::isfinite(c.ior) && c.ior >= 1 && c.ior < 4, "the IOR must be in [1, 4)");
  need(std::isfinite(c.waterHeight), "the water height must be finite");
  need(c.domain.xMax > c.domain.xMin && c.domain.yMax > c.domain.yMin, "the surface domain is empty");
  for (int a = 0; a < 3; a++) need(c.boxMax[a] >= c.boxMin[a], "the initial Gaussian box is empty");
  need(c.densityDecay > 0 && c.densityDecay <= 1, "--density-decay must be in (0, 1]");
  need(std::isfinite(c.densityLossWeight) && c.densityLossWeight >= 0 && c.densityLossWeight <= 1000, "--density-loss must be in [0, 1000]");
  need(c.schedule.shDegreeInterval >= 1, "--sh-interval must be at least 1");
  need(c.schedule.lrSteps >= 1, "--lr-steps must be at least 1");
  for (int r : c.schedule.gaussianRestarts) need(r > 0 && r < c.steps, "--restart-gaussians must be steps after the first and before the last");
  need(c.progressEvery >= 1, "--progress-every must be at least 1");
  need(c.evalEvery >= 0 && c.checkpointEvery >= 0, "--eval-every and --checkpoint-every must be >= 0");
}

nlohmann::json trainConfigToJson(const TrainConfig& c) {
  nlohmann::json j;
  j["dataset"] = c.dataset;
  nlohmann::json d;
  d["background"] = {c.datasetOptions.background.x, c.datasetOptions.background.y, c.datasetOptions.background.z};
  d["llff_factor"] = c.datasetOptions.llffFactor;
  d["llff_hold"] = c.datasetOptions.llffHold;
  if (c.datasetOptions.ior) d["ior"] = *c.datasetOptions.ior;
  if (c.datasetOptions.waterHeight) d["water_height"] = *c.datasetOptions.waterHeight;
  if (c.datasetOptions.waterDepth) d["water_depth"] = *c.datasetOptions.waterDepth;
  if (c.datasetOptions.domain) {
    const Rect& r = *c.datasetOptions.domain;
    d["domain"] = {r.xMin, r.yMin, r.xMax, r.yMax};
  }
  j["dataset_options"] = d;
  j["model"] = waterModelName(c.model);
  j["steps"] = c.steps;
  j["seed"] = c.seed;
  j["ior"] = c.ior;
  j["water_height"] = c.waterHeight;
  j["depth"] = c.depth;
  j["extent"] = c.extent;
  j["domain"] = {c.domain.xMin, c.domain.yMin, c.domain.xMax, c.domain.yMax};
  j["box_min"] = {c.boxMin[0], c.boxMin[1], c.boxMin[2]};
  j["box_max"] = {c.boxMax[0], c.boxMax[1], c.boxMax[2]};
  j["initial_gaussians"] = c.initialGaussians;
  j["init_depth"] = c.initDepth;
  j["max_gaussians"] = c.maxGaussians;
  j["initial_density"] = c.initialDensity;
  j["max_sh_degree"] = c.maxShDegree;
  j["k_buffer"] = c.kBuffer;
  j["hit_records"] = c.hitRecordsPerRay;
  j["proxy"] = c.proxy;
  j["mlp_width"] = c.mlpWidth;
  j["mlp_hidden_layers"] = c.mlpHiddenLayers;
  j["mlp_octaves"] = c.mlpOctaves;
  j["mlp_coarse_octaves"] = c.mlpCoarseOctaves;
  j["anchor_mean_height"] = c.anchorMeanHeight;
  j["mlp_init_range"] = c.mlpInitRange;
  j["surface_lr"] = c.surfaceLearningRate;
  if (c.surfaceBatch == 0)
    j["surface_batch"] = "views";
  else
    j["surface_batch"] = c.surfaceBatch;
  j["surface_smoothness"] = c.surfaceSmoothness;
  j["level_prior"] = c.levelPrior;
  j["grid_cells"] = c.gridCells;
  j["subdivision_levels"] = c.subdivisionLevels;
  const ScheduleSteps& k = c.schedule;
  j["schedule"] = {{"surface_freeze", k.surfaceFreeze},         {"face_normals_until", k.faceNormalsUntil},
                   {"octaves_open_until", k.octavesOpenUntil},
                   {"sh_degree_interval", k.shDegreeInterval},  {"density_reset_interval", k.densityResetInterval},
                   {"density_reset_until", k.densityResetUntil}, {"density_decay_interval", k.densityDecayInterval},
                   {"densify_from", k.densifyFrom},             {"densify_interval", k.densifyInterval},
                   {"densify_until", k.densifyUntil},           {"lr_steps", k.lrSteps},
                   {"prune_interval", k.pruneInterval},         {"prune_large_from", k.pruneLargeFrom},
                   {"gaussian_restarts", k.gaussianRestarts}};
  j["densify"] = c.densify;
  j["densify_grad_threshold"] = c.densifyGradThreshold;
  j["density_decay"] = c.densityDecay;
  j["density_reset_value"] = c.densityResetValue;
  j["density_loss"] = c.densityLossWeight;
  j["patch"] = c.patch;
  j["train_views"] = c.trainViews;
  j["progress_every"] = c.progressEvery;
  j["eval_every"] = c.evalEvery;
  j["checkpoint_every"] = c.checkpointEvery;
  return j;
}

TrainConfig trainConfigFromJson(const nlohmann::json& j, const std::string& where) {
  TrainConfig c;
  try {
    c.dataset = j.at("dataset").get<std::string>();
    const auto& d = j.at("dataset_options");
    auto bg = d.at("background");
    c.datasetOptions.background = glm::dvec3(bg.at(0).get<double>(), bg.at(1).get<double>(), bg.at(2).get<double>());
    c.datasetOptions.llffFactor = d.at("llff_factor").get<int>();
    c.datasetOptions.llffHold = d.at("llff_hold").get<int>();
    if (d.contains("ior")) c.datasetOptions.ior = d["ior"].get<double>();
    if (d.contains("water_height")) c.datasetOptions.waterHeight = d["water_height"].get<double>();
    if (d.contains("water_depth")) c.datasetOptions.waterDepth = d["water_depth"].get<double>();
    if (d.contains("domain")) {
      auto r = d["domain"];
      c.datasetOptions.domain = Rect{r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>(), r.at(3).get<double>()};
    }
    c.model = parseWaterModel(j.at("model").get<std::string>());
    c.steps = j.at("steps").get<int>();
    c.seed = j.at("seed").get<uint64_t>();
    c.ior = j.at("ior").get<double>();
    c.waterHeight = j.at("water_height").get<double>();
    c.depth = j.at("depth").get<double>();
    c.extent = j.at("extent").get<double>();
    auto r = j.at("domain");
    c.domain = Rect{r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>(), r.at(3).get<double>()};
    for (int a = 0; a < 3; a++) {
      c.boxMin[a] = j.at("box_min").at(a).get<double>();
      c.boxMax[a] = j.at("box_max").at(a).get<double>();
    }
    c.initialGaussians = j.at("initial_gaussians").get<uint32_t>();
    c.initDepth = j.value("init_depth", std::string("box"));  // runs written before the option: the box
    c.maxGaussians = j.at("max_gaussians").get<uint32_t>();
    c.initialDensity = j.at("initial_density").get<double>();
    c.maxShDegree = j.at("max_sh_degree").get<uint32_t>();
    c.kBuffer = j.at("k_buffer").get<uint32_t>();
    c.hitRecordsPerRay = j.value("hit_records", kDefaultHitRecordsPerRay);  // runs written before the option: the default
    c.proxy = j.at("proxy").get<std::string>();
    c.mlpWidth = j.at("mlp_width").get<uint32_t>();
    c.mlpHiddenLayers = j.at("mlp_hidden_layers").get<uint32_t>();
    c.mlpOctaves = j.at("mlp_octaves").get<uint32_t>();
    c.mlpCoarseOctaves = j.value("mlp_coarse_octaves", c.mlpOctaves);
    c.anchorMeanHeight = j.value("anchor_mean_height", false);  // runs written before the option: every octave open
    c.mlpInitRange = j.at("mlp_init_range").get<double>();
    c.surfaceLearningRate = j.value("surface_lr", 5e-4);  // runs written before the option: the reference
    // "views" is 0 in TrainConfig; anything but it or a count >= 1 is refused by the validation below.
    const nlohmann::json batch = j.value("surface_batch", nlohmann::json(1));
    c.surfaceBatch = batch == "views" ? 0 : batch.is_number_integer() && batch.get<long>() >= 1 ? int(std::min(batch.get<long>(), 1000000L)) : -1;
    c.surfaceSmoothness = j.value("surface_smoothness", 0.0);  // runs written before the option: no prior
    c.levelPrior = j.value("level_prior", 0.0);                // likewise
    c.gridCells = j.at("grid_cells").get<uint32_t>();
    c.subdivisionLevels = j.at("subdivision_levels").get<uint32_t>();
    const auto& s = j.at("schedule");
    ScheduleSteps& k = c.schedule;
    k.surfaceFreeze = s.at("surface_freeze").get<int>();
    k.faceNormalsUntil = s.at("face_normals_until").get<int>();
    k.octavesOpenUntil = s.value("octaves_open_until", 0);
    k.shDegreeInterval = s.at("sh_degree_interval").get<int>();
    k.densityResetInterval = s.at("density_reset_interval").get<int>();
    k.densityResetUntil = s.at("density_reset_until").get<int>();
    k.densityDecayInterval = s.at("density_decay_interval").get<int>();
    k.densifyFrom = s.at("densify_from").get<int>();
    k.densifyInterval = s.at("densify_interval").get<int>();
    k.densifyUntil = s.at("densify_until").get<int>();
    k.lrSteps = s.at("lr_steps").get<int>();
    k.pruneInterval = s.at("prune_interval").get<int>();
    k.pruneLargeFrom = s.at("prune_large_from").get<int>();
    // Runs written before the list held one step (0: none); runs before that, no restart.
    if (s.contains("gaussian_restarts")) k.gaussianRestarts = s.at("gaussian_restarts").get<std::vector<int>>();
    else if (s.value("gaussian_restart", 0) > 0) k.gaussianRestarts = {s.at("gaussian_restart").get<int>()};
    c.densify = j.at("densify").get<bool>();
    c.densifyGradThreshold = j.at("densify_grad_threshold").get<double>();
    c.densityDecay = j.at("density_decay").get<double>();
    c.densityResetValue = j.at("density_reset_value").get<double>();
    c.densityLossWeight = j.value("density_loss", 0.007);  // runs written before the option: the reference
    c.patch = j.at("patch").get<uint32_t>();
    c.trainViews = j.value("train_views", 0u);  // runs written before the option used every view
    c.progressEvery = j.at("progress_every").get<int>();
    c.evalEvery = j.at("eval_every").get<int>();
    c.checkpointEvery = j.at("checkpoint_every").get<int>();
  } catch (const nlohmann::json::exception& e) {
    fail(where + ": not a training configuration (" + e.what() + ")");
  }
  validateTrainConfig(c);
  return c;
}

}  // namespace refrax
