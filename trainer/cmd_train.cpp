// refrax train <dataset> -o RUN: jointly optimises the water surface (a neural height field)
// and the Gaussians under it (engine/train/). --no-refraction and --flat-water train the
// comparison models on the same data, --known-water the oracle (the true surface, fixed).
// --resume RUN continues from the newest checkpoint.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "engine/dataset/dataset.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/io/json_io.h"
#include "engine/train/checkpoint.h"
#include "engine/train/train_run.h"
#include "engine/train/train_views.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"
#include "trainer/cli.h"
#include "trainer/dataset_options.h"

namespace refrax {
namespace {

uint32_t positiveCount(const cli::Args& a, const char* name, long fallback, long lo, long hi) {
  return uint32_t(a.getIntIn(name, fallback, lo, hi));
}

void scheduleOption(const cli::Args& a, const char* name, int& field) {
  if (!a.has(name)) return;
  long v = a.getInt(name, 0);
  if (v < 0 || v > 100000000) fail(std::string("--") + name + " must be a step count >= 0");
  field = int(v);
}

TrainConfig configFromArgs(const cli::Args& a) {
  TrainConfig c;
  c.datasetOptions = datasetOptionsFrom(a);
  if (a.has("no-refraction") + a.has("flat-water") + a.has("known-water") > 1)
    fail("--no-refraction, --flat-water and --known-water exclude each other");
  c.model = a.has("no-refraction") ? WaterModel::NoRefraction
            : a.has("flat-water")  ? WaterModel::FlatWater
            : a.has("known-water") ? WaterModel::KnownWater
                                   : WaterModel::Refraction;
  c.steps = int(positiveCount(a, "steps", 15000, 1, 10000000));
  c.seed = uint64_t(a.getInt("seed", 1));
  c.initialGaussians = positiveCount(a, "gaussians", 20000, 1, 50000000);
  c.initDepth = a.get("init-depth", "box");
  c.maxGaussians = positiveCount(a, "max-gaussians", std::max<long>(1000000, c.initialGaussians), 1, 100000000);
  c.initialDensity = a.getDouble("initial-density", 0.1);
  c.maxShDegree = positiveCount(a, "sh-degree", 3, 0, 3);
  c.kBuffer = positiveCount(a, "k-buffer", kDefaultKBuffer, 1, 64);
  c.hitRecordsPerRay = positiveCount(a, "hit-records", kDefaultHitRecordsPerRay, 0, 1024);
  c.proxy = a.get("proxy", "auto");
  c.mlpWidth = positiveCount(a, "mlp-width", 64, 1, 256);
  c.mlpHiddenLayers = positiveCount(a, "mlp-layers", 3, 1, 8);
  c.mlpOctaves = positiveCount(a, "mlp-octaves", 6, 0, 16);
  c.mlpCoarseOctaves = positiveCount(a, "mlp-coarse-octaves", c.mlpOctaves, 0, 16);
  c.anchorMeanHeight = a.has("anchor-mean-height");
  c.mlpInitRange = a.getDouble("mlp-init-range", 1e-3);
  c.surfaceLearningRate = a.getDouble("surface-lr", 5e-4);
  c.surfaceBatch = a.get("surface-batch", "1") == "views" ? 0 : int(a.getIntIn("surface-batch", 1, 1, 100000));
  c.surfaceSmoothness = a.getDouble("surface-smoothness", 0.0);
  c.levelPrior = a.getDouble("level-prior", 0.0);
  c.gridCells = positiveCount(a, "grid-cells", 64, 1, 4096);
  c.subdivisionLevels = positiveCount(a, "subdivision", 2, 0, 6);
  c.patch = positiveCount(a, "patch", 0, 0, 16384);
  if (a.has("train-views")) {
    long n = a.getInt("train-views", 0);
    if (n < 1) fail("--train-views must be at least 1, got " + a.get("train-views"));
    c.trainViews = uint32_t(std::min<long>(n, 1000000000));
  }
  c.densityDecay = a.getDouble("density-decay", 0.99);
  c.densityLossWeight = a.getDouble("density-loss", 0.007);
  scheduleOption(a, "surface-freeze", c.schedule.surfaceFreeze);
  scheduleOption(a, "face-normals-until", c.schedule.faceNormalsUntil);
  scheduleOption(a, "octaves-open-until", c.schedule.octavesOpenUntil);
  scheduleOption(a, "sh-interval", c.schedule.shDegreeInterval);
  scheduleOption(a, "density-reset-every", c.schedule.densityResetInterval);
  scheduleOption(a, "density-reset-until", c.schedule.densityResetUntil);
  scheduleOption(a, "density-decay-every", c.schedule.densityDecayInterval);
  scheduleOption(a, "densify-from", c.schedule.densifyFrom);
  scheduleOption(a, "densify-every", c.schedule.densifyInterval);
  scheduleOption(a, "densify-until", c.schedule.densifyUntil);
  scheduleOption(a, "lr-steps", c.schedule.lrSteps);
  scheduleOption(a, "prune-every", c.schedule.pruneInterval);
  scheduleOption(a, "prune-large-from", c.schedule.pruneLargeFrom);
  if (a.has("restart-gaussians")) {
    // A comma-separated list of steps; 0 alone: never.
    const std::string list = a.get("restart-gaussians");
    for (double v : parseNumbers(list, 0, "--restart-gaussians", "steps separated by commas")) {
      if (v != std::floor(v) || v < 0 || v > 100000000) fail("--restart-gaussians expects steps separated by commas, got '" + list + "'");
      if (v > 0) c.schedule.gaussianRestarts.push_back(int(v));
    }
  }
  c.densify = !a.has("no-densify");
  c.densifyGradThreshold = a.getDouble("densify-grad", 3e-4);
  c.progressEvery = int(positiveCount(a, "progress-every", 50, 1, 100000000));
  c.evalEvery = int(positiveCount(a, "eval-every", 0, 0, 100000000));
  c.checkpointEvery = int(positiveCount(a, "checkpoint-every", 500, 0, 100000000));
  return c;
}

// What --resume accepts besides the run: how far it goes, how it reports, and the device.
const std::set<std::string>& resumeOptions() {
  static const std::set<std::string> names = [] {
    std::set<std::string> n = {"resume", "steps", "progress-every", "eval-every", "checkpoint-every", "profile", "time-limit"};
    for (const cli::Option& o : cli::deviceOptions()) n.insert(o.name);
    return n;
  }();
  return names;
}

void printSummary(const nlohmann::json& m) {
  std::printf("test psnr %.3f  ssim %.4f", m["psnr"].get<double>(), m["ssim"].get<double>());
  if (m.contains("surface_rmse")) std::printf("  surface rmse %.5f (initial flat %.5f)", m["surface_rmse"].get<double>(), m["initial_flat_surface_rmse"].get<double>());
  if (m.contains("surface_rmse_missing")) std::printf("  surface rmse n/a: %s", m["surface_rmse_missing"].get<std::string>().c_str());
  if (m.contains("water_removal_psnr")) std::printf("  water-removal psnr %.3f", m["water_removal_psnr"].get<double>());
  std::printf("  gaussians %llu  %.1f s\n", (unsigned long long)m["gaussians"].get<uint64_t>(), m["training_seconds"].get<double>());
}

int runTrain(const cli::Args& args) {
  namespace fs = std::filesystem;
  TrainProgress progress;
  progress.line = [](const std::string& text) { std::fprintf(stderr, "%s\n", text.c_str()); };
  progress.profile = args.has("profile");
  if (args.has("time-limit")) {
    progress.timeLimitSeconds = args.getDouble("time-limit", 0);
    if (!(progress.timeLimitSeconds > 0 && progress.timeLimitSeconds < 1e9)) fail("--time-limit must be a number of seconds above 0");
  }
  if (args.has("resume")) {
    if (!args.positional.empty() || args.has("output")) fail("--resume RUN takes no dataset and no -o: the run folder holds both");
    // The run's configuration is RUN/config.json; only how far and how it reports may change.
    for (const auto& [name, value] : args.values)
      if (!resumeOptions().count(name))
        fail("--" + name + " cannot change when a run resumes (RUN/config.json holds the run's configuration); with --resume only " +
             "--steps, --progress-every, --eval-every, --checkpoint-every, --profile, --time-limit and the device options apply");
    std::string run = args.get("resume");
    TrainConfig stored = readRunConfig(run);
    std::string ckpt = latestCheckpoint(run);
    if (ckpt.empty()) fail(run + " has no checkpoint to resume from");
    try {
      verifyCheckpointFile(ckpt);
    } catch (const Error& e) {
      // Offer an intact older checkpoint rather than resume from it unasked (it loses steps).
      std::string older = intactCheckpointBefore(run, checkpointStep(ckpt));
      if (older.empty()) throw;
      fail(std::string(e.what()) + "; " + older + " is intact: remove " + ckpt + " to resume from it");
    }
    if (args.has("steps")) {
      int steps = int(positiveCount(args, "steps", stored.steps, 1, 10000000));
      int reached = checkpointStep(ckpt);
      if (steps < reached)
        fail("--steps " + std::to_string(steps) + " is below the step the run has reached (" + std::to_string(reached) + ", " + ckpt + ")");
      stored.steps = steps;
    }
    if (args.has("progress-every")) stored.progressEvery = int(positiveCount(args, "progress-every", 50, 1, 100000000));
    if (args.has("eval-every")) stored.evalEvery = int(positiveCount(args, "eval-every", 0, 0, 100000000));
    if (args.has("checkpoint-every")) stored.checkpointEvery = int(positiveCount(args, "checkpoint-every", 500, 0, 100000000));
    auto ctx = cli::openContext(args);
    auto session = openRun(*ctx, run);
    session->config.steps = stored.steps;
    session->config.progressEvery = stored.progressEvery;
    session->config.evalEvery = stored.evalEvery;
    session->config.checkpointEvery = stored.checkpointEvery;
    writeJson((fs::path(run) / "config.json").string(), trainConfigToJson(session->config));
    std::fprintf(stderr, "resuming %s at step %d of %d\n", run.c_str(), session->step, session->config.steps);
    printSummary(trainToEnd(*session, run, progress));
    if (progress.profile) std::fprintf(stderr, "%s", profileTable(session->profiler).c_str());
    return 0;
  }
  if (args.positional.size() != 1) fail("refrax train needs one dataset folder");
  if (!args.has("output")) fail("refrax train needs -o RUN (the output folder)");
  std::string run = args.get("output");
  std::error_code ec;
  if (fs::exists(run, ec) && !(fs::is_directory(run, ec) && fs::is_empty(run, ec)))
    fail(run + " already exists and is not empty (use --resume " + run + " to continue it, or another folder)");

  TrainConfig config = configFromArgs(args);
  config.dataset = fs::absolute(args.positional[0]).lexically_normal().string();
  Dataset dataset = loadDataset(config.dataset, config.datasetOptions);
  keepTrainViews(dataset, config.trainViews);  // before the scene bounds: they come from the views trained on
  resolveSceneConfig(config, dataset);
  // Everything checked: the run folder appears only now (and goes again if the device fails).
  auto folder = cli::createOutputFolder(run, "-o");
  auto ctx = cli::openContext(args);
  auto session = createTrainSession(*ctx, config, std::move(dataset));
  folder->keep();
  writeJson((fs::path(run) / "config.json").string(), trainConfigToJson(session->config));
  std::fprintf(stderr, "training %s (%s): %u Gaussians, %d steps, %zu training views -> %s\n", config.dataset.c_str(),
               waterModelName(config.model), config.initialGaussians, config.steps, session->dataset.split("train").size(), run.c_str());
  printSummary(trainToEnd(*session, run, progress));
  if (progress.profile) std::fprintf(stderr, "%s", profileTable(session->profiler).c_str());
  return 0;
}

std::vector<cli::Option> trainOptions() {
  std::vector<cli::Option> o = {
      {"output", "RUN", "output folder (-o); must not exist or be empty", ""},
      {"resume", "RUN", "continue RUN from its newest checkpoint (with --steps N: on to step N; only --steps, --progress-every, --eval-every, --checkpoint-every, --profile and the device options may be given)", ""},
      {"no-refraction", "", "comparison: plain 3DGRT, straight rays, no water surface", ""},
      {"flat-water", "", "comparison: a flat water plane whose only parameter, its height, is learned", ""},
      {"known-water", "", "oracle: the dataset's ground-truth surface (water.json), fixed; only the Gaussians learn", ""},
      {"steps", "N", "training steps (one training image or patch each)", "15000"},
      {"seed", "S", "random seed (initial Gaussians, height field, view order, patches)", "1"},
      {"gaussians", "N", "initial Gaussians, uniform in the box derived under the water", "20000"},
      {"init-depth", "KIND", "the initial (and restarted) Gaussians' depth: box (uniform in the box, the reference) or sweep (a plane sweep of the training views through the current water; docs/training.md)", "box"},
      {"max-gaussians", "N", "cap on the Gaussian count (enforced by densification)", "1000000"},
      {"initial-density", "X", "initial Gaussian density", "0.1"},
      {"sh-degree", "D", "highest SH degree (reached one degree per --sh-interval steps)", "3"},
      {"k-buffer", "K", "tracer k-buffer size", std::to_string(kDefaultKBuffer)},
      {"hit-records", "N", "hits per ray the forward records so the backward need not re-trace (8 bytes each; 0: re-trace)",
       std::to_string(kDefaultHitRecordsPerRay)},
      {"proxy", "KIND", "Gaussian proxies: aabb, instanced or auto", "auto"},
      {"mlp-width", "W", "height-field MLP width", "64"},
      {"mlp-layers", "L", "height-field MLP hidden layers", "3"},
      {"mlp-octaves", "O", "height-field frequency-encoding octaves", "6"},
      {"mlp-coarse-octaves", "C", "coarse-to-fine: octaves open while the surface is frozen, the rest open gradually until --octaves-open-until (>= O: all from the start)", "O"},
      {"mlp-init-range", "X", "height-field last layer initialised in +-X (reference 0.1)", "0.001"},
      {"surface-lr", "X", "surface learning rate at step 0 (MLP weights, or the flat height), decaying to X/100 (reference 5e-4)", "5e-4"},
      {"grid-cells", "N", "water-surface proxy mesh cells per side", "64"},
      {"subdivision", "K", "recursive subdivision levels of the surface trace", "2"},
      {"train-views", "N", "train on N of the training views, spread evenly in file order (first and last included); the test views are unchanged", "all"},
      {"patch", "P", "train on one random P x P patch per step (0: whole images); ~P^2/(w h) of the time per step", "0"},
      {"density-decay", "X", "density multiplier every --density-decay-every steps", "0.99"},
      {"density-loss", "X", "weight of the density loss X mean(density^2) over all Gaussians (0: off, the paper's ablation)", "0.007"},
      {"surface-batch", "N|views", "one surface Adam step every N steps, on the gradient summed over their N views (1: every step, the reference; views: the training view count, one step per pass over the views, which the shuffled order visits once each when the surface starts learning at a pass's start)", "1"},
      {"surface-freeze", "N", "surface frozen for the first N steps", "1000 x steps/15000"},
      {"face-normals-until", "N", "flat face normals until step N, then interpolated", "7500 x steps/15000"},
      {"surface-smoothness", "X", "weight of a slope prior on the water, X mean((h_a - h_b) / spacing)^2 over the coarse grid's edges: damps a fast surface's runaway (0.1 left 2 of 9 tiny presets running away, 4 without; docs/training.md)", "0"},
      {"level-prior", "X", "weight of a prior holding the seen water level: X times the mean square of its tilt and bowl (the {x, y, x^2, xy, y^2} part of a least-squares fit, each vertex weighted by the training views that see it): straight-down views barely see them (docs/training.md)", "0"},
      {"anchor-mean-height", "", "keep the learned water's mean height (each vertex weighted by the training views that see it) at the given water height: straight-down views barely see a uniform shift", ""},
      {"octaves-open-until", "N", "every encoding octave open from step N (the window opens linearly from --surface-freeze)", "7500 x steps/15000"},
      {"sh-interval", "N", "SH degree +1 every N steps", "1000 x steps/15000"},
      {"density-reset-every", "N", "density reset to <= 0.01 every N steps (part of densification: only when it runs)", "max(1000, 3000 x steps/15000)"},
      {"density-reset-until", "N", "no density reset from step N", "12000 x steps/15000"},
      {"density-decay-every", "N", "density decay every N steps", "50"},
      {"densify-from", "N", "densification from step N", "500 x steps/15000"},
      {"densify-every", "N", "densification every N steps", "max(100, 300 x steps/15000)"},
      {"densify-until", "N", "densification until step N", "12000 x steps/15000"},
      {"no-densify", "", "no clone/split/prune (and no density reset)", ""},
      {"densify-grad", "X", "clone/split threshold on the mean positional-gradient statistic", "3e-4"},
      {"prune-every", "N", "prune low-density Gaussians every N steps (densify-from..densify-until)", "100"},
      {"prune-large-from", "N", "also prune Gaussians larger than 10% of the extent from step N", "3000 x steps/15000"},
      {"lr-steps", "N", "length of the decaying learning-rate schedules", "30000 x steps/15000"},
      {"restart-gaussians", "N[,N...]", "draw the Gaussians afresh after each step N (as at step 0, with fresh Adam state and schedules), the surface kept: the first Gaussians absorb the distortion of the still-flat water, and fresh ones let it grow toward the true amplitude; with --init-depth sweep each restart looks through a better surface (docs/training.md) (0: never)", "0"},
      {"progress-every", "N", "progress line every N steps (stderr)", "50"},
      {"eval-every", "N", "test-split evaluation every N steps (0: at the end only)", "0"},
      {"checkpoint-every", "N", "checkpoint every N steps (0: at the end only)", "500"},
      {"time-limit", "S", "stop after the step that reaches S seconds of training (the outputs are written as at the end; --resume continues)", ""},
      {"profile", "", "progress lines name the three costliest stages, and the end prints every stage's mean ms per step (always in metrics.json's \"profile\")", ""},
  };
  for (auto& d : datasetOptions()) o.push_back(d);
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"train", "jointly optimise the water surface and the Gaussians under it", "refrax train <dataset> -o RUN [options] | refrax train --resume RUN",
                trainOptions(), runTrain});

}  // namespace
}  // namespace refrax
