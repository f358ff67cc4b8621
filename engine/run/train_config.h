#pragma once
// Everything one training run is made of, resolved before the first step and written to
// RUN/config.json, so `refrax render`, `refrax eval` and `--resume` rebuild the same model.
// Schedules (docs/method.md §1.6) are given for the reference 15,000 steps; resolveSchedule scales
// every step count that was not set explicitly by steps / 15000, so a short run passes
// through the same phases (surface frozen, face normals, SH degrees, density resets).
#include <cstdint>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/dataset/dataset.h"
#include "engine/gaussian/gaussian_trace.h"  // kDefaultKBuffer

namespace refrax {

// KnownWater: the oracle, the dataset's ground-truth surface fixed (only the Gaussians learn):
// what the refraction model would reach with a perfect surface.
enum class WaterModel { Refraction, NoRefraction, FlatWater, KnownWater };
const char* waterModelName(WaterModel model);
WaterModel parseWaterModel(const std::string& name);

// A step count of the schedule: explicit (from the command line) or scaled from the reference.
// An interval of 0 (explicit only) switches its event off; the SH interval must be >= 1.
// The choices of the options table's "choice" rows: parsed from their names ("box", "mcmc")
// once, by the table (engine/run/train_options.cpp), and compared as enums where they are used.
enum class InitDepth { Box, Sweep };
// Which settings fill what the command line leaves open (engine/run/train_recipe.h): Method,
// the defaults of `refrax train`; Reference, the paper's schedule (TrainConfig's initialisers,
// and every run written before recipes).
enum class Recipe { Method, Reference };
enum class DensifyStrategy { Reference3dgs, Mcmc };

// The largest step any schedule option takes: a step no run reaches, what "never" is written as.
constexpr int kMaxScheduleStep = 100000000;

struct ScheduleSteps {
  int surfaceFreeze = -1;        // surface (and flat height) frozen before this step; reference 1,000
  int surfaceUntil = 0;          // ... and frozen again after this step (0: learns to the end, the reference)
  int faceNormalsUntil = -1;     // flat face normals before this step; reference 7,500
  int octavesOpenUntil = -1;     // the height encoding's window fully open at this step; 7,500 (ours)
  int shDegreeInterval = -1;     // SH degree +1 every this many steps; reference 1,000
  int densityResetInterval = -1; // density reset to <= 0.01 every ...; reference 3,000
  int densityResetUntil = -1;    // no reset from this step on; reference 12,000 (a reset needs steps to recover)
  int densityDecayInterval = -1; // density x decay every ...; reference 50
  int densifyFrom = -1;          // densification call site from ...; reference 500
  int densifyInterval = -1;      // ... every ...; reference 300
  int densifyUntil = -1;         // ... until; reference 15,000 * 0.8
  int pruneInterval = -1;        // low-density pruning every ...; reference 100 (same from/until)
  int pruneLargeFrom = -1;       // pruning of over-large Gaussians from ...; reference 3,000
  int lrSteps = -1;              // length of the decaying learning-rate schedules; reference 30,000
  std::vector<int> gaussianRestarts;  // Gaussians drawn afresh after these steps (none: the reference)
  // The refit: after the run's `steps`, this many more steps of Gaussians drawn afresh under the
  // water as it was learned, held fixed, their schedule counted again from the refit's start
  // (0: none). Why: Gaussians fitted while the water moved keep its history in their colours;
  // fresh ones under the learned water of evaluation scene 1008 ended 1.3 dB higher
  // (docs/experiments/2026-12-05-water-valley.md).
  int refitSteps = 0;
};

struct TrainConfig {
  std::string dataset;
  DatasetOptions datasetOptions;  // as given on the command line (overrides water.json)
  WaterModel model = WaterModel::Refraction;
  // The recipe the run's open settings came from; the values below are the reference's, which
  // `refrax train` replaces with the method's (applyRecipe) unless --recipe reference.
  Recipe recipe = Recipe::Reference;
  int steps = 15000;
  uint64_t seed = 1;

  // Water (resolved from water.json / options / the cameras).
  double ior = kWaterIor, waterHeight = 0, depth = 0, extent = 1;
  Rect domain;
  double boxMin[3] = {0, 0, 0}, boxMax[3] = {0, 0, 0};

  // Gaussians.
  uint32_t initialGaussians = 20000;
  // Where the initial (and restarted) Gaussians' depths come from: Box ("box"), uniform in
  // the box (the reference), or Sweep ("sweep"), a plane sweep of the training views through
  // the current water (engine/train/plane_sweep.h).
  InitDepth initDepth = InitDepth::Box;
  // --init-points: the Gaussians start at the dataset's sparse points under the water
  // (COLMAP's, moved to their paraxial true depth; engine/train/init_gaussians.h), the rest
  // as initDepth says.
  bool initPoints = false;
  // Studies of the water's chain (issue 45): the initial (and restarted) Gaussians read from a
  // 3DGS PLY (an absolute path; e.g. a --known-water run's point_cloud.ply) instead of drawn,
  // and, with gaussiansFixed, kept as read: no Adam step, no density schedule, no densification,
  // every SH degree on from step 1. Only the water then learns, against Gaussians that already
  // fit the true water, so what the surface reaches says whether its gradient chain is sound.
  std::string gaussiansFrom;
  bool gaussiansFixed = false;
  // With KnownWater: the true relief scaled about its level (waves' amplitudes, or a height map
  // about its mean) by this factor; 1 is the truth. A study of how the loss varies between the
  // flat start and the truth.
  double knownWaterScale = 1;
  uint32_t maxGaussians = 1000000;
  double initialDensity = 0.1;
  uint32_t maxShDegree = 3;
  uint32_t kBuffer = kDefaultKBuffer;
  // Hits per ray the forward records for the backward (0: the backward re-traces every ray).
  uint32_t hitRecordsPerRay = kDefaultHitRecordsPerRay;
  std::string proxy = "auto";

  // Height field and surface.
  uint32_t mlpWidth = 64, mlpHiddenLayers = 3, mlpOctaves = 6;
  // Coarse-to-fine encoding (height_encoding.glsl): only the first mlpCoarseOctaves octaves are
  // open until the surface starts learning, then the window opens linearly to every octave by
  // schedule.octavesOpenUntil; >= mlpOctaves (the default): off. Why it exists: with the
  // Gaussians fixed at the oracle's, the surface of the strong-wave tiny preset learned far
  // faster with 3 octaves than with 6 (test PSNR 14.4 -> 20.6 dB in 250 steps against
  // 14.4 -> 14.7), as slopes make high octaves stiff; in joint training neither helped yet.
  uint32_t mlpCoarseOctaves = 6;
  // Keep the learned water's mean height over the domain at waterHeight: after each surface
  // step the height field's constant (initialHeight) is reset so the coarse grid's mean is the
  // given height (a projection; the MLP has no bias). Why: straight-down views barely see a
  // uniform shift, and the learned mean drifted 12 cm on the strong-wave tiny preset. Off by
  // default: there it halved the surface RMSE (0.084 -> 0.046) but the seen centre still sat
  // 6 cm low, balanced by the unseen border (the domain mean is the wrong constraint there).
  bool anchorMeanHeight = false;
  // At each --restart-gaussians step, before the Gaussians are drawn afresh, sweep the views
  // through the learned water and through its mirror image about waterHeight, and keep the
  // mirror when the views agree clearly more through it (WaterSignCheck). Why: full-size runs
  // learned the right waves upside down in 2 of 8 runs, fitting the views nearly as well; the
  // restart discards the Gaussians fitted to the old sign anyway
  // (docs/experiments/2026-11-28-upside-down-water.md). Off by default: a method setting.
  bool waterSignCheck = false;
  // At each --restart-gaussians step, before the Gaussians are drawn afresh, sweep the views
  // through the learned water's relief scaled about waterHeight by each of kWaterScales and keep
  // the scale they agree best through (WaterScaleSearch). Why: the Gaussians absorb the warp of
  // a water learned at part of its height, so the images barely pull it higher; the sweep does
  // not pass through them, and its cost is least at the true height
  // (docs/experiments/2026-12-05-water-valley.md). A study option, off.
  bool waterScaleSearch = false;
  // Weight of the sweep loss on the height field (engine/train/sweep_loss.h: the training views'
  // rays against the colour a plane sweep through the same water finds they agree on where they
  // land), applied at every sweepLossEvery'th surface step, summed as the surface batch's
  // steps' gradients are; 0: none. A study option.
  double sweepLoss = 0;
  int sweepLossEvery = 1;
  // The water learns from the sweep loss alone: the images' gradient reaches the Gaussians,
  // not the water. Why: the images pull the water through Gaussians that absorbed its warp; the
  // views' agreement does not pass through them. A study option.
  bool sweepLossOnly = false;
  // At each --restart-gaussians step, before the Gaussians are drawn afresh, sweep the views
  // through the learned water and through flat water; when their colours agree less through the
  // learned water (its plane-sweep cost above surfaceGate times the flat water's), the water
  // starts again from its initial state (SurfaceGateCheck). Why: on a top-down rig the surface
  // ran away to 24 cm RMS while the training loss fell, as the Gaussians fitted each
  // distortion it made; the sweep does not pass through the Gaussians, so they cannot make it
  // agree. 0 (the reference): no gate.
  double surfaceGate = 0;
  // At each --restart-gaussians step, the Gaussians are drawn afresh only when the views agree
  // more through the learned water than through flat water (its plane-sweep cost below
  // restartGate times the flat water's; RestartGateCheck); otherwise the step passes and they
  // keep fitting. Why: a restart lets fresh Gaussians fit a water learned since they were drawn;
  // with no such water it only costs their fit (dev 15, the water held flat by --sweep-watch:
  // -0.55 dB against straight rays with the two restarts, -0.25 without; one seed,
  // docs/experiments/2026-12-05-water-valley.md). 0: every restart is drawn. A study option.
  double restartGate = 0;
  // Every sweepWatch steps while the water learns, and at its last step, sweep the views
  // through the learned water (its plane-sweep cost against the flat water's, SweepWatchCheck);
  // when they agree less through it than through flat water (by more than 1%), the water goes back to the state
  // they agreed on best at a check so far (flat water at the water height if none), its Adam's first moments
  // cleared and its learning rate halved. Why: the water learned from the views' agreement
  // (--sweep-loss-only) ran away on three of six dev scenes, each ending with the views agreeing
  // less than through flat water, and a water reset only at the restarts (surfaceGate) ran away
  // again (docs/experiments/2026-12-05-water-valley.md). 0: no watch. A study option.
  int sweepWatch = 0;
  // The height MLP's Adam steps scaled by (|m^| / sqrt(v^))^surfaceAgreement, how consistently
  // the surface steps' gradients have pointed one way (shaders/include/adam_update.glsl
  // adamUpdateAgreed). Why: views that disagree, or Gaussians that have absorbed the waves,
  // leave the surface a gradient of noise about zero, which plain Adam still follows about the
  // learning rate per step: the surface walks away while the loss falls. 0 (the reference): plain Adam.
  double surfaceAgreement = 0;
  // Last-layer initial range: the reference's 0.1 starts a 64-wide MLP with height noise of
  // about +-0.3 (larger than the waves of the scenes); a small range starts nearly flat.
  double mlpInitRange = 1e-3;
  // Adam learning rate of the surface (MLP weights, or the flat plane's height) at step 0,
  // decaying exponentially to 1/100 of it over lrSteps; reference 5e-4 (docs/method.md §1.6).
  double surfaceLearningRate = 5e-4;
  // The surface's Adam step every this many steps, on the gradient summed over them (the
  // views in between); 1 (the reference): every step. Why: one view's gradient is right for
  // that view (refrax gradcheck) but views disagree; on the weak-wave presets Adam, which
  // steps about the learning rate whatever the gradient's size, walked the surface away on
  // their disagreement (docs/experiments/2026-11-26-surface-batch.md). 0 (--surface-batch views): the training view count, one
  // surface step per pass over the views (surfaceBatchSteps).
  int surfaceBatch = 1;
  // Weight of the slope prior (engine/surface/surface_prior.h) added to the loss while the surface
  // learns; 0 (the reference): none.
  double surfaceSmoothness = 0;
  // Weight of the level prior (engine/surface/surface_prior.h: the seen water's tilt and bowl) added
  // to the loss while the height field learns; 0 (the reference): none.
  double levelPrior = 0;
  // The level prior on the tilt alone, not the bowl: a wave longer than the seen water projects
  // onto the bowl, which the prior then holds flat (surface_prior.h).
  bool levelPriorTiltOnly = false;
  // The level prior's highest total degree (x^a y^b, a + b <= it); 2, tilt and bowl (the
  // reference's prior, when on); --level-prior-tilt-only makes it 1.
  int levelPriorDegree = 2;
  // The level prior's terms past the bowl weighted this share of levelPrior (1: the same).
  double levelPriorWarpShare = 1.0;
  uint32_t gridCells = 64, subdivisionLevels = 2;

  // Schedule and its resolved values.
  ScheduleSteps schedule;
  double densityDecay = 0.99;
  double densityResetValue = 0.01;
  // Weight of the density (opacity) loss, weight * mean(sigmoid(logit)^2) over all Gaussians;
  // reference 0.007 (docs/method.md §1.6), 0 switches it off (the paper's ablation).
  double densityLossWeight = 0.007;
  bool densify = true;             // clone/split/prune (engine/gaussian/densify.h)
  double densifyGradThreshold = 3e-4;
  // Reference3dgs ("3dgs"): clone, split, prune and density resets (engine/gaussian/densify.h,
  // the reference); Mcmc ("mcmc"): relocation, growth and position noise
  // (engine/gaussian/mcmc.h), at the same steps.
  DensifyStrategy densifyStrategy = DensifyStrategy::Reference3dgs;

  // Batching: 0 trains on whole images; P > 0 on one random P x P patch of the image per step
  // (SSIM needs an image-shaped batch: a patch keeps its window statistics; about P^2 / (w h)
  // of the rays and time per step, and the same number of steps sees P^2 / (w h) of the pixels).
  uint32_t patch = 0;
  // Training views used (number-of-views sweeps): 0 all of them, N an even spread of N
  // (engine/run/train_views.h), applied wherever the run's dataset is loaded.
  uint32_t trainViews = 0;

  // The model's size from the data (engine/train/model_sizing.h): the config keys the command line
  // left to it (the sized options it was not given); resolveSceneConfig derives them, records the
  // choices and reasons in modelSizing (config.json "model_sizing"; null: nothing derived) and
  // empties the set. A config built in code sizes nothing unless it names keys here.
  std::set<std::string> sizeFromData;
  nlohmann::json modelSizing;

  // Logging and files.
  int progressEvery = 50, evalEvery = 0, checkpointEvery = 500;
};

// Fills every unset step count of the schedule from the reference values scaled by steps / 15000.
void resolveSchedule(TrainConfig& config);
// The run's last step: steps, and the refit's after them.
int totalSteps(const TrainConfig& config);
// The Gaussians' schedule (densification, density events, SH degree) at step t: counted from the
// refit's start in the refit, so it runs again as in the run's first `steps`.
int gaussianScheduleStep(const TrainConfig& config, int t);
// Whether the refit's fresh Gaussians are drawn before step t (the first step after `steps`).
bool refitStartsAt(const TrainConfig& config, int t);
// The height field's encoding window (HeightFieldConfig::encodingWindow) at step t.
float encodingWindowAt(const TrainConfig& config, int t);
// The window the height field holds after step t: the surface is lifted for the next step
// at each surface step (every surfaceBatchSteps steps once it learns, t > surfaceFreeze);
// before the first it keeps the coarse window of step 0.
float encodingWindowAfterStep(const TrainConfig& config, int t, int surfaceBatchSteps = 1);
// Steps per surface Adam step: config.surfaceBatch, or with 0 (--surface-batch views) the
// training view count.
int surfaceBatchSteps(const TrainConfig& config, size_t trainViews);
// Throws refrax::Error naming the first bad value.
void validateTrainConfig(const TrainConfig& config);

nlohmann::json trainConfigToJson(const TrainConfig& config);
TrainConfig trainConfigFromJson(const nlohmann::json& json, const std::string& where);
// The defaults that follow other options when not given (`given` by config.json key):
// --max-gaussians at least --gaussians, --mlp-coarse-octaves = --mlp-octaves (coarse-to-fine off).
void applyDerivedDefaults(TrainConfig& config, const std::function<bool(const std::string& key)>& given);

}  // namespace refrax
