// refrax gradcheck RUN: the water's gradient of a trained run (its newest checkpoint) against
// central differences of the loss, batch by batch (engine/train/gradient_check.h). A ratio
// near 1 at the small steps means the chain from the image loss to the height MLP is right
// there; a ratio that is off, or of the wrong sign, names the batch to look at.
#include <cmath>
#include <cstdio>

#include "engine/base/error.h"
#include "engine/io/json_io.h"
#include "engine/train/gradient_check.h"
#include "engine/train/train_run.h"
#include "engine/vk/vk_context.h"
#include "engine/app/cli.h"
#include "trainer/dataset_options.h"

namespace refrax {
namespace {

int runGradcheck(const cli::Args& args) {
  if (args.positional.size() != 1) fail("refrax gradcheck needs one run folder");
  const long batches = args.getIntIn("batches", 8, 1, 100000);
  std::vector<double> steps = parseNumbers(args.get("steps", "1e-4,3e-4,1e-3,3e-3"), 0, "--steps", "step sizes separated by commas");
  for (double h : steps)
    if (!(h > 0) || !std::isfinite(h)) fail("--steps expects positive step sizes separated by commas, got '" + args.get("steps") + "'");
  const std::string run = args.positional[0];
  TrainConfig config = readRunConfig(run);
  if (config.model != WaterModel::Refraction) fail(run + " was trained with " + waterModelName(config.model) + ": gradcheck needs the learned water (refraction)");
  auto ctx = cli::openContext(args);
  auto session = openRun(*ctx, run);
  std::printf("%s at step %d: d = the backward's gradient (unit), slope = dL/dw . d, CD(h) = central difference at step h (ratio CD/slope), dH = largest height change at +h\n",
              run.c_str(), session->model.step);
  nlohmann::json out = nlohmann::json::array();
  for (long b = 0; b < batches; b++) {
    StepBatch batch = nextStepBatch(*session);
    SurfaceGradientCheck r = checkSurfaceGradient(*session, batch, {}, steps);
    const std::string& name = session->dataset.split("train")[batch.view].name;
    std::printf("view %-12s patch (%u,%u) %ux%u  loss %.5f  slope %.4g\n", name.c_str(), batch.x0, batch.y0, batch.width, batch.height, r.loss, r.slope);
    nlohmann::json j = {{"view", name}, {"x0", batch.x0}, {"y0", batch.y0}, {"width", batch.width}, {"height", batch.height},
                        {"loss", r.loss}, {"slope", r.slope}, {"steps", nlohmann::json::array()}};
    for (size_t k = 0; k < r.steps.size(); k++) {
      std::printf("    h %-8.2g CD %-11.4g ratio %-8.3f dH %.3g m\n", r.steps[k], r.centralDifferences[k], r.centralDifferences[k] / r.slope, r.heightChanges[k]);
      j["steps"].push_back({{"h", r.steps[k]}, {"central_difference", r.centralDifferences[k]}, {"height_change", r.heightChanges[k]}});
    }
    out.push_back(j);
  }
  if (args.has("output")) writeJson(args.get("output"), nlohmann::json{{"run", run}, {"step", session->model.step}, {"batches", out}});
  return 0;
}

std::vector<cli::Option> gradcheckOptions() {
  std::vector<cli::Option> o = {{"batches", "N", "batches to check: the next N of the run's own sampler (view order, patches)", "8"},
                                {"steps", "H[,H...]", "step sizes along the unit gradient, in weight units (the height change each gives is printed)", "1e-4,3e-4,1e-3,3e-3"},
                                {"output", "FILE", "also write the results as JSON (-o)", ""}};
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"gradcheck", "check a run's water gradient (image loss -> height MLP) against central differences",
                "refrax gradcheck RUN [--batches N] [--steps H,...] [-o FILE]", gradcheckOptions(), runGradcheck});

}  // namespace
}  // namespace refrax
