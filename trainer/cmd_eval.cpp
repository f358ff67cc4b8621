// refrax eval RUN -o metrics.json: a trained run's metrics against a dataset (the run's own,
// or --dataset DIR): test PSNR/SSIM, surface RMSE against the ground truth, water-removal PSNR.
#include <cstdio>

#include "engine/base/error.h"
#include "engine/io/json_io.h"
#include "engine/model/render_model.h"
#include "engine/model/open_model.h"
#include "engine/vk/vk_context.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

int runEval(const cli::Args& args) {
  if (args.positional.size() != 1) fail("refrax eval needs one run folder");
  if (!args.has("output")) fail("refrax eval needs -o metrics.json");
  std::string run = args.positional[0];
  TrainConfig config = readRunConfig(run);
  std::optional<Dataset> other;
  if (args.has("dataset")) other = loadDataset(args.get("dataset"), config.datasetOptions);
  const Dataset dataset = loadRunDataset(config);
  // Metrics against another scene would read as this run's: refused unless asked for.
  std::vector<std::string> mismatches = other ? sceneMismatches(config, dataset, *other) : std::vector<std::string>{};
  if (!mismatches.empty()) {
    std::string list;
    for (const std::string& w : mismatches) list += (list.empty() ? "" : "; ") + w;
    if (!args.has("force"))
      fail("--dataset " + other->root + " is not the scene " + run + " learned: " + list + " (--force evaluates it anyway)");
    std::fprintf(stderr, "warning: --dataset %s is not the scene %s learned: %s; evaluating anyway (--force)\n", other->root.c_str(),
                 run.c_str(), list.c_str());
  }
  auto ctx = cli::openContext(args);
  auto model = openModel(*ctx, run, dataset);
  nlohmann::json m = evaluateModel(*model, other ? *other : dataset, "");
  m["dataset"] = other ? other->root : dataset.root;
  if (!mismatches.empty()) m["dataset_mismatches"] = mismatches;
  writeJson(args.get("output"), m);
  std::printf("%s\n", m.dump(2).c_str());
  return 0;
}

std::vector<cli::Option> evalOptions() {
  std::vector<cli::Option> o = {{"output", "FILE", "metrics JSON to write (-o)", ""},
                                {"dataset", "DIR", "dataset to evaluate against (default: the run's); refused when its water or training cameras are not the run's", ""},
                                {"force", "", "evaluate a --dataset whose scene is not the run's anyway (a warning, and metrics.json lists what differs)", ""}};
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"eval", "metrics of a trained run against a dataset's test split and ground-truth surface",
                "refrax eval RUN -o metrics.json [--dataset DIR [--force]]", evalOptions(), runEval});

}  // namespace
}  // namespace refrax
