// The training step's submissions (issue 48). The water's surface step rides in the batch's
// own submission: the push of the summed gradient, the water's Adam step and the surface's lift
// recorded after the backward, the host's anchor and checks after the one wait. It must learn
// what the surface step in a submission of its own learns, priors included, and submit once a
// step less often. And a run's steps with nothing for the host after them are not waited for:
// the host records the next while the device runs them, and reads their losses later.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "engine/io/json_io.h"
#include "engine/train/checkpoint.h"
#include "engine/vk/vk_profile.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

namespace refrax {
namespace {

const char* kTinyRunOptions = " --steps 300 --gaussians 2000 --patch 32 --progress-every 100 --checkpoint-every 0";

struct SteppedWater {
  CheckpointContents contents;
  uint64_t submits = 0;
};

SteppedWater trainSteps(Context& ctx, bool inBatch, int surfaceBatch, int steps) {
  Dataset d;
  TrainConfig c = test::sessionConfig(test::tinyDataset("nerfrac-primary-sine"), std::max(steps, 1), 300, 16, 1, d);
  c.schedule.surfaceFreeze = 0;
  c.surfaceLearningRate = 1e-2;  // the water moves well past float noise in a few steps
  c.surfaceBatch = surfaceBatch;
  c.surfaceSmoothness = 1e-2;  // a prior whose gradient is added on the device, before the backward in a batch
  auto s = createTrainSession(ctx, c, d);
  s->surfaceStepInBatch = inBatch;
  GpuProfiler profiler;
  attachProfiler(ctx, profiler);
  while (s->model.step < steps) trainStep(*s);
  detachProfiler(ctx);
  pushWaterGradient(*s);
  return {checkpointContents(*s), profiler.submits};
}

double maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  double m = 0;
  for (size_t k = 0; k < a.size(); k++) m = std::max(m, std::abs(double(a[k]) - double(b[k])));
  return m;
}

}  // namespace

GPU_TEST_CASE("training: the water's surface step in the batch's submission learns what a separate one learns, in one submission fewer") {
  // Every step a surface step, then one per three steps (a gradient summed over a batch).
  struct Case {
    int surfaceBatch, steps;
  };
  // Every step a water step for 3 steps, not 6: under the compute trace the same path twice
  // ended either about 1e-6 or 0.003 to 0.008 apart after 6 (0.43x the water's move; a CI
  // pass measured its Adam moments 0.017 apart, 0.45x their size), once a hit came out the
  // other way in one of them and the steps after it traced other water; after 3 steps, 8
  // runs of 8 ended 2e-5 to 1e-4 of the move apart.
  for (const Case k : {Case{1, 3}, Case{3, 6}}) {
    CAPTURE(k.surfaceBatch);
    const SteppedWater separate = trainSteps(ctx, false, k.surfaceBatch, k.steps);
    const SteppedWater inBatch = trainSteps(ctx, true, k.surfaceBatch, k.steps);
    // How far the water moved (Adam moves each weight up to about the learning rate a step),
    // against how far the two paths ended apart: the sums are taken in another order (atomics),
    // so not bit for bit. Measured (lavapipe), apart over moved: with the ray-query trace up
    // to 2.3e-3, with the compute trace up to 1.7e-3; their Adam moments up to 6e-5 of their
    // largest. A push that leaves out the cache's points or the priors' gradient ends 0.02 to
    // 0.05 apart (1.7x the move and more); without the priors' gradient, its moments 0.35x
    // to 1.2x their largest apart.
    const SteppedWater start = trainSteps(ctx, true, k.surfaceBatch, 0);
    const double moved = maxDifference(start.contents.heightWeights, separate.contents.heightWeights);
    const double apart = maxDifference(inBatch.contents.heightWeights, separate.contents.heightWeights);
    double momentSize = 0;
    for (const float m : separate.contents.heightM) momentSize = std::max(momentSize, std::abs(double(m)));
    const double momentsApart = maxDifference(inBatch.contents.heightM, separate.contents.heightM);
    MESSAGE("surface batch " << k.surfaceBatch << ": the water's weights moved up to " << moved << ", the two paths ended " << apart
                             << " apart; their Adam moments (up to " << momentSize << ") " << momentsApart << " apart");
    CHECK(moved > 1e-3);
    const double share = ctx.trace == TraceBackend::Compute ? 2e-2 : 5e-3;
    CHECK(apart <= share * moved);
    CHECK(momentsApart <= share * momentSize);
    CHECK(inBatch.contents.heightStep == separate.contents.heightStep);
    // One submission fewer per surface step.
    const uint64_t surfaceSteps = uint64_t(k.steps / k.surfaceBatch);
    CHECK(separate.submits - inBatch.submits == surfaceSteps);
  }
}

TEST_CASE("training: steps not waited for learn what waited-for steps learn, and their losses and water reach the surface watch") {
  // The tiny preset for 300 steps, once as a run (steps not waited for where nothing follows
  // them) and once with REFRAX_STEP_SYNC=1 (every step waited for): at the GPU's defaults (a water
  // step per pass over the views, its mean height anchored), and at --recipe reference (a water
  // step every step, not waited for either: its heights checked once it has run). The losses
  // that the surface watch averages over every three steps are read from the steps' rows of the
  // loss log, its water's RMS height from the checks: they match the waited-for run's to float
  // noise (measured: losses median 1e-5 to 3e-4, largest 5e-4 to 1.3e-3 of the loss; heights
  // median 1e-3, largest 1e-2: the backward's atomics), where a step's loss read from another
  // step's row is off by tens of percent.
  struct Case {
    const char* options;
    int notWaitedAtLeast;  // measured 177 and 197 of 300
  };
  // The defaults' case takes the GPU's water settings (test::kGpuWater300StepOptions).
  for (const Case& k : {Case{test::kGpuWater300StepOptions, 150}, Case{" --recipe reference --surface-freeze 30", 170}}) {
    CAPTURE(k.options);
    test::TrainTempDir dir;
    const std::string data = test::tinyDataset("nerfrac-primary-sine");
    const char* cli = std::getenv("REFRAX_CLI");
    const std::string train = std::string(cli ? cli : REFRAX_CLI) + " train " + data + kTinyRunOptions + k.options;
    const test::CliResult deferred = test::runShell(train + " -o " + (dir / "deferred"));
    const test::CliResult waited = test::runShell("REFRAX_STEP_SYNC=1 " + train + " -o " + (dir / "waited"));
    INFO(deferred.output);
    INFO(waited.output);
    REQUIRE(deferred.exitCode == 0);
    REQUIRE(waited.exitCode == 0);
    const nlohmann::json a = readJson(dir / "deferred/metrics.json"), b = readJson(dir / "waited/metrics.json");
    CHECK(b["profile"]["steps_not_waited_for"].get<int>() == 0);
    CHECK(a["profile"]["steps_not_waited_for"].get<int>() >= k.notWaitedAtLeast);
    // The final PSNR is one evaluation after 300 steps whose atomics sum in another order, so
    // it spreads run to run with either trace (measured: a waited-for pair 0.06 dB apart under
    // the compute trace, and 0.063 dB under the ray-query trace in a CI pass): the bound is
    // loose, and the medians of the surface watch's losses and heights below are the test.
    const char* trace = std::getenv("REFRAX_TRACE");
    const bool computeTrace = trace && std::string(trace) == "compute";
    CHECK(std::abs(a["psnr"].get<double>() - b["psnr"].get<double>()) <= 0.3);
    const nlohmann::json wa = readJson(dir / "deferred/surface_watch.json"), wb = readJson(dir / "waited/surface_watch.json");
    REQUIRE(wa.size() == wb.size());
    REQUIRE(wa.size() >= 50);
    std::vector<double> lossApart, heightApart;
    for (size_t i = 0; i < wa.size(); i++) {
      CHECK(wa[i]["step"] == wb[i]["step"]);
      lossApart.push_back(std::abs(wa[i]["loss"].get<double>() - wb[i]["loss"].get<double>()) / wb[i]["loss"].get<double>());
      heightApart.push_back(std::abs(wa[i]["height_rms"].get<double>() - wb[i]["height_rms"].get<double>()) /
                            std::max(wb[i]["height_rms"].get<double>(), 1e-6));
    }
    std::sort(lossApart.begin(), lossApart.end());
    std::sort(heightApart.begin(), heightApart.end());
    // (the compute trace's median: 1.2e-3 in one suite pass; a loss read from another row: 3.6e-2)
    // The largest is one sample's tail: 2.4e-2 under the ray-query trace in a CI sanitizer pass,
    // so it only bounds a runaway; the median is the test.
    CHECK(lossApart[lossApart.size() / 2] <= (computeTrace ? 5e-3 : 1e-3));
    CHECK(lossApart.back() <= 0.1);
    CHECK(heightApart[heightApart.size() / 2] <= 0.01);
    CHECK(heightApart.back() <= (computeTrace ? 0.2 : 0.05));
  }
}

TEST_CASE("training: a water that diverges at a step not waited for stops the run at that step, as a waited-for run does") {
  // The reference recipe's water step every step, at a learning rate that throws the water out
  // of the scene within a few steps: the check of a step's heights runs once the step has run,
  // and its error is the run's (measured: both at step 31; with the checks of the steps not
  // waited for left out, the next waited-for step's).
  test::TrainTempDir dir;
  const char* cli = std::getenv("REFRAX_CLI");
  const std::string train = std::string(cli ? cli : REFRAX_CLI) + " train " + test::tinyDataset("nerfrac-primary-sine") + kTinyRunOptions +
                            " --recipe reference --surface-freeze 30 --surface-lr 0.9 --mlp-init-range 0.1";
  std::vector<std::string> messages;
  for (const char* sync : {"", "REFRAX_STEP_SYNC=1 "}) {
    const test::CliResult r = test::runShell(std::string(sync) + train + " -o " + (dir / (std::string("run") + std::to_string(messages.size()))));
    INFO(r.output);
    CHECK(r.exitCode == 1);
    CHECK(r.output.find("terminate") == std::string::npos);
    const size_t at = r.output.find("refrax: error: the water surface diverged at step ");
    REQUIRE(at != std::string::npos);
    messages.push_back(r.output.substr(at, r.output.find(':', at + 50) - at));
  }
  CHECK(messages[0] == messages[1]);
}

}  // namespace refrax
