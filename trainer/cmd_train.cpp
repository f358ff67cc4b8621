// refrax train <dataset> -o RUN: jointly optimises the water surface (a neural height field)
// and the Gaussians under it (engine/train/). --no-refraction and --flat-water train the
// comparison models on the same data, --known-water the oracle (the true surface, fixed).
// --resume RUN continues from the newest checkpoint.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include "engine/dataset/dataset.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/io/json_io.h"
#include "engine/train/checkpoint.h"
#include "engine/train/model_sizing.h"
#include "engine/train/step_probe.h"
#include "engine/run/train_options.h"
#include "engine/run/train_recipe.h"
#include "engine/train/train_run.h"
#include "engine/run/train_views.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"
#include "engine/app/cli.h"
#include "trainer/dataset_options.h"

namespace refrax {
namespace {

// Whether the command line gave the option of a config.json key.
bool givenOnCommandLine(const cli::Args& a, const std::string& key) {
  for (const TrainOption& o : trainOptionTable())
    if (o.key == key) return !o.flag.empty() && a.has(o.flag);
  return false;
}

// The training options from the command line, through the table (engine/run/train_options.h):
// each given flag's text parsed and checked by its row, the rest TrainConfig's defaults.
TrainConfig configFromArgs(const cli::Args& a) {
  TrainConfig c;
  c.datasetOptions = datasetOptionsFrom(a);
  std::map<std::string, std::string> groups;  // group -> the flag given for it
  for (const TrainOption& o : trainOptionTable()) {
    if (o.flag.empty() || !a.has(o.flag)) continue;
    if (!o.group.empty()) {
      auto [it, first] = groups.emplace(o.group, o.flag);
      if (!first) fail("--" + it->second + " and --" + o.flag + " exclude each other");
    }
    const std::string name = "--" + o.flag;
    o.set(c, o.parse(a.get(o.flag), name), name);
  }
  auto given = [&](const std::string& key) { return givenOnCommandLine(a, key); };
  applyDerivedDefaults(c, given);
  if (!a.has("recipe")) c.recipe = Recipe::Method;  // TrainConfig{}'s values are the reference's
  for (const std::string& key : sizedConfigKeys())
    if (!given(key)) c.sizeFromData.insert(key);
  return c;
}

// The recipe's choices for this dataset and device; returns them as the line that names the
// flags that would give them (empty: none).
std::string applyRecipeFor(TrainConfig& c, const cli::Args& a, const Dataset& d, const DeviceCaps& caps, bool stepsGiven = false) {
  int width = 1 << 30, height = 1 << 30;
  for (const View& v : d.split("train")) width = std::min(width, v.camera.width), height = std::min(height, v.camera.height);
  const RecipeDevice device{caps.type == VK_PHYSICAL_DEVICE_TYPE_CPU};
  auto given = [&](const std::string& key) { return givenOnCommandLine(a, key) || (stepsGiven && key == "steps"); };
  const std::vector<RecipeChoice> chosen = applyRecipe(c, given, device, width, height);
  if (chosen.empty()) return "";
  std::string flags;
  for (const RecipeChoice& choice : chosen) {
    std::string flag = choice.key;
    for (const TrainOption& o : trainOptionTable())
      if (o.key == choice.key) flag = o.flag;
    flags += " --" + flag + (choice.value == "true" ? "" : " " + choice.value);
  }
  return std::string("the method's settings for a ") + (device.cpu ? "CPU" : "GPU") + " device (--recipe reference: the paper's schedule):" + flags;
}

// "model size from the data: --mlp-octaves 6 (why)" for each value the data chose.
void printModelSizing(const TrainConfig& c) {
  if (c.modelSizing.is_null()) return;
  const nlohmann::json& derived = c.modelSizing["derived"];
  for (const std::string& key : sizedConfigKeys()) {
    if (!derived.contains(key)) continue;
    const nlohmann::json& choice = derived[key];
    std::string flag = key;
    for (const TrainOption& o : trainOptionTable())
      if (o.key == key) flag = o.flag;
    std::fprintf(stderr, "model size from the data: --%s %.0f (%s)\n", flag.c_str(), choice["value"].get<double>(),
                 choice["reason"].get<std::string>().c_str());
  }
}

// What --resume accepts besides the run: how far it goes, how it reports, and the device.
const std::set<std::string>& resumeOptions() {
  static const std::set<std::string> names = [] {
    std::set<std::string> n = {"resume", "profile", "time-limit"};
    for (const TrainOption& o : trainOptionTable())
      if (o.resumable) n.insert(o.flag);
    for (const cli::Option& o : cli::deviceOptions()) n.insert(o.name);
    return n;
  }();
  return names;
}

std::string resumeOptionList() {
  std::set<std::string> device;
  for (const cli::Option& o : cli::deviceOptions()) device.insert(o.name);
  std::string list;
  for (const std::string& name : resumeOptions())
    if (name != "resume" && !device.count(name)) list += (list.empty() ? "--" : ", --") + name;
  return list + " and the device options";
}

void printSummary(const nlohmann::json& m) {
  std::printf("test psnr %.3f  ssim %.4f", m["psnr"].get<double>(), m["ssim"].get<double>());
  if (m.contains("surface_rmse")) {
    std::printf("  surface rmse %.5f", m["surface_rmse"].get<double>());
    if (m.contains("initial_flat_surface_rmse")) std::printf(" (initial flat %.5f)", m["initial_flat_surface_rmse"].get<double>());
  }
  if (m.contains("surface_correlation")) std::printf("  correlation with the true waves %.2f", m["surface_correlation"].get<double>());
  if (m.contains("surface_rmse_missing")) std::printf("  surface rmse n/a: %s", m["surface_rmse_missing"].get<std::string>().c_str());
  if (m.contains("water_removal_psnr")) std::printf("  water-removal psnr %.3f", m["water_removal_psnr"].get<double>());
  if (m.contains("between_psnr"))
    std::printf("  between-view psnr %.3f (%llu views)", m["between_psnr"].get<double>(), (unsigned long long)m["between_views"].get<uint64_t>());
  std::printf("  gaussians %llu  %.1f s\n", (unsigned long long)m["gaussians"].get<uint64_t>(), m["training_seconds"].get<double>());
}

int runTrain(const cli::Args& args) {
  namespace fs = std::filesystem;
  TrainProgress progress;
  progress.line = [](const std::string& text) { std::fprintf(stderr, "%s\n", text.c_str()); };
  progress.profile = args.has("profile");
  if (args.has("time-limit")) {
    progress.timeLimitSeconds = args.getDouble("time-limit", 0);
    if (!(progress.timeLimitSeconds > 0 && progress.timeLimitSeconds < 1e9)) fail("--time-limit must be a number of seconds above 0 and below 1e9 (about 31 years), got " + args.get("time-limit"));
  }
  if (args.has("resume")) {
    if (!args.positional.empty() || args.has("output")) fail("--resume RUN takes no dataset and no -o: the run folder holds both");
    // The run's configuration is RUN/config.json; only how far and how it reports may change.
    for (const auto& [name, value] : args.values)
      if (!resumeOptions().count(name))
        fail("--" + name + " cannot change when a run resumes (RUN/config.json holds the run's configuration); with --resume only " +
             resumeOptionList() + " apply");
    std::string run = args.get("resume");
    TrainConfig stored = readRunConfig(run);
    auto lock = cli::lockRunFolder(run);  // held until the run ends
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
    // The refit starts after the run's steps: moving them would move it under a resumed run.
    if (stored.schedule.refitSteps > 0 && args.has("steps") && args.getInt("steps", 0) != stored.steps)
      fail("--steps cannot change on --resume of a run with --refit (" + run + ")");
    for (const TrainOption& o : trainOptionTable())
      if (o.resumable && args.has(o.flag)) o.set(stored, o.parse(args.get(o.flag), "--" + o.flag), "--" + o.flag);
    if (int reached = checkpointStep(ckpt); totalSteps(stored) < reached)
      fail("--steps " + std::to_string(stored.steps) + " is below the step the run has reached (" + std::to_string(reached) + ", " + ckpt + ")");
    auto ctx = cli::openContext(args);
    auto session = openRun(*ctx, run);
    session->model.config.steps = stored.steps;
    session->model.config.progressEvery = stored.progressEvery;
    session->model.config.evalEvery = stored.evalEvery;
    session->model.config.checkpointEvery = stored.checkpointEvery;
    writeJson((fs::path(run) / "config.json").string(), trainConfigToJson(session->model.config));
    std::fprintf(stderr, "resuming %s at step %d of %d\n", run.c_str(), session->model.step, totalSteps(session->model.config));
    printSummary(trainToEnd(*session, run, progress));
    if (progress.profile) std::fprintf(stderr, "%s", profileTable(session->log.profiler).c_str());
    return 0;
  }
  if (args.positional.size() != 1) fail("refrax train needs one dataset folder");
  if (!args.has("output")) fail("refrax train needs -o RUN (the output folder)");
  std::string run = args.get("output");
  const std::string advice = "use --resume " + run + " to continue it, or another folder";
  cli::checkNewOrEmptyFolder(run, "-o", advice);  // before the dataset loads: a refusal costs nothing

  TrainConfig config = configFromArgs(args);
  config.dataset = fs::absolute(args.positional[0]).lexically_normal().string();
  Dataset dataset = loadDataset(config.dataset, config.datasetOptions);
  for (const std::string& note : dataset.notes) std::fprintf(stderr, "%s: %s\n", config.dataset.c_str(), note.c_str());
  keepTrainViews(dataset, config.trainViews);  // before the scene bounds: they come from the views trained on
  auto ctx = cli::openContext(args, false);  // the recipe sizes the run for the device
  const TrainConfig fromArgs = config;
  std::string recipe = applyRecipeFor(config, args, dataset, ctx->caps);
  resolveSceneConfig(config, dataset);
  std::string probed;
  // The probe sizes the water's steps to the time: a refit would run past it.
  if (progress.timeLimitSeconds > 0 && !args.has("steps") && config.recipe == Recipe::Method && config.schedule.refitSteps > 0)
    fail("--refit needs --steps with --time-limit (the time limit sizes the run's steps, and the refit's would run past it)");
  if (progress.timeLimitSeconds > 0 && !args.has("steps") && config.recipe == Recipe::Method) {
    // the steps that fit the time, and the schedule sized to them (step_probe.h)
    const StepProbe probe = probeStepsForTime(*ctx, config, dataset, progress.timeLimitSeconds);
    probed = stepProbeLine(progress.timeLimitSeconds, probe);
    config = fromArgs;
    config.steps = probe.steps;
    recipe = applyRecipeFor(config, args, dataset, ctx->caps, true);
    resolveSceneConfig(config, dataset);
  }
  // Everything checked: the run folder appears only now, and the log begins.
  auto folder = cli::claimOutputFolder(run, "-o", advice);  // held until the run ends
  printContextLine(*ctx);
  if (!probed.empty()) std::fprintf(stderr, "%s\n", probed.c_str());
  if (!recipe.empty()) std::fprintf(stderr, "%s\n", recipe.c_str());
  auto session = createTrainSession(*ctx, config, std::move(dataset));
  folder->keep();
  writeJson((fs::path(run) / "config.json").string(), trainConfigToJson(session->model.config));
  printModelSizing(config);  // once everything is checked: a refused run prints one line
  const std::string atPoints = config.initPoints ? " (" + std::to_string(session->log.gaussiansAtPoints) + " at sparse points)" : "";
  const std::string refit = config.schedule.refitSteps > 0 ? " and a refit of " + std::to_string(config.schedule.refitSteps) : "";
  std::fprintf(stderr, "training %s (%s): %u Gaussians%s, %d steps%s, %zu training views -> %s\n", config.dataset.c_str(),
               waterModelName(config.model), config.initialGaussians, atPoints.c_str(), config.steps, refit.c_str(),
               session->dataset.split("train").size(), run.c_str());
  printSummary(trainToEnd(*session, run, progress));
  if (progress.profile) std::fprintf(stderr, "%s", profileTable(session->log.profiler).c_str());
  return 0;
}

std::vector<cli::Option> trainOptions() {
  std::vector<cli::Option> o = {
      {"output", "RUN", "output folder (-o); must not exist or be empty", ""},
      {"resume", "RUN", "continue RUN from its newest checkpoint (with --steps N: on to step N; only " + resumeOptionList() + " may be given)", ""},
  };
  for (const TrainOption& t : trainOptionTable())
    if (!t.flag.empty()) o.push_back({t.flag, t.metavar, t.help, shownDefault(t)});
  o.push_back({"time-limit", "S", "stop after the step that reaches S seconds of training (the outputs are written as at the end; --resume continues)", ""});
  o.push_back({"profile", "", "progress lines name the three costliest stages, and the end prints every stage's mean ms per step (always in metrics.json's \"profile\")", ""});
  for (auto& d : datasetOptions()) o.push_back(d);
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"train", "jointly optimise the water surface and the Gaussians under it", "refrax train <dataset> -o RUN [options] | refrax train --resume RUN",
                trainOptions(), runTrain});

}  // namespace
}  // namespace refrax
