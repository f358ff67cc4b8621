#include "engine/run/train_config.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"
#include "engine/run/train_options.h"

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

int surfaceBatchSteps(const TrainConfig& c, size_t trainViews) { return c.surfaceBatch > 0 ? c.surfaceBatch : int(trainViews); }

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

int totalSteps(const TrainConfig& c) { return c.steps + c.schedule.refitSteps; }
int gaussianScheduleStep(const TrainConfig& c, int t) { return c.schedule.refitSteps > 0 && t > c.steps ? t - c.steps : t; }
bool refitStartsAt(const TrainConfig& c, int t) { return c.schedule.refitSteps > 0 && t == c.steps + 1; }

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

namespace {

// The JSON object a row's key lives in ("schedule/NAME": inside "schedule") and its name there.
std::pair<const nlohmann::json*, std::string> locate(const nlohmann::json& j, const std::string& key) {
  size_t slash = key.find('/');
  if (slash == std::string::npos) return {&j, key};
  const std::string parent = key.substr(0, slash);
  return {j.contains(parent) ? &j.at(parent) : nullptr, key.substr(slash + 1)};
}

}  // namespace

void validateTrainConfig(const TrainConfig& c) {
  auto need = [](bool ok, const std::string& what) {
    if (!ok) fail("training configuration: " + what);
  };
  // Every option's range (engine/run/train_options.cpp): each value through its checked setter.
  TrainConfig scratch = c;
  for (const TrainOption& o : trainOptionTable()) {
    if (o.key.empty()) continue;
    try {
      o.set(scratch, o.get(c), o.flag.empty() ? o.key : "--" + o.flag);
    } catch (const Error& e) {
      fail(std::string("training configuration: ") + e.what());
    }
  }
  // What relates one value to another, and the values resolved from the data.
  need(c.maxGaussians >= c.initialGaussians, "--max-gaussians must be at least the initial count");
  need(validIor(c.ior), std::string("the index of refraction must be ") + kIorRange);
  need(std::isfinite(c.waterHeight), "the water height must be finite");
  need(c.domain.xMax > c.domain.xMin && c.domain.yMax > c.domain.yMin, "the surface domain is empty");
  for (int a = 0; a < 3; a++) need(c.boxMax[a] >= c.boxMin[a], "the initial Gaussian box is empty");
  need(c.schedule.shDegreeInterval >= 1, "--sh-interval must be at least 1");
  need(c.schedule.lrSteps >= 1, "--lr-steps must be at least 1");
  need(c.schedule.refitSteps >= 0, "--refit must be a step count >= 0");
  need(c.schedule.refitSteps == 0 || !c.gaussiansFixed, "--refit draws the Gaussians afresh: not with --gaussians-fixed");
  if (c.schedule.refitSteps > 0) {
    // The refit runs the Gaussians' schedule sized for --steps again: it must outlast its last
    // densification, density reset and SH degree, or the run would end on one of them.
    const ScheduleSteps& k = c.schedule;
    int last = 1;
    if (c.densify) last = std::max(last, k.densifyUntil + 1);
    if (c.densify && k.densityResetInterval > 0) last = std::max(last, k.densityResetUntil);
    last = std::max(last, int(c.maxShDegree) * k.shDegreeInterval + 1);
    need(k.refitSteps >= last, "--refit " + std::to_string(k.refitSteps) + " ends before the Gaussians' schedule for --steps " +
                                   std::to_string(c.steps) + " does (its last densification, density reset or SH degree): at least " +
                                   std::to_string(last) + " steps");
  }
  need(c.schedule.surfaceUntil >= 0, "--surface-until must be a step count >= 0");
  need(c.schedule.surfaceUntil == 0 || c.schedule.surfaceUntil > c.schedule.surfaceFreeze,
       "--surface-until must come after --surface-freeze (" + std::to_string(c.schedule.surfaceFreeze) + "), or the surface never learns");
  for (int r : c.schedule.gaussianRestarts) need(r > 0 && r < c.steps, "--restart-gaussians must be steps after the first and before the last");
  need(c.restartGate == 0 || (c.model == WaterModel::Refraction && !c.schedule.gaussianRestarts.empty()),
       "--restart-gate needs a learned water (not --no-refraction, --flat-water or --known-water) and --restart-gaussians");
  need(c.surfaceGate == 0 || (c.model == WaterModel::Refraction && !c.schedule.gaussianRestarts.empty()),
       "--surface-gate needs a learned water (not --no-refraction, --flat-water or --known-water) and --restart-gaussians");
  need(c.knownWaterScale == 1 || c.model == WaterModel::KnownWater, "--known-water-scale needs --known-water");
  need(c.sweepLoss == 0 || c.model == WaterModel::Refraction, "--sweep-loss needs a learned water (not --no-refraction, --flat-water or --known-water)");
  need(!c.sweepLossOnly || c.sweepLoss > 0, "--sweep-loss-only needs --sweep-loss W above 0 (the water would not learn at all)");
  need(c.sweepWatch == 0 || c.model == WaterModel::Refraction, "--sweep-watch needs a learned water (not --no-refraction, --flat-water or --known-water)");
  need(!c.waterScaleSearch || (c.model == WaterModel::Refraction && !c.schedule.gaussianRestarts.empty()),
       "--water-scale-search needs a learned water (not --no-refraction, --flat-water or --known-water) and --restart-gaussians");
  need(!c.waterSignCheck || (c.model == WaterModel::Refraction && !c.schedule.gaussianRestarts.empty()),
       "--water-sign-check needs a learned water (not --no-refraction, --flat-water or --known-water) and --restart-gaussians");
}

void applyDerivedDefaults(TrainConfig& c, const std::function<bool(const std::string& key)>& given) {
  if (!given("max_gaussians")) c.maxGaussians = std::max(c.maxGaussians, c.initialGaussians);
  if (!given("mlp_coarse_octaves")) c.mlpCoarseOctaves = c.mlpOctaves;  // coarse-to-fine off
}

nlohmann::json trainConfigToJson(const TrainConfig& c) {
  nlohmann::json j;
  j["dataset"] = c.dataset;
  nlohmann::json d;
  d["background"] = {c.datasetOptions.background.x, c.datasetOptions.background.y, c.datasetOptions.background.z};
  d["llff_factor"] = c.datasetOptions.llffFactor;
  d["llff_hold"] = c.datasetOptions.llffHold;
  if (!c.datasetOptions.testViews.empty()) d["test_views"] = c.datasetOptions.testViews;
  if (c.datasetOptions.ior) d["ior"] = *c.datasetOptions.ior;
  if (c.datasetOptions.waterHeight) d["water_height"] = *c.datasetOptions.waterHeight;
  if (c.datasetOptions.waterDepth) d["water_depth"] = *c.datasetOptions.waterDepth;
  if (c.datasetOptions.domain) {
    const Rect& r = *c.datasetOptions.domain;
    d["domain"] = {r.xMin, r.yMin, r.xMax, r.yMax};
  }
  if (c.datasetOptions.up) d["up"] = {c.datasetOptions.up->x, c.datasetOptions.up->y, c.datasetOptions.up->z};
  j["dataset_options"] = d;
  // resolved from the dataset and the cameras (engine/train/train_run.cpp resolveSceneConfig)
  j["ior"] = c.ior;
  j["water_height"] = c.waterHeight;
  j["depth"] = c.depth;
  j["extent"] = c.extent;
  j["domain"] = {c.domain.xMin, c.domain.yMin, c.domain.xMax, c.domain.yMax};
  j["box_min"] = {c.boxMin[0], c.boxMin[1], c.boxMin[2]};
  j["box_max"] = {c.boxMax[0], c.boxMax[1], c.boxMax[2]};
  if (!c.modelSizing.is_null()) j["model_sizing"] = c.modelSizing;
  for (const TrainOption& o : trainOptionTable()) {
    if (o.key.empty()) continue;
    size_t slash = o.key.find('/');
    if (slash == std::string::npos) j[o.key] = o.get(c);
    else j[o.key.substr(0, slash)][o.key.substr(slash + 1)] = o.get(c);
  }
  return j;
}

TrainConfig trainConfigFromJson(const nlohmann::json& j, const std::string& where) {
  TrainConfig c;
  if (!j.is_object()) fail(where + ": not a training configuration (not a JSON object)");
  try {
    c.dataset = j.at("dataset").get<std::string>();
    const auto& d = j.at("dataset_options");
    auto bg = d.at("background");
    c.datasetOptions.background = glm::dvec3(bg.at(0).get<double>(), bg.at(1).get<double>(), bg.at(2).get<double>());
    c.datasetOptions.llffFactor = d.at("llff_factor").get<int>();
    c.datasetOptions.llffHold = d.at("llff_hold").get<int>();
    if (d.contains("test_views")) c.datasetOptions.testViews = d["test_views"].get<std::vector<std::string>>();
    if (d.contains("ior")) c.datasetOptions.ior = d["ior"].get<double>();
    if (d.contains("water_height")) c.datasetOptions.waterHeight = d["water_height"].get<double>();
    if (d.contains("water_depth")) c.datasetOptions.waterDepth = d["water_depth"].get<double>();
    if (d.contains("domain")) {
      auto r = d["domain"];
      c.datasetOptions.domain = Rect{r.at(0).get<double>(), r.at(1).get<double>(), r.at(2).get<double>(), r.at(3).get<double>()};
    }
    if (d.contains("up")) c.datasetOptions.up = glm::dvec3(d["up"].at(0).get<double>(), d["up"].at(1).get<double>(), d["up"].at(2).get<double>());
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
    if (j.contains("model_sizing")) {
      if (!j["model_sizing"].is_object()) fail(where + ": \"model_sizing\" is not an object");
      c.modelSizing = j["model_sizing"];
    }
  } catch (const nlohmann::json::exception& e) {
    fail(where + ": not a training configuration (" + e.what() + ")");
  }
  // Every option from the table; one absent from an older run keeps its default.
  for (const TrainOption& o : trainOptionTable()) {
    if (o.key.empty()) continue;
    auto [object, name] = locate(j, o.key);
    if (!object || !object->is_object() || !object->contains(name)) {
      if (o.required) fail(where + ": not a training configuration (no \"" + o.key + "\")");
      continue;
    }
    o.set(c, object->at(name), where + ": " + o.key);
  }
  applyDerivedDefaults(c, [&](const std::string& key) { auto [object, name] = locate(j, key); return object && object->contains(name); });
  // Runs written before the option: every octave open from the start; before the restart
  // list, one restart step (0: none).
  const nlohmann::json* schedule = j.contains("schedule") ? &j.at("schedule") : nullptr;
  if (schedule && !schedule->contains("octaves_open_until")) c.schedule.octavesOpenUntil = 0;
  if (schedule && !schedule->contains("gaussian_restarts") && schedule->contains("gaussian_restart")) {
    const nlohmann::json& one = schedule->at("gaussian_restart");
    if (one.is_number_integer() && one.get<long long>() > 0 && one.get<long long>() <= kMaxScheduleStep) c.schedule.gaussianRestarts = {one.get<int>()};
  }
  validateTrainConfig(c);
  return c;
}

}  // namespace refrax
