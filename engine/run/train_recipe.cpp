#include "engine/run/train_recipe.h"

#include <algorithm>
#include <cstdint>
#include <sstream>

namespace refrax {
namespace {

// The method's size by device. A whole 252 px image costs about 1.5 s a step on lavapipe: a CPU
// trains on patches, a GPU on whole images, as the paper. On a CPU, 4,000 steps of 64 px patches
// (about the time of 8,000 of 32 px): the larger patch gives the water's gradient more of the
// image, and with the CPU's water settings below it learned the water where 8,000 steps of 32 px
// had left it near flat (docs/experiments/2026-12-07-cpu-water.md).
constexpr int kGpuSteps = 15000;
constexpr int kCpuSteps = 4000;
constexpr uint32_t kCpuPatch = 64;
constexpr int kNever = kMaxScheduleStep;  // a step no run reaches

// A point in the run, as a fraction of its steps.
struct RunFraction {
  int numerator, denominator;
  int of(int steps) const { return int(int64_t(steps) * numerator / denominator); }
};

// The water's rates and schedule by device (docs/training.md "The defaults").
struct WaterRecipe {
  double surfaceLearningRate;
  int surfaceBatch;  // steps per surface step; 0: one pass over the views
  RunFraction surfaceFreeze;
  std::vector<RunFraction> gaussianRestarts;
};

// On a CPU: a fast surface stepping every step, three restarts (the long test's settings,
// measured on the development scenes at three seeds against straight rays trained alike,
// docs/experiments/2026-12-07-cpu-water.md).
const WaterRecipe kCpuWater{3e-3, 1, {1, 10}, {{1, 4}, {2, 5}, {11, 20}}};
// On a GPU (not measured there; chosen at the CPU's earlier budget of 8,000 steps of 32 px,
// docs/experiments/2026-12-04-defaults.md): twice the reference's rate, one surface step per pass
// over the views.
const WaterRecipe kGpuWater{1e-3, 0, {2, 15}, {{1, 3}, {8, 15}}};

// The height field's shape on every device: three coarse octaves; the slope prior, which held
// the last development scene that ran away; and the level prior at 10,000. On a GPU's settings
// 1,000 let tilts of 36 mm/m grow. On a CPU's, 1,000 let gentle waves run away (dev 10 to 3.75x
// the flat start's error, the gentle presets to 1.5-16x) and 10,000 held them (dev 10
// 0.35-0.43x, the presets 0.73-1.81x). Where the water is learned the images moved -0.21 to
// +0.28 dB (medians of dev 9, 14, 15), the strong wave's -0.79 (still +2.38 over straight rays).
// It does not hold the held-out set's gentlest waves (1009, 1010, 1012 still diverge: their
// relief grows the wrong shape, not a tilt or bowl) (docs/experiments/2026-12-07-level-prior-cpu.md).
constexpr uint32_t kCoarseOctaves = 3;
constexpr double kSurfaceSmoothness = 0.1;
constexpr double kLevelPrior = 10000;

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
    // images no larger than the patch train whole
    c.patch = device.cpu && std::min(imageWidth, imageHeight) > int(kCpuPatch) ? kCpuPatch : 0;
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

  // Where the water learns (the height field, or the flat plane): the device's water settings, the
  // Gaussians drawn afresh through the water learned so far.
  const bool waterLearns = c.model == WaterModel::Refraction || c.model == WaterModel::FlatWater;
  if (!waterLearns) return chosen;
  // The flat plane keeps the slower settings on a CPU too: its one parameter, the height, is
  // barely determined by top-down views, and Adam walks it about a learning rate a step, so a
  // step every step at 3e-3 carried it 0.39-0.60 m from the water (RMSE) on the tiny weak-wave
  // presets, 13.96-19.76 dB against 21.61-22.16 with these (docs/experiments/2026-12-07-eval-cpu-defaults.md).
  const WaterRecipe& water = device.cpu && c.model == WaterModel::Refraction ? kCpuWater : kGpuWater;
  if (open("surface_lr")) c.surfaceLearningRate = water.surfaceLearningRate, note("surface_lr", text(water.surfaceLearningRate));
  if (open("surface_batch")) {
    c.surfaceBatch = water.surfaceBatch;
    note("surface_batch", water.surfaceBatch == 0 ? "views" : text(water.surfaceBatch));
  }
  if (open("schedule/surface_freeze")) {
    c.schedule.surfaceFreeze = water.surfaceFreeze.of(c.steps);
    note("schedule/surface_freeze", text(c.schedule.surfaceFreeze));
  }
  if (open("schedule/gaussian_restarts") && !c.gaussiansFixed) {
    std::vector<int> restarts;
    for (const RunFraction& f : water.gaussianRestarts) {
      const int r = f.of(c.steps);
      if (r > 0 && r < c.steps && (restarts.empty() || r > restarts.back())) restarts.push_back(r);
    }
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
