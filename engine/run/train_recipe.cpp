#include "engine/run/train_recipe.h"

#include <algorithm>
#include <sstream>

namespace refrax {
namespace {

// The method's size by device. A 32 x 32 patch step costs about a third of a 64 x 64 one on
// lavapipe (34 against 101 ms with 7,900 Gaussians on this project's 2-core machine), and a
// whole 252 px image about 1.5 s: a CPU trains on patches; a GPU on whole images, as the paper.
// 8,000 CPU steps, not 4,000: the water learns slowly at the defaults, and at 4,000 it had barely
// left the flat start (amplitude 0.04) while straight rays led it; at 8,000 the method's lead
// over straight rays at equal steps grew on every development pair and the evaluation scenes
// (docs/experiments/2026-12-06-steps.md).
constexpr int kGpuSteps = 15000;
constexpr int kCpuSteps = 8000;
constexpr uint32_t kCpuPatch = 32;
constexpr int kNever = kMaxScheduleStep;  // a step no run reaches

// The method's surface (docs/training.md "The defaults"; chosen on bench/generalise.sh's
// development scenes and the strong-wave scene, docs/experiments/2026-12-04-defaults.md): twice
// the reference's learning rate (the short runs' 3e-3 let weakly seen water walk away, to 22x the
// flat start's error on one scene), the level prior ten times the short runs' 1,000 (tilts of
// 36 mm/m grew under it), and the slope prior, which held the last scene that ran away.
constexpr double kSurfaceLearningRate = 1e-3;
constexpr uint32_t kCoarseOctaves = 3;
constexpr double kLevelPrior = 10000;
constexpr double kSurfaceSmoothness = 0.1;

std::string text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

std::vector<RecipeChoice> applyRecipe(TrainConfig& c, const std::function<bool(const std::string& key)>& given, const RecipeDevice& device,
                                      int imageWidth, int imageHeight) {
  std::vector<RecipeChoice> chosen;
  if (c.recipe == Recipe::Reference) return chosen;
  auto open = [&](const std::string& key) { return !given(key); };
  auto note = [&](const std::string& key, const std::string& value) { chosen.push_back({key, value}); };

  // The run's size: the device decides.
  if (open("steps")) {
    c.steps = device.cpu ? kCpuSteps : kGpuSteps;
    note("steps", text(c.steps));
  }
  if (open("patch")) {
    // a patch needs room to move: images under twice its side train whole
    c.patch = device.cpu && std::min(imageWidth, imageHeight) >= int(2 * kCpuPatch) ? kCpuPatch : 0;
    note("patch", text(c.patch));
  }

  // The Gaussians, in every model. SH degree 0: a view-dependent colour is one more way for the
  // Gaussians to absorb the waves' distortion; no density resets (they cost the image and
  // raised the wave only with restarts, which replace them here).
  if (open("max_sh_degree")) c.maxShDegree = 0, note("max_sh_degree", "0");
  if (open("schedule/density_reset_interval")) c.schedule.densityResetInterval = 0, note("schedule/density_reset_interval", "0");
  if (open("init_depth") && c.gaussiansFrom.empty()) c.initDepth = InitDepth::Sweep, note("init_depth", "sweep");
  // No pruning of large Gaussians without density resets, as in 3DGS, which prunes by world size
  // only once its first opacity reset has run. The limit is a tenth of the cameras' extent, a few
  // centimetres over a top-down rig with a small baseline, where the floor's Gaussians are larger:
  // every 100 steps most of them were pruned and drawn again, and a run of 8,000 steps lost what it
  // had learned (the strong wave's oracle 24.7 dB without, 18.8 with it; the method's images +0.20 dB
  // median on the held-out scenes; docs/experiments/2026-12-06-large-prune.md).
  if (open("schedule/prune_large_from") && c.schedule.densityResetInterval == 0)
    c.schedule.pruneLargeFrom = kNever, note("schedule/prune_large_from", std::to_string(kNever));

  // Where the water learns (the height field, or the flat plane): a fast surface, one step per
  // pass over the views, and the Gaussians drawn afresh twice through the water learned so far.
  const bool waterLearns = c.model == WaterModel::Refraction || c.model == WaterModel::FlatWater;
  if (!waterLearns) return chosen;
  if (open("surface_lr")) c.surfaceLearningRate = kSurfaceLearningRate, note("surface_lr", text(kSurfaceLearningRate));
  if (open("surface_batch")) c.surfaceBatch = 0, note("surface_batch", "views");
  if (open("schedule/surface_freeze")) {
    c.schedule.surfaceFreeze = c.steps * 2 / 15;
    note("schedule/surface_freeze", text(c.schedule.surfaceFreeze));
  }
  if (open("schedule/gaussian_restarts") && !c.gaussiansFixed) {
    std::vector<int> restarts;
    for (int r : {c.steps / 3, c.steps * 8 / 15})
      if (r > 0 && r < c.steps && (restarts.empty() || r > restarts.back())) restarts.push_back(r);
    c.schedule.gaussianRestarts = restarts;
    std::string list;
    for (int r : restarts) list += (list.empty() ? "" : ",") + text(r);
    note("schedule/gaussian_restarts", list.empty() ? "0" : list);
  }
  if (c.model != WaterModel::Refraction) return chosen;
  if (open("mlp_coarse_octaves")) c.mlpCoarseOctaves = kCoarseOctaves, note("mlp_coarse_octaves", text(kCoarseOctaves));
  if (open("schedule/octaves_open_until")) c.schedule.octavesOpenUntil = kNever, note("schedule/octaves_open_until", std::to_string(kNever));
  if (open("anchor_mean_height")) c.anchorMeanHeight = true, note("anchor_mean_height", "true");
  if (open("level_prior")) c.levelPrior = kLevelPrior, note("level_prior", text(kLevelPrior));
  if (open("surface_smoothness")) c.surfaceSmoothness = kSurfaceSmoothness, note("surface_smoothness", text(kSurfaceSmoothness));
  return chosen;
}

}  // namespace refrax
