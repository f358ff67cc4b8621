// `refrax train` end to end on tiny synthetic presets: refraction against the straight-ray
// model, resuming from a checkpoint, and bad datasets. Sizes are CI-sized (lavapipe, 2 cores):
// few Gaussians and steps; the bars below were set from measured runs (see each CHECK).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "engine/dataset/dataset.h"
#include "engine/dataset/ground_truth.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/height/height_field.h"
#include "engine/surface/surface_prior.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/train/checkpoint.h"
#include "engine/model/render_model.h"
#include "engine/train/train_run.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"
#include "tests/water_json_height.h"

namespace fs = std::filesystem;

namespace refrax {
namespace {

using test::TrainTempDir;

const char* kTinyOptions = " --steps 300 --gaussians 2000 --patch 32 --progress-every 100 --checkpoint-every 0";
// The refraction runs below take the GPU's water settings (test::kGpuWater300StepOptions).
// Measured (lavapipe, seed 1, the model sized from the data): test PSNR 16.00 to 16.17 after
// 300 steps over four runs; the bar leaves 1.0 dB.
constexpr double kRefractionPsnrBar = 15.0;
// Float atomics in the backward passes add in thread order, so even two uninterrupted runs
// differ (measured on lavapipe, 40 steps: parameter differences max 0.019, RMS 8e-4, test
// PSNR equal to 1e-4 dB); a resumed run must stay within that run-to-run spread.
constexpr double kResumePsnrTolerance = 0.05;
constexpr double kResumeParameterRms = 5e-3;

// The refraction and straight-ray models trained once per test process on the same data.
struct TinyComparison {
  TrainTempDir dir;
  nlohmann::json refraction, plain;
};
const TinyComparison& tinyComparison() {
  static TinyComparison c = [] {
    TinyComparison t;
    std::string data = test::tinyDataset("nerfrac-primary-sine");
    t.refraction = test::trainAndReadMetrics(data, t.dir / "refraction", std::string(kTinyOptions) + test::kGpuWater300StepOptions);
    t.plain = test::trainAndReadMetrics(data, t.dir / "plain", std::string(kTinyOptions) + " --no-refraction");
    MESSAGE("refraction psnr " << t.refraction["psnr"] << " ssim " << t.refraction["ssim"] << " surface rmse "
                               << t.refraction["surface_rmse"] << " (flat " << t.refraction["initial_flat_surface_rmse"]
                               << "); no-refraction psnr " << t.plain["psnr"] << "; water-removal psnr " << t.refraction["water_removal_psnr"]
                               << " against " << t.plain["water_removal_psnr"]);
    return t;
  }();
  return c;
}

// The refraction and straight-ray runs of seeds 1-3 (seed 1: tinyComparison's), for the one
// comparison a seed decides by more than its bar: the water-removal PSNR, about 0.5 dB apart
// with a spread of as much.
constexpr double kWaterRemovalBehindBar = 1.0;
std::vector<std::pair<nlohmann::json, nlohmann::json>> tinySeedPairs(const TinyComparison& c) {
  static std::vector<std::pair<nlohmann::json, nlohmann::json>> pairs = [&] {
    std::vector<std::pair<nlohmann::json, nlohmann::json>> p{{c.refraction, c.plain}};
    std::string data = test::tinyDataset("nerfrac-primary-sine");
    for (int seed = 2; seed <= 3; seed++) {
      const std::string options = std::string(kTinyOptions) + " --seed " + std::to_string(seed);
      p.push_back({test::trainAndReadMetrics(data, c.dir / ("refraction-" + std::to_string(seed)), options + test::kGpuWater300StepOptions),
                   test::trainAndReadMetrics(data, c.dir / ("plain-" + std::to_string(seed)), options + " --no-refraction")});
    }
    return p;
  }();
  return pairs;
}

// One test case, two subcases: CTest runs each case in a process of its own, and the two
// trainings behind both (tinyComparison) cost about 30 s here and 90 s under ASan; the
// quality subcase trains two seeds more of each (tinySeedPairs).
TEST_CASE("train: a tiny NeRFrac-like run writes every output, reaches the measured PSNR, and profiles each stage") {
  const TinyComparison& c = tinyComparison();
  SUBCASE("its outputs and quality") {
    for (const char* f : {"config.json", "metrics.json", "point_cloud.ply", "water_height.npy", "height_field.bin", "renders/test_000.png",
                          "renders/test_000_air.png"})
      CHECK_MESSAGE(fs::exists(fs::path(c.dir / "refraction") / f), f);
    CHECK(!fs::exists(fs::path(c.dir / "plain") / "water_height.npy"));
    CHECK(c.refraction["psnr"].get<double>() >= kRefractionPsnrBar);
    CHECK(c.refraction["gaussians"].get<uint64_t>() == readGaussiansPly(c.dir / "refraction/point_cloud.ply").count());
    CHECK(c.refraction.contains("water_removal_psnr"));
    CHECK(c.refraction["missed_rays"].get<uint64_t>() == 0);
    // The surface's own metrics are reported, each consistent with its parts; how well each one
    // judges a surface is tested where it is computed (correlation: test_metrics.cpp; the sweep
    // agreement: test_plane_sweep.cpp; the mirror: test_water_sign.cpp). 300 steps leave this
    // surface worse than the flat start: measured over three runs (lavapipe, the model sized from
    // the data) surface RMSE 0.0376 to 0.0382 against a flat start of 0.0173, correlation 0.11 to
    // 0.13, sweep ratio 2.04 to 2.07, mirror ratio 1.04 to 1.24 (warned in each). So no bound
    // on the correlation or the mirror ratio holds from what this run must do; the one that
    // does is the sweep's: a surface this far behind flat water must read as agreeing less.
    // Beside the RMSE, the learned heights' correlation with the true ones at the same points:
    // present, and a correlation.
    const double rmse = c.refraction["surface_rmse"].get<double>(), flatRmse = c.refraction["initial_flat_surface_rmse"].get<double>();
    CHECK(c.refraction["surface_points"].get<uint64_t>() > 0);
    CHECK(std::abs(c.refraction["surface_correlation"].get<double>()) <= 1);
    CHECK(!c.plain.contains("surface_correlation"));
    // The learned water's checks (docs/training.md, "Is the learned water right?"): only where water is learned.
    CHECK(!c.refraction.contains("surface_unchecked"));
    const nlohmann::json& agreement = c.refraction["surface_agreement"];
    const double ratio = agreement["ratio"].get<double>();
    CHECK(agreement["cells"].get<uint64_t>() > 0);
    CHECK(agreement["flat_sweep_cost"].get<double>() > 0);
    CHECK(ratio == doctest::Approx(agreement["sweep_cost"].get<double>() / agreement["flat_sweep_cost"].get<double>()));
    CHECK(agreement["warned"].get<bool>() == (ratio > 1.02));  // engine/train/train_run.cpp kAgreementWarning
    INFO("surface rmse " << rmse << " against the flat start's " << flatRmse << ", sweep ratio " << ratio);
    if (rmse > 1.5 * flatRmse) CHECK(agreement["warned"].get<bool>());
    // the waves against their mirror image: present, positive, and read against its 0.95 (kMirrorBetter)
    const double mirror = agreement["mirror_ratio"].get<double>();
    CHECK(mirror > 0);
    CHECK(agreement["mirror_better"].get<bool>() == (mirror < 0.95));
    CHECK(c.refraction["surface_roughening"]["judged"].get<bool>());
    CHECK(c.refraction["surface_watch"].size() >= 50);
    CHECK(!c.plain.contains("surface_agreement"));
    CHECK(!c.plain.contains("surface_watch"));
    NpyArray heights = readNpy(c.dir / "refraction/water_height.npy");
    const size_t vertices = readJson(c.dir / "refraction/config.json")["grid_cells"].get<size_t>() + 1;  // the grid the data sized
    CHECK(heights.shape == std::vector<size_t>{vertices, vertices});
    // The straight-ray model's Gaussians sit where the water makes the scene appear, so with the
    // water removed it must not see the scene much better than the refraction model, on the
    // median of three seeds (the pairs below). Measured with the model sized from the data (16 x 2
    // grid, 4 octaves; lavapipe): refraction behind by 0.27, 0.87 and 0.44 dB at seeds 1-3 at
    // 72305e4, by 0.86, 0.54 and 0.87 at 27fed7b (whose random draws differ: over seeds 1-7 the
    // refraction's water-removal PSNR has medians 16.62 and 16.53 dB, spreads 0.45 and 0.99),
    // so one seed against the earlier bar of 0.6 dB passed about as often as it failed; with the
    // refraction planted wrong (eta = n_water instead of 1 / n_water) behind by 1.28 dB in each of
    // two runs of seed 1 (earlier), and by 1.22, 1.53 and 1.98 at seeds 1-3 planted again at
    // 27fed7b (median 1.53: fails).
    std::vector<double> behind;
    for (const auto& [refraction, plain] : tinySeedPairs(c))
      behind.push_back(plain["water_removal_psnr"].get<double>() - refraction["water_removal_psnr"].get<double>());
    std::sort(behind.begin(), behind.end());
    INFO("refraction's water-removal PSNR behind straight rays', seeds 1-3: " << behind[0] << ", " << behind[1] << ", " << behind[2]);
    CHECK(behind[1] <= kWaterRemovalBehindBar);
    // The four views between the rig's training cameras (refrax synth's between/), reported
    // apart from the protocol's test view: views of the same water and floor from inside the
    // rig, so as well fitted. Measured (lavapipe, 300 steps): 0.44 and 0.66 dB over the test
    // view for refraction (seeds 1, 2), 0.58 for straight rays. This holds the split's
    // plumbing (its four views, their images and masks, PSNR against the right pictures), not
    // the water: at IOR 1.1 these views read nearly alike with it removed (16.60 against 16.83 dB).
    for (const nlohmann::json* m : {&c.refraction, &c.plain}) {
      CHECK((*m)["between_views"].get<uint64_t>() == 4);
      CHECK(std::abs((*m)["between_psnr"].get<double>() - (*m)["psnr"].get<double>()) <= 1.5);
      CHECK((*m)["between_ssim"].get<double>() > 0);
      CHECK((*m)["between_ssim"].get<double>() <= 1);
    }
  }
  // Every run's metrics.json gives the mean time per step of each stage (engine/vk/vk_profile.h),
  // and --profile prints them.
  SUBCASE("metrics.json profiles each stage of a step, and --profile prints the table") {
    const nlohmann::json& p = c.refraction["profile"];
    CHECK(p["steps"] == 300);
    const double wall = p["wall_ms_per_step"].get<double>();
    CHECK(wall > 0);
    CHECK(p["submits_per_step"].get<double>() >= 1);
    CHECK(p["dispatches_per_step"].get<double>() >= 1);
    REQUIRE(p["timestamps"].get<bool>());  // lavapipe writes them
    double gpu = 0;
    for (auto& [stage, ms] : p["gpu"].items()) {
      CHECK_MESSAGE(ms.get<double>() >= 0, stage);
      gpu += ms.get<double>();
    }
    CHECK(gpu == doctest::Approx(p["gpu_ms_per_step"].get<double>()));
    CHECK(gpu <= wall);  // every submission is waited for within its step
    for (const char* stage : {"camera rays", "water trace: global trace", "water trace: refract", "gaussian forward", "loss",
                              "gaussian backward", "water backward: to heights", "water backward: to weights", "water adam",
                              "water update (heights, refit)"})
      CHECK_MESSAGE(p["gpu"].contains(stage), stage);
    CHECK(p["gpu"].contains("gaussian adam"));  // the Gaussians step on the device (gaussian_device_step.h)
    const nlohmann::json& plain = c.plain["profile"]["gpu"];
    CHECK(plain.contains("gaussian forward"));
    // Straight rays: one submission a step (forward, backward, the Gaussians' Adam and their
    // proxies' refit), but at the steps where the host densifies or reorders the proxies.
    CHECK(c.plain["profile"]["submits_per_step"].get<double>() < 1.2);
    // Refraction: the water's trace is one submission with the forward, the loss, the backward,
    // the Gaussians' step (each level's new lattice points counted on the device) and, where the
    // water steps, its gradient's points listed and pushed on the count the device wrote, its
    // Adam step and the surface's update; more at the anchor's re-lifts and the host's events
    // (the restarts' plane sweeps). Measured 1.23 here; 1.34 when the water's step was a
    // submission of its own, 1.45 when the push read its count back, and 6.45 (40 steps of the
    // defaults) when the trace read each level's count back.
    CHECK_MESSAGE(p["submits_per_step"].get<double>() < 1.3, p["submits_per_step"].get<double>());
    {
      // As a discrete GPU counts them (REFRAX_FORCE_STAGING: lavapipe maps device memory, so
      // its transfers cost no submission): the batch's uploads ride in the step's own command
      // buffer, the surface step's anchor, priors and divergence check read the heights its
      // submissions copied, and the priors' gradient is added on the device in the push's
      // submission (addGridGradient). Measured 1.41; 1.53 when the water's step was a
      // submission of its own, 1.75 when the priors' gradient was read back and written again,
      // 4.2 when each upload and each read of the heights was a submission of its own.
      TrainTempDir staged;
      const char* cli = std::getenv("REFRAX_CLI");
      test::CliResult r = test::runShell("REFRAX_FORCE_STAGING=1 " + std::string(cli ? cli : REFRAX_CLI) + " train " +
                                         test::tinyDataset("nerfrac-primary-sine") + " -o " + (staged / "run") + kTinyOptions + test::kGpuWater300StepOptions);
      INFO(r.output);
      REQUIRE(r.exitCode == 0);
      const double submits = readJson(staged / "run/metrics.json")["profile"]["submits_per_step"].get<double>();
      CHECK_MESSAGE(submits < 1.5, submits);
    }
    CHECK(plain.contains("gaussian proxies"));
    for (auto& [stage, ms] : plain.items()) CHECK_MESSAGE(stage.rfind("water", 0) != 0, stage);  // no water in straight rays

    TrainTempDir dir;
    test::CliResult r = test::runCli("train " + test::tinyDataset("nerfrac-primary-sine") + " -o " + (dir / "run") +
                                     " --steps 12 --gaussians 300 --patch 16 --progress-every 6 --checkpoint-every 0 --profile");
    INFO(r.output);
    REQUIRE(r.exitCode == 0);
    CHECK(r.output.find("profile: 12 steps") != std::string::npos);
    CHECK(r.output.find("gaussian forward") != std::string::npos);
    CHECK(r.output.find("steps/s  eta 0 s  | ") != std::string::npos);  // the progress line's three costliest stages
  }
}

// Strong refraction (IOR 1.33, the preset's sine at twice its amplitude: 0.05 m, slope 0.63)
// at 96 px, where straight rays cannot fake the water: measured with the water known (oracle)
// 21.5 dB against 15.6 dB for --no-refraction after 3,000 steps of 32 x 32 patches. The joint run uses what short
// runs need (see --help): three octaves, a faster surface, the anchored mean height, the level
// prior, the slope prior (below), and the Gaussians drawn afresh three times as the surface learns the wave, each time
// at the depth a plane sweep finds through the water learned so far; a surface step per step
// (the reference: no --surface-batch). The presets table and the demo sum a pass over the views
// per surface step (--surface-batch views: with a step per view the surface ran away on 5 of
// the 9 weak-wave presets), but on this strong wave that trails by about 1.3 dB, which left
// this test's 3 dB bar a coin toss (docs/experiments/2026-11-26-surface-batch.md, 2026-11-27).
const char* kStrongWaveSynth = "--width 96 --ior 1.33 --wave-amplitude 2";
const char* kStrongWaveOptions =
    " --recipe reference --steps 4000 --patch 64 --gaussians 2000 --max-gaussians 4000 --density-reset-every 0 --sh-degree 0 --progress-every 500 "
    "--checkpoint-every 0";
const char* kStrongWaveJoint = " --mlp-octaves 4 --grid-cells 16 --subdivision 2"
                               " --mlp-coarse-octaves 3 --octaves-open-until 10000000 --surface-lr 3e-3 --surface-freeze 400 --anchor-mean-height"
                               " --level-prior 1000 --surface-smoothness 0.1 --init-depth sweep --restart-gaussians 1000,1600,2200";

// Three seeds of the joint run and one straight-ray run (its spread is small: 15.71-16.40 dB
// over the runs below), each gain taken against that one.
constexpr int kStrongWaveSeeds = 3;
struct StrongWaveComparison {
  TrainTempDir dir;
  std::vector<nlohmann::json> refraction;  // seeds 1..kStrongWaveSeeds
  nlohmann::json plain;                    // seed 1
};
const StrongWaveComparison& strongWaveComparison() {
  static StrongWaveComparison c = [] {
    StrongWaveComparison t;
    std::string data = test::tinyDataset("nerfrac-primary-sine", kStrongWaveSynth);
    t.plain = test::trainAndReadMetrics(data, t.dir / "plain", std::string(kStrongWaveOptions) + " --no-refraction");
    for (int seed = 1; seed <= kStrongWaveSeeds; seed++) {
      std::string run = t.dir / ("refraction-" + std::to_string(seed));
      t.refraction.push_back(
          test::trainAndReadMetrics(data, run, std::string(kStrongWaveOptions) + kStrongWaveJoint + " --seed " + std::to_string(seed)));
      const nlohmann::json& m = t.refraction.back();
      MESSAGE("strong wave, seed " << seed << ": refraction psnr " << m["psnr"] << " (gain "
                                   << m["psnr"].get<double>() - t.plain["psnr"].get<double>() << " dB) surface rmse "
                                   << m["surface_rmse"] << " (flat " << m["initial_flat_surface_rmse"] << ")");
    }
    MESSAGE("strong wave: no-refraction psnr " << t.plain["psnr"]);
    return t;
  }();
  return c;
}

constexpr double kStrongWaveGainBar = 3.0;     // dB over straight rays, the median seed
constexpr double kStrongWaveSurfaceBar = 0.5;  // of the flat start's surface RMSE, the median seed
constexpr double kStrongWaveWorstGain = 0.0;   // the worst seed
constexpr double kStrongWaveWorstSurface = 1.0;
constexpr double kStrongWavePlainFloor = 15.0;  // dB: straight rays measured 15.71-16.40

double medianOf(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// The paper's claim at CI size: refraction beats straight rays by 3 dB and recovers the
// surface to half the flat plane's error (issue 6's bars), asserted on the median of three
// seeds, with the worst seed held to never losing to straight rays nor ending further from the
// truth than the flat start. One run of one seed could not carry the claim: it failed once in
// about ten (below, +0.70 dB in CI), and a rerun until it passed hid that (issue 47). Measured (lavapipe, 64 x 64
// patches, against --no-refraction with the same seed and steps):
//   this test, seed 1: 2026-11-26, three runs: +3.29, +3.98, +3.79 dB (19.69, 20.38, 20.19
//   against 16.40), surface RMSE 0.0094, 0.0118, 0.0113 (0.28-0.36x the flat plane's);
//   2026-11-27, four runs of the refraction arm: 20.03, 21.20, 20.10, 20.17 dB (straight
//   rays: 15.99-16.31 in five runs that day; the last run's pair +4.10 dB), 0.0118, 0.0103,
//   0.0138, 0.0113 m (0.31-0.41x); and once in CI, 18.77 against 16.11 (+2.66: failed);
//   with the densification statistic scaled to the batch (densifyStatScale, 4x at 64 x 64):
//   two runs 20.82, 20.40 dB against 16.14 (+4.68, +4.26), 0.34x, 0.30x; 6,000 steps before
//   that change: 20.86, 20.74 against 16.08, climbing about 0.5 dB per 1,000 steps after 4,000;
//   5,000 steps with it: 20.11 (one run; the spread, not the steps, decides a run);
//   seed 2 +2.96 dB (19.09 against 16.14), 0.42x; seed 3 +5.52 dB (21.23 against 15.71), 0.32x;
//   --surface-batch views, seed 1, 13 runs over six commits (2026-11-26 and 27): 18.87-20.36
//   dB, mean 19.4 (+3.3 over straight rays: it failed three of five suite runs);
//   --surface-batch 20: +2.89 dB, 0.44x (one run);
//   3,000 steps, restarts as here: seeds 1, 2, 3 +2.90, +2.80, +1.97 dB, 0.42, 0.42, 0.54x;
//   3,000 steps, one restart at 1,200 from the box (the earlier settings): +2.04 to +2.49 dB,
//   0.48-0.64x.
// The model is sized here, not from the data: at 96 px the data's size is a 32 x 2 grid and 5
// octaves, of which this window opens 3 in 4,000 steps, and the unused lattice doubled the
// refraction step (148 against 75 ms at 400 steps); the test took 940 s alone (2026-11-28,
// +4.03 dB in its last suite run). Pinned to what the data gave on 2026-11-27 (16 x 2, 4
// octaves: passed, 487 s alone then), 632 s alone; one run printed 20.87 against 15.95 dB (+4.92),
// surface 0.27x the flat plane's. In a CI-like run from a clean clone that day it failed once
// far under the bars (16.77 against 16.07, +0.70 dB; surface 0.67x) and passed on its retry:
// three passes and one failure at this size, two passes at 32 x 2, too few to tell them apart.
// Since the MLP runs on padded straight-line kernels (2026-11-28, these 4 octaves on the
// 6-octave kernels), three runs of the refraction arm alone: 21.86, 22.01, 21.97 dB, surface
// 0.27x, 0.22x, 0.25x the flat plane's, 248-271 s each; in a CI-like run the whole test passed
// in 527 s (618 s before).
// What the last steps add is the Gaussians' refit after the third restart (800 steps at
// 3,000). Gradient sums are not deterministic, so one seed varies between runs: seed 1's
// refraction arm spread over 18.77-21.20 dB in its ten runs at 4,000 steps with a surface
// step per step, and one of them (the CI run) missed the gain's bar. The bars are the issue's;
// the surface's margin is 0.07x under the worst run's.
// Three seeds (2026-12-02, lavapipe, the arms run by hand as this test runs them): straight
// rays 16.15 dB; seeds 1, 2, 3 22.09, 21.76, 22.71 dB (+5.94, +5.61, +6.56), surface 0.31x,
// 0.17x, 0.18x the flat start's; the four arms 1,456 s beside builds.
// The slope prior (--surface-smoothness 0.1, the defaults' value): without it seed 1's water
// left the scene twice in four suite runs (2026-12-06: at steps 2,523 and 3,245, each after a
// restart, a surface step per step at --surface-lr 3e-3); with it three seeds held, +3.13,
// +4.02, +5.28 dB, 0.25-0.29x the flat start's error (docs/experiments/2026-12-06-steps.md).
TEST_CASE("train: refraction beats straight rays and halves the flat surface error on a tiny NeRFrac-like run" *
          doctest::test_suite("long")) {
  const StrongWaveComparison& c = strongWaveComparison();
  const double plain = c.plain["psnr"].get<double>();
  // The straight-ray run's floor: a regression there would widen every gain below.
  CHECK(plain >= kStrongWavePlainFloor);
  std::vector<double> gains, surfaceRatios;
  for (size_t k = 0; k < c.refraction.size(); k++) {
    const nlohmann::json& m = c.refraction[k];
    double gain = m["psnr"].get<double>() - plain;
    double ratio = m["surface_rmse"].get<double>() / m["initial_flat_surface_rmse"].get<double>();
    gains.push_back(gain), surfaceRatios.push_back(ratio);
    // Every seed under the median's bars is a failure of the method on that seed, logged even
    // when the median passes.
    if (gain < kStrongWaveGainBar || ratio > kStrongWaveSurfaceBar)
      WARN_MESSAGE(false, "strong wave, seed " << k + 1 << " under the bars: gain " << gain << " dB, surface " << ratio << "x the flat start's");
    // The worst seed: refraction never loses to straight rays, and its water never ends
    // further from the truth than the flat start (a surface that ran away).
    CHECK(gain >= kStrongWaveWorstGain);
    CHECK(ratio <= kStrongWaveWorstSurface);
    CHECK(m["missed_rays"].get<uint64_t>() == 0);
  }
  // The median of the three seeds: the bars.
  CHECK(medianOf(gains) >= kStrongWaveGainBar);
  CHECK(medianOf(surfaceRatios) <= kStrongWaveSurfaceBar);
}

GPU_TEST_CASE("train: resuming from a mid-run checkpoint ends where the uninterrupted run ends" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 40, 1000, 32, rng(), d);
  c.checkpointEvery = 20;
  TrainProgress quiet;

  auto whole = createTrainSession(ctx, c, d);
  nlohmann::json a = trainToEnd(*whole, dir / "whole", quiet);

  // The roughening watch (engine/surface/surface_watch.h) samples every step of so short a run
  // once the surface has stepped, and judges the series; a run resumed from the checkpoint at
  // step 20 keeps the samples before it (RUN/surface_watch.json) and ends with as many.
  REQUIRE(a.contains("surface_watch"));
  CHECK(a["surface_watch"].size() >= 30);
  CHECK(a["surface_roughening"]["judged"].get<bool>());
  fs::copy(dir / "whole", dir / "rewound", fs::copy_options::recursive);
  fs::remove(checkpointPath(dir / "rewound", 40));
  auto rewound = createTrainSession(ctx, c, d);
  loadCheckpoint(*rewound, latestCheckpoint(dir / "rewound"));
  REQUIRE(rewound->model.step == 20);
  nlohmann::json again = trainToEnd(*rewound, dir / "rewound", quiet);
  REQUIRE(again["surface_watch"].size() == a["surface_watch"].size());
  for (size_t k = 0; k < a["surface_watch"].size(); k++) {
    CHECK(again["surface_watch"][k]["step"] == a["surface_watch"][k]["step"]);
    if (a["surface_watch"][k]["step"].get<int>() <= 20) CHECK(again["surface_watch"][k]["loss"] == a["surface_watch"][k]["loss"]);
  }

  auto first = createTrainSession(ctx, c, d);
  while (first->model.step < 20) trainStep(*first);
  saveCheckpoint(*first, dir / "split");
  first.reset();
  auto second = createTrainSession(ctx, c, d);
  loadCheckpoint(*second, latestCheckpoint(dir / "split"));
  CHECK(second->model.step == 20);
  nlohmann::json b = trainToEnd(*second, dir / "split", quiet);

  REQUIRE(whole->model.gaussians.params.size() == second->model.gaussians.params.size());
  double sumSquares = 0;
  for (size_t i = 0; i < whole->model.gaussians.params.size(); i++)
    sumSquares += std::pow(double(whole->model.gaussians.params[i]) - double(second->model.gaussians.params[i]), 2);
  double rms = std::sqrt(sumSquares / double(whole->model.gaussians.params.size()));
  MESSAGE("psnr " << a["psnr"] << " vs " << b["psnr"] << ", parameter difference RMS " << rms);
  CHECK(std::abs(a["psnr"].get<double>() - b["psnr"].get<double>()) <= kResumePsnrTolerance);
  CHECK(std::abs(a["ssim"].get<double>() - b["ssim"].get<double>()) <= 1e-3);
  CHECK(std::abs(a["surface_rmse"].get<double>() - b["surface_rmse"].get<double>()) <= 1e-4);
  CHECK(rms <= kResumeParameterRms);

  // A corrupted checkpoint is one clear error, for the engine and the CLI.
  std::string path = latestCheckpoint(dir / "split");
  std::string bytes = readFile(path);
  bytes[bytes.size() / 2] ^= 0x5a;
  writeFileAtomic(path, bytes.data(), bytes.size());
  auto third = createTrainSession(ctx, c, d);
  CHECK_THROWS_WITH_AS(loadCheckpoint(*third, path), doctest::Contains("corrupted"), Error);
  writeTextAtomic(dir / "split/config.json", trainConfigToJson(c).dump());
  test::CliResult r = test::runCli("train --resume " + (dir / "split"));
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("corrupted") != std::string::npos);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
}

GPU_TEST_CASE("train: --restart-gaussians draws the Gaussians afresh at its step, the same after a resume, and is validated" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 10, 300, 16, rng(), d);
  c.schedule.gaussianRestarts = {6, 8};
  c.schedule.surfaceFreeze = 0;  // the surface learns from the start, and its fit must survive
  const float freshLogit = float(std::log(c.initialDensity / (1.0 - c.initialDensity)));

  auto whole = createTrainSession(ctx, c, d);
  while (whole->model.step < 5) CHECK(!trainStep(*whole).restarted);
  saveCheckpoint(*whole, dir / "split");
  const GaussianSet before = whole->model.gaussians;
  std::vector<float> heightWeights = downloadVector<float>(ctx, whole->model.height->weights, whole->model.height->parameterCount);
  StepResult r = trainStep(*whole);
  REQUIRE(whole->model.step == 6);
  CHECK(r.restarted);
  CHECK(r.gaussians == 300);
  REQUIRE(whole->model.gaussians.count() == 300);
  // Fresh: every density back at its initial value, no Adam moments, schedules from their start.
  size_t notFresh = 0;
  for (size_t i = 0; i < 300; i++) notFresh += whole->model.gaussians.at(i)[f32::kGaussLogitDensity] != freshLogit;
  CHECK(notFresh == 0);
  CHECK(std::all_of(whole->state.gaussianAdam.m.begin(), whole->state.gaussianAdam.m.end(), [](float x) { return x == 0.0f; }));
  CHECK(std::all_of(whole->state.gaussianAdam.v.begin(), whole->state.gaussianAdam.v.end(), [](float x) { return x == 0.0f; }));
  for (const auto& g : whole->state.gaussianAdam.groups) CHECK(g.step == 0);
  // New positions, not the trained ones with their densities reset.
  double moved = 0;
  for (size_t i = 0; i < std::min(before.count(), whole->model.gaussians.count()); i++)
    moved += std::abs(whole->model.gaussians.at(i)[f32::kGaussMean] - before.at(i)[f32::kGaussMean]);
  CHECK(moved / 300.0 > 0.01);
  // The surface is kept: step 6 took one more surface update, which is small next to the
  // field's weights.
  std::vector<float> after = downloadVector<float>(ctx, whole->model.height->weights, whole->model.height->parameterCount);
  double change = 0, norm = 0;
  for (size_t i = 0; i < after.size(); i++) change += std::pow(after[i] - heightWeights[i], 2), norm += std::pow(heightWeights[i], 2);
  CHECK(std::sqrt(change) < 0.05 * std::sqrt(norm));

  // A run resumed before the restart draws the same fresh Gaussians (the RNG is checkpointed)
  // and goes on to the end.
  auto resumed = createTrainSession(ctx, c, d);
  loadCheckpoint(*resumed, latestCheckpoint(dir / "split"));
  REQUIRE(resumed->model.step == 5);
  CHECK(trainStep(*resumed).restarted);
  CHECK(resumed->model.gaussians.params == whole->model.gaussians.params);
  // The second restart, and no other.
  while (resumed->model.step < c.steps) {
    bool restarted = trainStep(*resumed).restarted;
    CHECK(restarted == (resumed->model.step == 8));
  }

  // config.json keeps the steps; runs written with one step, or before the option, read as
  // they ran; a step at or past the last is refused, on the command line too, as is a list
  // that is not one.
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").schedule.gaussianRestarts == std::vector<int>{6, 8});
  nlohmann::json old = trainConfigToJson(c);
  old["schedule"].erase("gaussian_restarts");
  CHECK(trainConfigFromJson(old, "test").schedule.gaussianRestarts.empty());
  old["schedule"]["gaussian_restart"] = 7;
  CHECK(trainConfigFromJson(old, "test").schedule.gaussianRestarts == std::vector<int>{7});
  c.schedule.gaussianRestarts = {6, c.steps};
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--restart-gaussians"), Error);
  for (const char* bad : {"4", "1,x", "2,,3"}) {
    test::CliResult cli = test::runCli("train " + data + " -o " + (dir / "late") + " --steps 4 --restart-gaussians " + bad + " --gaussians 100");
    CHECK(cli.exitCode != 0);
    CHECK(cli.output.find("--restart-gaussians") != std::string::npos);
    CHECK(!fs::exists(dir / "late"));
  }
}

// Runs `refrax train` on a broken copy of the tiny dataset: one clear error naming `expect`,
// a non-zero exit and no run folder (extra `options` appended).
void expectCleanFailure(const std::string& dataset, const std::string& run, const std::string& expect, const std::string& options = "") {
  test::CliResult r = test::runCli("train " + dataset + " -o " + run + " --steps 2 --gaussians 100" + options);
  INFO(r.output);
  CHECK(r.exitCode != 0);
  CHECK(r.output.find(expect) != std::string::npos);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
  CHECK(!fs::exists(run));
}

// The oracle's heights against water.json's formula at every node of water_height.npy.
double worstKnownWaterError(const std::string& data, const std::string& run) {
  nlohmann::json surface = readJson(data + "/water.json")["surface"];
  NpyArray h = readNpy(run + "/water_height.npy");
  REQUIRE(h.shape.size() == 2);
  auto domain = readJson(run + "/metrics.json")["water_height_domain"];
  size_t ny = h.shape[0], nx = h.shape[1], worst = 0;
  double worstDiff = 0;
  for (size_t j = 0; j < ny; j++)
    for (size_t i = 0; i < nx; i++) {
      double x = domain[0].get<double>() + (domain[2].get<double>() - domain[0].get<double>()) * double(i) / double(nx - 1);
      double y = domain[1].get<double>() + (domain[3].get<double>() - domain[1].get<double>()) * double(j) / double(ny - 1);
      double diff = std::abs(h.data[j * nx + i] - test::heightFromJson(surface, x, y));
      if (diff > worstDiff) worstDiff = diff, worst = j * nx + i;
    }
  INFO("worst height difference " << worstDiff << " at " << worst);
  return worstDiff;
}

TEST_CASE("train: the known-water oracle keeps the true surface fixed, ripples included, the height map where no closed form holds it" *
          doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  nlohmann::json m = test::trainAndReadMetrics(data, dir / "known", " --known-water --steps 20 --gaussians 500 --patch 16 --checkpoint-every 0");
  // Measured 0.00023 against the flat plane's 0.0173: only the proxy mesh's facets and the
  // ground-truth height map's bilinear sampling differ from the true sine.
  CHECK(m["surface_rmse"].get<double>() * 20 <= m["initial_flat_surface_rmse"].get<double>());
  CHECK(worstKnownWaterError(data, dir / "known") <= 1e-5);  // float32 positions (x, y up to ~1) through sin

  // A radial ripple with its sines (the hybrid preset; the random scenes draw them too): the
  // oracle holds it as refrax synth drew it. Before ripples were held the oracle refused such
  // scenes, and a ripple read as a sine (its sigma dropped) is off by its whole amplitude.
  const std::string hybrid = test::tinyDataset("nerfrac-hybrid");
  REQUIRE(!readJson(hybrid + "/water.json")["surface"]["radial_ripples"].empty());
  nlohmann::json r = test::trainAndReadMetrics(hybrid, dir / "hybrid", " --known-water --steps 4 --gaussians 300 --patch 16 --checkpoint-every 0");
  CHECK(r["surface_rmse"].get<double>() * 20 <= r["initial_flat_surface_rmse"].get<double>());
  CHECK(worstKnownWaterError(hybrid, dir / "hybrid") <= 1e-5);

  // Six sines (the desk preset) are more than the closed form's four components: the oracle
  // takes water.json's height map instead, sampled bilinearly (before, it refused such water,
  // so the desk, kitchen and toys presets had no oracle).
  const std::string desk = test::tinyDataset("desk");
  REQUIRE(readJson(desk + "/water.json")["surface"]["directional_waves"].size() > 4);
  nlohmann::json d = test::trainAndReadMetrics(desk, dir / "desk", " --known-water --steps 4 --gaussians 300 --patch 16 --checkpoint-every 0");
  CHECK(d["surface_rmse"].get<double>() * 5 <= d["initial_flat_surface_rmse"].get<double>());  // 0.1 measured
  {
    const HeightGrid truth = *loadGroundTruthSurface(loadDataset(desk));
    NpyArray h = readNpy(dir / "desk" + "/water_height.npy");
    REQUIRE(h.shape.size() == 2);
    auto domain = d["water_height_domain"];
    double worst = 0;
    for (size_t j = 0; j < h.shape[0]; j++)
      for (size_t i = 0; i < h.shape[1]; i++) {
        double x = domain[0].get<double>() + (domain[2].get<double>() - domain[0].get<double>()) * double(i) / double(h.shape[1] - 1);
        double y = domain[1].get<double>() + (domain[3].get<double>() - domain[1].get<double>()) * double(j) / double(h.shape[0] - 1);
        worst = std::max(worst, std::abs(h.data[j * h.shape[1] + i] - sampleHeight(truth, x, y)));
      }
    INFO("worst height difference from the height map " << worst);
    CHECK(worst <= 1e-5);
  }

  // Five terms and no height map: the oracle has nothing to hold, and says why.
  const std::string five = dir / "five";
  fs::copy(data, five, fs::copy_options::recursive);
  nlohmann::json water = readJson(five + "/water.json");
  nlohmann::json& waves = water["surface"]["directional_waves"];
  while (waves.size() + water["surface"]["radial_ripples"].size() < 5) waves.push_back(waves[0]);
  water.erase("height_map");
  writeJson(five + "/water.json", water);
  expectCleanFailure(five, dir / "five-run", "at most 4 directional waves and radial ripples", " --known-water");
}

TEST_CASE("train: --surface-lr sets the surface's first Adam step, survives config.json, and is validated" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  // Adam's first step moves each parameter by the learning rate (|m / sqrt(v)| = 1), so a flat
  // plane unfrozen from step 0 ends one step at +-0.02 from its start (the water height, 0).
  nlohmann::json m = test::trainAndReadMetrics(
      data, dir / "flat", " --recipe reference --flat-water --surface-lr 0.02 --surface-freeze 0 --lr-steps 100000000 --steps 1 --gaussians 200 --patch 16 --checkpoint-every 0");
  CHECK(std::abs(m["flat_water_height"].get<double>()) == doctest::Approx(0.02).epsilon(1e-3));
  TrainConfig c = trainConfigFromJson(readJson(dir / "flat/config.json"), "config.json");
  CHECK(c.surfaceLearningRate == 0.02);
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").surfaceLearningRate == 0.02);
  for (double bad : {0.0, -1e-3, 1.0, double(NAN)}) {
    c.surfaceLearningRate = bad;
    CHECK_THROWS_AS(validateTrainConfig(c), Error);
  }
}

// A run's learned water heights (water_height.npy, n x n) on a grid of unit spacing: the
// surface-prior tests measure them with the priors' own energies.
struct LearnedHeights {
  std::vector<float> heights;
  GridLayout grid;
};
LearnedHeights learnedHeights(const fs::path& run) {
  NpyArray h = readNpy((run / "water_height.npy").string());
  const uint32_t n = uint32_t(h.shape.at(0));
  return {std::vector<float>(h.data.begin(), h.data.end()), GridLayout{n - 1, n - 1, n, 0, 1.0, 1.0}};
}

TEST_CASE("train: --surface-batch steps the surface once per N steps, survives config.json, and is validated" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  // The flat plane learns from step 0; with N = 3 its first Adam step (a move of exactly the
  // learning rate) comes at step 3, not before.
  std::string flat = " --flat-water --surface-lr 0.02 --surface-freeze 0 --lr-steps 100000000 --gaussians 200 --patch 16 --checkpoint-every 0 --surface-batch 3";
  CHECK(test::trainAndReadMetrics(data, dir / "two", flat + " --steps 2")["flat_water_height"].get<double>() == 0.0);
  CHECK(std::abs(test::trainAndReadMetrics(data, dir / "three", flat + " --steps 3")["flat_water_height"].get<double>()) ==
        doctest::Approx(0.02).epsilon(1e-3));
  // The height MLP likewise: its heights after 2 steps are the frozen field's.
  std::string mlp = " --surface-lr 0.01 --surface-freeze 0 --mlp-width 16 --mlp-layers 1 --gaussians 200 --patch 16 --checkpoint-every 0";
  test::trainAndReadMetrics(data, dir / "frozen", mlp + " --steps 2 --surface-freeze 5");
  test::trainAndReadMetrics(data, dir / "mlp2", mlp + " --steps 2 --surface-batch 3");
  test::trainAndReadMetrics(data, dir / "mlp3", mlp + " --steps 3 --surface-batch 3");
  std::vector<float> frozen = learnedHeights(dir / "frozen").heights;
  CHECK(learnedHeights(dir / "mlp2").heights == frozen);
  CHECK(learnedHeights(dir / "mlp3").heights != frozen);

  // --surface-batch views: N is the training view count (8 in this preset; 5 kept by
  // --train-views), so the plane first moves at step 8 (5).
  std::string views = " --flat-water --surface-lr 0.02 --surface-freeze 0 --lr-steps 100000000 --gaussians 200 --patch 16 --checkpoint-every 0 --surface-batch views";
  REQUIRE(loadDataset(data).split("train").size() == 8);
  CHECK(test::trainAndReadMetrics(data, dir / "views7", views + " --steps 7")["flat_water_height"].get<double>() == 0.0);
  CHECK(std::abs(test::trainAndReadMetrics(data, dir / "views8", views + " --steps 8")["flat_water_height"].get<double>()) ==
        doctest::Approx(0.02).epsilon(1e-3));
  CHECK(test::trainAndReadMetrics(data, dir / "kept4", views + " --steps 4 --train-views 5")["flat_water_height"].get<double>() == 0.0);
  CHECK(std::abs(test::trainAndReadMetrics(data, dir / "kept5", views + " --steps 5 --train-views 5")["flat_water_height"].get<double>()) ==
        doctest::Approx(0.02).epsilon(1e-3));

  TrainConfig c = trainConfigFromJson(readJson(dir / "mlp3/config.json"), "config.json");
  CHECK(c.surfaceBatch == 3);
  CHECK(trainConfigFromJson(trainConfigToJson(c), "test").surfaceBatch == 3);
  nlohmann::json viewsJson = readJson(dir / "views8/config.json");
  CHECK(viewsJson["surface_batch"] == "views");
  CHECK(trainConfigFromJson(viewsJson, "config.json").surfaceBatch == 0);
  for (nlohmann::json bad : {nlohmann::json("view"), nlohmann::json(2.5), nlohmann::json(0), nlohmann::json(-3)}) {
    viewsJson["surface_batch"] = bad;
    CHECK_THROWS_AS(trainConfigFromJson(viewsJson, "config.json"), Error);
  }
  for (int bad : {-1, 100001}) {
    c.surfaceBatch = bad;
    CHECK_THROWS_AS(validateTrainConfig(c), Error);
  }
  for (std::string bad : {"0", "view", "-2"}) {
    test::CliResult r = test::runCli("train " + data + " -o " + (dir / "bad") + " --surface-batch " + bad);
    CHECK(r.exitCode != 0);
    CHECK(r.output.find("surface-batch") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad"));
  }
}

TEST_CASE("train: --surface-until freezes the water after its last surface step, survives config.json, and is validated" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  // The flat plane's first Adam step moves it by exactly the learning rate; stopped after step
  // 1, three steps leave it there, where without the option the later steps move it on.
  std::string flat = " --recipe reference --flat-water --surface-lr 0.02 --surface-freeze 0 --lr-steps 100000000 --gaussians 200 --patch 16 --checkpoint-every 0 --steps 3";
  const double learned = test::trainAndReadMetrics(data, dir / "flat", flat)["flat_water_height"].get<double>();
  CHECK(std::abs(learned) > 0.021);
  CHECK(std::abs(test::trainAndReadMetrics(data, dir / "flat1", flat + " --surface-until 1")["flat_water_height"].get<double>()) ==
        doctest::Approx(0.02).epsilon(1e-3));
  // The height MLP: stopped after its surface step at step 2 (--surface-batch 2; N = 3 is no
  // surface step), four steps end with the heights of two. (The schedules that scale with
  // --steps are fixed, so the first two steps are alike.)
  std::string mlp = " --recipe reference --surface-lr 0.01 --surface-freeze 0 --lr-steps 100000000 --face-normals-until 0 --mlp-width 16 --mlp-layers 1 "
                    "--gaussians 200 --patch 16 --checkpoint-every 0 --surface-batch 2";
  test::trainAndReadMetrics(data, dir / "mlp2", mlp + " --steps 2");
  test::trainAndReadMetrics(data, dir / "until3", mlp + " --steps 4 --surface-until 3");
  test::trainAndReadMetrics(data, dir / "mlp4", mlp + " --steps 4");
  // (The gradient's float sums are not deterministic on every device: alike within 1e-6 m.)
  const std::vector<float> two = learnedHeights(dir / "mlp2").heights;
  auto largestChange = [&](const std::string& run) {
    const std::vector<float> h = learnedHeights(dir / run).heights;
    REQUIRE(h.size() == two.size());
    float change = 0;
    for (size_t i = 0; i < h.size(); i++) change = std::max(change, std::abs(h[i] - two[i]));
    return change;
  };
  CHECK(largestChange("until3") < 1e-6f);
  CHECK(largestChange("mlp4") > 1e-3f);

  TrainConfig c = trainConfigFromJson(readJson(dir / "until3/config.json"), "config.json");
  CHECK(c.schedule.surfaceUntil == 3);
  nlohmann::json older = readJson(dir / "mlp4/config.json");
  older["schedule"].erase("surface_until");  // a run written before the option learns to the end
  CHECK(trainConfigFromJson(older, "config.json").schedule.surfaceUntil == 0);
  c.schedule.surfaceFreeze = 3;
  CHECK_THROWS_WITH_AS(validateTrainConfig(c), doctest::Contains("--surface-until must come after --surface-freeze (3)"), Error);
  // A surface step never reached: refused before the run folder is made.
  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "none") + mlp + " --steps 4 --surface-until 1");
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("--surface-until 1 leaves the surface no step") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "none"));
}

// Two training views: the plane sweep that checks the learned water needs three views on a cell,
// so the check has nothing to compare; the run must say so, not pass over it in silence (the
// stability chart's 2-view run ended 2.9x further from the truth than the flat start unsaid).
TEST_CASE("train: a run whose views cannot check the learned water says so" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "two") +
                                   " --train-views 2 --gaussians 200 --patch 16 --checkpoint-every 0 --steps 2 --surface-freeze 0");
  REQUIRE(r.exitCode == 0);
  CHECK(r.output.find("warning: the run cannot check its learned water (no water cell is seen by 3 of the training views") !=
        std::string::npos);
  nlohmann::json m = readJson(dir / "two/metrics.json");
  CHECK(m.contains("surface_unchecked"));
  CHECK(!m.contains("surface_agreement"));
}

GPU_TEST_CASE("train: a checkpoint in the middle of a --surface-batch sum resumes with the sum" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 10, 300, 16, rng(), d);
  c.mlpWidth = 16;
  c.mlpHiddenLayers = 1;
  c.schedule.surfaceFreeze = 0;
  c.surfaceLearningRate = 1e-2;
  c.surfaceBatch = 4;
  auto whole = createTrainSession(ctx, c, d);
  while (whole->model.step < 10) trainStep(*whole);

  auto first = createTrainSession(ctx, c, d);
  while (first->model.step < 6) trainStep(*first);  // two of step 8's four gradients summed
  saveCheckpoint(*first, dir / "split");
  first.reset();
  auto second = createTrainSession(ctx, c, d);
  loadCheckpoint(*second, latestCheckpoint(dir / "split"));
  while (second->model.step < 10) trainStep(*second);

  // The same surface steps on the same sums: the weights agree up to the float-atomic sums'
  // order. Adam amplifies that order's noise where a weight's gradient is near zero (its step
  // is about the learning rate whatever the gradient's size), so the largest difference ranged
  // 1e-7 to 1.7e-3 here (the most with other work on the machine), and the RMS over the
  // weights is what the check reads. Without the sum in the checkpoint, step 8 loses two of its
  // four gradients and the weights move by about the learning rate (planted: RMS 4.5-5.4e-3,
  // largest 1.09e-2).
  std::vector<float> a = downloadWeights(ctx, *whole->model.height), b = downloadWeights(ctx, *second->model.height);
  REQUIRE(a.size() == b.size());
  double most = 0, squares = 0;
  for (size_t i = 0; i < a.size(); i++) {
    const double d = std::abs(double(a[i]) - b[i]);
    most = std::max(most, d);
    squares += d * d;
  }
  const double rms = std::sqrt(squares / double(a.size()));
  MESSAGE("weight difference: RMS " << rms << ", largest " << most << " (learning rate " << c.surfaceLearningRate << ")");
  CHECK(rms < 0.05 * c.surfaceLearningRate);
}

// A surface prior's weight: config.json keeps the run's value (and 0 for the run without it),
// and a negative or non-finite weight is refused.
void checkPriorWeightKeptAndValidated(const fs::path& withPrior, double weight, const fs::path& without, double TrainConfig::*field) {
  TrainConfig c = trainConfigFromJson(readJson(withPrior / "config.json"), "config.json");
  CHECK(c.*field == weight);
  CHECK(trainConfigFromJson(readJson(without / "config.json"), "config.json").*field == 0.0);
  for (double bad : {-1e-3, double(NAN), double(INFINITY)}) {
    c.*field = bad;
    CHECK_THROWS_AS(validateTrainConfig(c), Error);
  }
}

// The surface-prior train tests' comparison: a rough initial field (init range 0.1, slopes,
// tilt and bowl of a few cm) learning from step 0 at a fast rate for 8 steps, with the prior
// and without it (same seed, same patches). `energy` is the prior's own measure of a run's
// heights; it must fall well under the run without the prior and under the start.
void checkPriorLowersItsEnergy(const std::string& priorFlag, const char* energyName, const std::function<double(const fs::path&)>& energy,
                               const fs::path& dir) {
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  std::string options = " --recipe reference --seed 3 --mlp-init-range 0.1 --mlp-width 16 --mlp-layers 2 --gaussians 200 --patch 16 --checkpoint-every 0";
  std::string learn = options + " --steps 8 --surface-freeze 0 --surface-lr 1e-2";
  test::trainAndReadMetrics(data, dir / "prior", learn + " " + priorFlag);
  test::trainAndReadMetrics(data, dir / "free", learn);
  test::trainAndReadMetrics(data, dir / "start", options + " --steps 1 --surface-freeze 5");
  double start = energy(dir / "start"), prior = energy(dir / "prior"), free = energy(dir / "free");
  MESSAGE(energyName << " at the start " << start << ", after 8 steps with " << priorFlag << " " << prior << ", without " << free);
  CHECK(start > 0);
  CHECK(prior < 0.5 * free);
  CHECK(prior < 0.5 * start);
}

TEST_CASE("train: --surface-smoothness pulls a rough surface toward flat, survives config.json, and is validated" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  checkPriorLowersItsEnergy("--surface-smoothness 100", "slope energy (unit spacing)", [](const fs::path& run) {
    LearnedHeights h = learnedHeights(run);
    return slopePrior(h.heights, h.grid, 1.0, nullptr);
  }, dir.path);
  checkPriorWeightKeptAndValidated(dir / "prior", 100.0, dir / "free", &TrainConfig::surfaceSmoothness);
}

TEST_CASE("train: --level-prior pulls a tilted, bowled surface level, survives config.json, and is validated" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  checkPriorLowersItsEnergy("--level-prior 1000", "tilt and bowl mean square", [](const fs::path& run) {
    // Over the central half of the domain (each side), which the tiny rig's views all see.
    LearnedHeights h = learnedHeights(run);
    const size_t n = h.grid.rowLength;
    std::vector<double> weights(h.heights.size(), 0.0);
    for (size_t j = n / 4; j < n - n / 4; j++)
      for (size_t i = n / 4; i < n - n / 4; i++) weights[j * n + i] = 1.0;
    return levelPrior(h.heights, h.grid, weights, 1.0, nullptr);
  }, dir.path);
  checkPriorWeightKeptAndValidated(dir / "prior", 1000.0, dir / "free", &TrainConfig::levelPrior);
}

TEST_CASE("train: the height encoding opens coarse to fine between the surface freeze and --octaves-open-until" * doctest::test_suite("one-backend")) {
  TrainConfig c;
  c.steps = 15000;
  resolveSchedule(c);
  REQUIRE(c.schedule.surfaceFreeze == 1000);
  REQUIRE(c.schedule.octavesOpenUntil == 7500);
  REQUIRE(c.mlpOctaves == 6);
  CHECK(encodingWindowAt(c, 0) == 1.0f);  // off by default: every octave open
  c.mlpCoarseOctaves = 3;
  CHECK(encodingWindowAt(c, 0) == doctest::Approx(0.5));
  CHECK(encodingWindowAt(c, 1000) == doctest::Approx(0.5));
  CHECK(encodingWindowAt(c, 4250) == doctest::Approx(0.75));  // half way: 4.5 of 6 octaves
  CHECK(encodingWindowAt(c, 7500) == doctest::Approx(1.0));
  CHECK(encodingWindowAt(c, 14000) == doctest::Approx(1.0));
  // What the field holds after a step: frozen steps keep step 0's window, learning steps lift
  // the surface for the next one.
  CHECK(encodingWindowAfterStep(c, 1000) == doctest::Approx(0.5));
  CHECK(encodingWindowAfterStep(c, 4249) == doctest::Approx(0.75));
  c.domain = Rect{-1, -1, 1, 1};
  for (int a = 0; a < 3; a++) c.boxMax[a] = 1;
  TrainConfig back = trainConfigFromJson(trainConfigToJson(c), "test");
  CHECK(back.mlpCoarseOctaves == 3);
  CHECK(back.schedule.octavesOpenUntil == 7500);
  c.mlpCoarseOctaves = 6;  // >= octaves: the plain encoding throughout
  CHECK(encodingWindowAt(c, 0) == 1.0f);
  c.mlpCoarseOctaves = 2;
  c.mlpOctaves = 0;
  CHECK(encodingWindowAt(c, 0) == 1.0f);

  // End to end: the saved height field carries the window of its last step.
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  test::trainAndReadMetrics(data, dir / "run",
                            " --recipe reference --steps 4 --mlp-octaves 6 --mlp-coarse-octaves 3 --surface-freeze 0 --octaves-open-until 100 --gaussians 200 --patch 16 "
                            "--checkpoint-every 0 "
                            "--mlp-width 16 --mlp-layers 2");
  Context& ctx = test::context();
  HeightField hf = loadHeightField(ctx, dir / "run/height_field.bin");
  CHECK(hf.config.encodingWindow == doctest::Approx((3.0 + 3.0 * 5.0 / 100.0) / 6.0).epsilon(1e-6));
}

TEST_CASE("train: --anchor-mean-height keeps the mean height the training views see at the given height" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  // A wavy initial field (init range 0.1) whose mean is off the water height (0), learning
  // from step 0: with the anchor the mean of the saved grid, each vertex weighted by the
  // training views that see it, is the height; without it it is not, and the unweighted mean
  // (corners one view sees included at full weight) is not either.
  std::string options = " --recipe reference --steps 6 --seed 1 --surface-freeze 0 --mlp-init-range 0.1 --mlp-width 16 --mlp-layers 2 --gaussians 200 "
                        "--patch 16 --checkpoint-every 0";
  test::trainAndReadMetrics(data, dir / "anchored", options + " --anchor-mean-height");
  test::trainAndReadMetrics(data, dir / "free", options);
  Dataset d = loadDataset(data);
  nlohmann::json m = readJson(dir / "anchored/metrics.json");
  const double x0 = m["water_height_domain"][0], y0 = m["water_height_domain"][1], x1 = m["water_height_domain"][2],
               y1 = m["water_height_domain"][3];
  NpyArray grid = readNpy(dir / "anchored/water_height.npy");
  const size_t n = grid.shape.at(0);
  std::vector<double> weights(n * n, 0.0);
  for (size_t j = 0; j < n; j++)
    for (size_t i = 0; i < n; i++) {
      glm::dvec3 p(x0 + (x1 - x0) * double(i) / double(n - 1), y0 + (y1 - y0) * double(j) / double(n - 1), 0.0);
      for (const View& v : d.split("train")) weights[j * n + i] += v.camera.sees(p) ? 1.0 : 0.0;
    }
  auto means = [&](const std::string& run) {
    NpyArray h = readNpy(run + "/water_height.npy");
    double weighted = 0, weight = 0, plain = 0;
    for (size_t k = 0; k < h.data.size(); k++) {
      weighted += weights[k] * h.data[k];
      weight += weights[k];
      plain += h.data[k];
    }
    return std::make_pair(weighted / weight, plain / double(h.data.size()));
  };
  auto [anchoredSeen, anchoredAll] = means(dir / "anchored");
  auto [freeSeen, freeAll] = means(dir / "free");
  MESSAGE("seen-weighted mean height anchored " << anchoredSeen << " (unweighted " << anchoredAll << "), free " << freeSeen);
  double most = *std::max_element(weights.begin(), weights.end()), least = *std::min_element(weights.begin(), weights.end());
  CHECK(most == double(d.split("train").size()));  // the centre: every view
  CHECK(least < most / 2);
  CHECK(std::abs(anchoredSeen) < 1e-4);
  CHECK(std::abs(anchoredAll) > 1e-3);
  CHECK(std::abs(freeSeen) > 1e-3);
  CHECK(trainConfigFromJson(readJson(dir / "anchored/config.json"), "config.json").anchorMeanHeight);
}

TEST_CASE("train: bad datasets give one clear error and leave no run folder" * doctest::test_suite("one-backend")) {
  TrainTempDir dir;
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  auto copy = [&](const std::string& name) {
    fs::copy(data, dir / name, fs::copy_options::recursive);
    return dir / name;
  };
  nlohmann::json train = readJson(data + "/transforms_train.json");
  std::string firstImage = train["frames"][0]["file_path"].get<std::string>();
  if (fs::path(firstImage).extension().empty()) firstImage += ".png";

  std::string missing = copy("missing");
  fs::remove(fs::path(missing) / firstImage);
  expectCleanFailure(missing, dir / "run_missing", fs::path(firstImage).stem().string() + " does not exist");

  std::string wrongSize = copy("wrong_size");
  Image small;
  small.width = small.height = 7;
  small.channels = 3;
  small.pixels.assign(7 * 7 * 3, 0.5f);
  writePng((fs::path(wrongSize) / firstImage).string(), small);
  expectCleanFailure(wrongSize, dir / "run_wrong_size", fs::path(firstImage).filename().string());

  std::string malformed = copy("malformed");
  writeTextAtomic(malformed + "/transforms_train.json", "{\"camera_angle_x\": 0.8, \"frames\": [");
  expectCleanFailure(malformed, dir / "run_malformed", "transforms_train.json");

  // A NaN pose: the LLFF layout (poses_bounds.npy) once the Blender files are gone.
  std::string nanPose = copy("nan_pose");
  for (const char* f : {"transforms_train.json", "transforms_test.json", "transforms_air.json"}) fs::remove(fs::path(nanPose) / f);
  NpyArray poses = readNpy(nanPose + "/poses_bounds.npy");
  poses.data[3] = std::nan("");
  writeNpy(nanPose + "/poses_bounds.npy", poses, true);
  expectCleanFailure(nanPose, dir / "run_nan_pose", "poses_bounds.npy");

  std::string emptySplit = copy("empty_split");
  nlohmann::json test = readJson(data + "/transforms_test.json");
  test["frames"] = nlohmann::json::array();
  writeTextAtomic(emptySplit + "/transforms_test.json", test.dump());
  expectCleanFailure(emptySplit, dir / "run_empty_split", "transforms_test.json");

  // An existing non-empty run folder is left untouched.
  fs::create_directories(dir / "taken");
  writeTextAtomic(dir / "taken/keep.txt", "x");
  test::CliResult r = test::runCli("train " + data + " -o " + (dir / "taken") + " --steps 2");
  CHECK(r.exitCode != 0);
  CHECK(r.output.find("not empty") != std::string::npos);
  CHECK(readFile(dir / "taken/keep.txt") == "x");
  CHECK(std::distance(fs::directory_iterator(dir / "taken"), fs::directory_iterator()) == 1);
}

}  // namespace
}  // namespace refrax

namespace refrax {

// The densification statistic per ray (sum over rays / their count) from `steps` steps of
// `patch` x `patch` batches (0: whole images), densification off: the same Gaussians, moved
// only by a few Adam steps.
double meanDensifyStatistic(Context& ctx, const std::string& data, uint32_t patch, int steps) {
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 40, 500, patch, 7, d);
  c.densify = false;
  auto s = createTrainSession(ctx, c, d);
  for (int step = 0; step < steps; step++) trainStep(*s);
  pullGaussians(*s);  // the sums are the device's
  double sum = 0, rays = 0;
  for (size_t i = 0; i < s->model.gaussians.count(); i++) {
    sum += s->state.densifyStats[2 * i];
    rays += s->state.densifyStats[2 * i + 1];
  }
  REQUIRE(rays > 0);
  return sum / rays;
}

// The loss is a mean over the batch, so each ray's gradient falls as the batch grows; the
// trainer scales the statistic back (densifyStatScale) so that one threshold densifies
// patches and whole images alike. Unscaled, whole 64 x 64 images read 16x under 16 x 16 patches.
GPU_TEST_CASE("train: the densification statistic reads alike for small patches and whole images") {
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  const double patches = meanDensifyStatistic(ctx, data, 16, 16), whole = meanDensifyStatistic(ctx, data, 0, 1);
  MESSAGE("per-ray statistic: 16 x 16 patches " << patches << ", whole images " << whole);
  CHECK(whole / patches >= 0.5);
  CHECK(whole / patches <= 2.0);
}

GPU_TEST_CASE("train: a step's loss holds the density regulariser of the table it traced") {
  std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset d;
  TrainConfig c = test::sessionConfig(data, 20, 300, 16, 5, d);
  c.schedule.surfaceFreeze = 1000;  // no water prior in the loss
  c.densityLossWeight = 0.5;
  auto s = createTrainSession(ctx, c, d);
  for (int step = 0; step < 3; step++) {
    pullGaussians(*s);   // the table the device stepped to
    double squares = 0;  // the regulariser of the table the step traces: weight * mean(sigmoid(logit)^2)
    for (size_t i = 0; i < s->model.gaussians.count(); i++) {
      const double density = 1 / (1 + std::exp(-double(s->model.gaussians.at(i)[f32::kGaussLogitDensity])));
      squares += density * density;
    }
    const StepResult r = trainStep(*s);
    CHECK(r.loss - r.imageLoss == doctest::Approx(c.densityLossWeight * squares / double(s->model.gaussians.count())).epsilon(1e-4));
  }
}

}  // namespace refrax
