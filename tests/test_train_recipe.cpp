// The recipe (engine/run/train_recipe.h): what `refrax train DATA -o RUN` does with no method
// flags. The method's settings fill only what the command line left open, sized for the
// device and the images; the reference recipe changes nothing; a run records its recipe and
// every value it chose, so a resumed run keeps them.
#include <doctest/doctest.h>

#include <filesystem>
#include <set>

#include "engine/io/json_io.h"
#include "engine/run/train_recipe.h"
#include "tests/gpu_test.h"
#include "tests/train_test_util.h"

using namespace refrax;

namespace {

TrainConfig methodConfig(WaterModel model = WaterModel::Refraction) {
  TrainConfig c;
  c.recipe = Recipe::Method;
  c.model = model;
  return c;
}

auto givenKeys(std::set<std::string> keys) {
  return [keys](const std::string& key) { return keys.count(key) > 0; };
}

}  // namespace

TEST_CASE("recipe: the method sizes the run for the device and fills the water's settings") {
  TrainConfig cpu = methodConfig();
  applyRecipe(cpu, givenKeys({}), RecipeDevice{true}, 252, 252);
  CHECK(cpu.steps == 4000);
  CHECK(cpu.patch == 64);
  CHECK(cpu.maxShDegree == 0);
  CHECK(cpu.schedule.densityResetInterval == 0);
  CHECK(cpu.schedule.pruneLargeFrom > 100 * cpu.steps);  // no density resets, no large prune (3DGS)
  CHECK(cpu.initDepth == InitDepth::Sweep);
  CHECK(cpu.surfaceLearningRate == 3e-3);
  CHECK(cpu.surfaceBatch == 1);  // a surface step every step
  CHECK(cpu.schedule.surfaceFreeze == 400);
  CHECK(cpu.schedule.gaussianRestarts == std::vector<int>{1000, 1600, 2200});
  CHECK(cpu.mlpCoarseOctaves == 3);
  CHECK(cpu.anchorMeanHeight);
  CHECK(cpu.levelPrior == 10000);  // the gentlest waves ran away under 1,000
  CHECK(cpu.surfaceSmoothness == 0.1);

  TrainConfig gpu = methodConfig();
  applyRecipe(gpu, givenKeys({}), RecipeDevice{false}, 252, 252);
  CHECK(gpu.steps == 15000);
  CHECK(gpu.patch == 0);  // whole images
  CHECK(gpu.surfaceLearningRate == 1e-3);  // the GPU's water is not the CPU's
  CHECK(gpu.surfaceBatch == 0);            // views
  CHECK(gpu.schedule.surfaceFreeze == 2000);
  CHECK(gpu.schedule.gaussianRestarts == std::vector<int>{5000, 8000});
  CHECK(gpu.levelPrior == 10000);
  CHECK(gpu.surfaceSmoothness == 0.1);

  TrainConfig small = methodConfig();  // images no larger than the 64 px patch train whole
  applyRecipe(small, givenKeys({}), RecipeDevice{true}, 64, 200);
  CHECK(small.patch == 0);
  TrainConfig fits = methodConfig();
  applyRecipe(fits, givenKeys({}), RecipeDevice{true}, 65, 200);
  CHECK(fits.patch == 64);
}

TEST_CASE("recipe: a flag given wins, and the schedule follows the steps given") {
  TrainConfig c = methodConfig();
  c.steps = 1500;
  c.patch = 16;
  c.levelPrior = 10;
  c.maxShDegree = 2;
  const std::vector<RecipeChoice> chosen =
      applyRecipe(c, givenKeys({"steps", "patch", "level_prior", "max_sh_degree"}), RecipeDevice{true}, 252, 252);
  CHECK(c.steps == 1500);
  CHECK(c.patch == 16);
  CHECK(c.levelPrior == 10);
  CHECK(c.maxShDegree == 2);
  CHECK(c.schedule.gaussianRestarts == std::vector<int>{375, 600, 825});  // 1/4, 2/5 and 11/20 of the run
  CHECK(c.schedule.surfaceFreeze == 150);
  for (const RecipeChoice& choice : chosen) CHECK(std::set<std::string>{"steps", "patch", "level_prior", "max_sh_degree"}.count(choice.key) == 0);

  TrainConfig shortRun = methodConfig();  // too short for a restart: none, not a refused run
  shortRun.steps = 1;
  applyRecipe(shortRun, givenKeys({"steps"}), RecipeDevice{true}, 252, 252);
  CHECK(shortRun.schedule.gaussianRestarts.empty());

  // Density resets given bring the large prune back at its reference step; a large prune given
  // is kept either way.
  TrainConfig resets = methodConfig();
  resets.schedule.densityResetInterval = 1000;
  applyRecipe(resets, givenKeys({"schedule/density_reset_interval"}), RecipeDevice{true}, 252, 252);
  CHECK(resets.schedule.pruneLargeFrom == -1);  // resolveSchedule's 3000 x steps/15000
  TrainConfig pruned = methodConfig();
  pruned.schedule.pruneLargeFrom = 700;
  applyRecipe(pruned, givenKeys({"schedule/prune_large_from"}), RecipeDevice{true}, 252, 252);
  CHECK(pruned.schedule.pruneLargeFrom == 700);
}

TEST_CASE("recipe: the comparison models take the Gaussians' settings, not the water's") {
  for (WaterModel model : {WaterModel::NoRefraction, WaterModel::KnownWater}) {
    TrainConfig c = methodConfig(model);
    applyRecipe(c, givenKeys({}), RecipeDevice{true}, 252, 252);
    INFO(waterModelName(model));
    CHECK(c.patch == 64);
    CHECK(c.maxShDegree == 0);
    CHECK(c.initDepth == InitDepth::Sweep);
    CHECK(c.schedule.pruneLargeFrom > 100 * c.steps);
    CHECK(c.schedule.gaussianRestarts.empty());  // restarts free the water from a warped scene: no learned water, none
    CHECK(c.surfaceLearningRate == TrainConfig{}.surfaceLearningRate);
    CHECK(!c.anchorMeanHeight);
  }
  // A learned plane: the water's schedule, no height-field terms; on a CPU too the GPU's slower
  // water settings, under which its barely determined height walks less far.
  TrainConfig flat = methodConfig(WaterModel::FlatWater);
  applyRecipe(flat, givenKeys({}), RecipeDevice{true}, 252, 252);
  CHECK(flat.steps == 4000);
  CHECK(flat.schedule.gaussianRestarts == std::vector<int>{1333, 2133});
  CHECK(flat.schedule.surfaceFreeze == 533);
  CHECK(flat.surfaceLearningRate == 1e-3);
  CHECK(flat.surfaceBatch == 0);
  CHECK(flat.levelPrior == 0);
  CHECK(flat.surfaceSmoothness == 0);

  TrainConfig fromPly = methodConfig();  // Gaussians read from a file take no depth; fixed ones no restarts
  fromPly.gaussiansFrom = "/x.ply";
  fromPly.gaussiansFixed = true;
  applyRecipe(fromPly, givenKeys({}), RecipeDevice{true}, 252, 252);
  CHECK(fromPly.initDepth == InitDepth::Box);
  CHECK(fromPly.schedule.gaussianRestarts.empty());
}

TEST_CASE("recipe: the reference changes nothing") {
  TrainConfig c;
  c.recipe = Recipe::Reference;
  CHECK(applyRecipe(c, givenKeys({}), RecipeDevice{true}, 252, 252).empty());
  CHECK(trainConfigToJson(c) == trainConfigToJson(TrainConfig{}));
}

TEST_CASE("recipe: refrax train records the method's choices, --recipe reference the paper's, and a resume keeps them" *
          doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  const std::string data96 = test::tinyDataset("nerfrac-primary-sine", "--width 96");  // room for a 64 px patch
  test::CliResult method = test::runCli("train " + data96 + " -o " + (dir / "method") + " --steps 12 --gaussians 200 --checkpoint-every 6");
  INFO(method.output);
  REQUIRE(method.exitCode == 0);
  CHECK(method.output.find("the method's settings for a") != std::string::npos);
  nlohmann::json c = readJson(dir / "method/config.json");
  CHECK(c["recipe"] == "method");
  CHECK(c["steps"] == 12);  // given
  CHECK(c["anchor_mean_height"] == true);
  // the device decides the batch and the water's settings: lavapipe is a CPU (patches), a GPU
  // trains whole images
  const bool cpu = method.output.find("for a CPU device") != std::string::npos;
  CHECK(c["patch"] == (cpu ? 64 : 0));
  CHECK(c["surface_lr"] == (cpu ? 3e-3 : 1e-3));
  const nlohmann::json restarts = cpu ? nlohmann::json::array({3, 4, 6}) : nlohmann::json::array({4, 6});
  CHECK(c["schedule"]["gaussian_restarts"] == restarts);

  test::CliResult reference =
      test::runCli("train " + data + " -o " + (dir / "reference") + " --recipe reference --steps 12 --gaussians 200 --checkpoint-every 0");
  REQUIRE(reference.exitCode == 0);
  CHECK(reference.output.find("the method's settings") == std::string::npos);
  nlohmann::json r = readJson(dir / "reference/config.json");
  CHECK(r["recipe"] == "reference");
  CHECK(r["surface_lr"] == 5e-4);
  CHECK(r["max_sh_degree"] == 3);
  CHECK(r["patch"] == 0);

  // resumed to a later step: the recipe is not applied again (the restarts stay those of 12 steps)
  test::CliResult resumed = test::runCli("train --resume " + (dir / "method") + " --steps 15");
  INFO(resumed.output);
  REQUIRE(resumed.exitCode == 0);
  CHECK(readJson(dir / "method/config.json")["schedule"]["gaussian_restarts"] == restarts);

  test::checkOneError(test::runCli("train " + data + " -o " + (dir / "bad") + " --recipe paper"), "--recipe must be method or reference");
  CHECK(!std::filesystem::exists(dir / "bad"));
}

TEST_CASE("recipe: --time-limit without --steps sizes the run to the time, and --steps given is kept" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  test::CliResult timed = test::runCli("train " + data + " -o " + (dir / "timed") + " --time-limit 3 --gaussians 200 --checkpoint-every 0");
  INFO(timed.output);
  REQUIRE(timed.exitCode == 0);
  const size_t at = timed.output.find("--time-limit 3: 30 probe steps took ");
  REQUIRE(at != std::string::npos);
  // "... ms each (N s in all): STEPS steps": config.json holds those steps, and the schedule scaled to them
  const std::string line = timed.output.substr(at, timed.output.find('\n', at) - at);
  const int steps = std::stoi(line.substr(line.rfind("): ") + 3));
  const nlohmann::json c = readJson(dir / "timed/config.json");
  CHECK(c["steps"] == steps);
  CHECK(steps >= 100);
  const bool cpu = timed.output.find("for a CPU device") != std::string::npos;
  CHECK(c["schedule"]["gaussian_restarts"] ==
        (cpu ? nlohmann::json::array({steps / 4, steps * 2 / 5, steps * 11 / 20}) : nlohmann::json::array({steps / 3, steps * 8 / 15})));

  test::CliResult given = test::runCli("train " + data + " -o " + (dir / "given") + " --time-limit 3 --steps 7 --gaussians 200 --checkpoint-every 0");
  REQUIRE(given.exitCode == 0);
  CHECK(given.output.find("probe steps") == std::string::npos);
  CHECK(readJson(dir / "given/config.json")["steps"] == 7);
}
