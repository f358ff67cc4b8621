#pragma once
// Shared by the training tests: a temporary folder, and tiny synthetic datasets generated
// once per test process by the `refrax synth` CLI.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "engine/dataset/dataset.h"
#include "engine/io/json_io.h"
#include "engine/train/train_run.h"
#include "tests/gpu_test.h"

namespace refrax::test {

struct TrainTempDir {
  std::filesystem::path path;
  TrainTempDir() {
    path = std::filesystem::temp_directory_path() / ("refrax-train-test-" + std::to_string(getpid()) + "-" + std::to_string(freshSeed()) + "-" + std::to_string(std::rand()));
    std::filesystem::create_directories(path);
  }
  ~TrainTempDir() { std::filesystem::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

// The GPU's water settings for a 300-step run (one surface step per pass over the views, the
// schedule of train_recipe.cpp's kGpuWater at 300 steps), given so that a CPU trains them too:
// the tiny training tests' figures were measured under them. The CPU's own (a surface step every
// step) waited for 281 of 300 steps and made 2.08 submissions a step there (2026-12-07; issue 48).
inline constexpr const char* kGpuWater300StepOptions =
    " --surface-batch views --surface-lr 1e-3 --level-prior 10000 --restart-gaussians 100,160 --surface-freeze 40";

// The tiny preset's dataset folder, with extra `refrax synth` options (generated on first
// use; removed at process exit).
inline std::string tinyDataset(const std::string& preset, const std::string& options = "") {
  static TrainTempDir root;
  static std::map<std::string, std::string> made;
  const std::string key = preset + options;
  auto it = made.find(key);
  if (it != made.end()) return it->second;
  std::string dir = root / (preset + "-" + std::to_string(made.size()));
  CliResult r = runCli("synth " + preset + " --size tiny " + options + " -o " + dir);
  REQUIRE_MESSAGE(r.exitCode == 0, r.output);
  return made[key] = dir;
}

// The repository's textures (assets/textures), or a copied build's (scripts/gpu-check.sh --bundle
// sets REFRAX_SOURCE_DIR).
inline std::string textureDir() {
  const char* source = std::getenv("REFRAX_SOURCE_DIR");
  return std::string(source ? source : REFRAX_SOURCE_DIR) + "/assets/textures";
}

// A refusal as the CLI must give it: a non-zero exit and one line that says `words`.
inline void checkOneError(const CliResult& r, const std::string& words) {
  INFO(r.output);
  CHECK(r.exitCode != 0);
  CHECK(r.output.find(words) != std::string::npos);
  CHECK(std::count(r.output.begin(), r.output.end(), '\n') == 1);
}

// A configuration for driving a TrainSession directly: `steps` steps of `patch` x `patch`
// patches from `gaussians` initial Gaussians on `data`, resolved against its dataset (loaded
// into `dataset`) as `refrax train` resolves it. Set schedule fields after this call.
inline TrainConfig sessionConfig(const std::string& data, int steps, uint32_t gaussians, uint32_t patch, uint64_t seed, Dataset& dataset) {
  TrainConfig c;
  c.dataset = data;
  c.steps = steps;
  c.initialGaussians = gaussians;
  c.patch = patch;
  c.seed = seed;
  dataset = loadDataset(data, c.datasetOptions);
  resolveSceneConfig(c, dataset);
  return c;
}

inline nlohmann::json trainAndReadMetrics(const std::string& dataset, const std::string& run, const std::string& options) {
  CliResult r = runCli("train " + dataset + " -o " + run + " " + options);
  INFO(r.output);
  REQUIRE(r.exitCode == 0);
  return readJson(run + "/metrics.json");
}

}  // namespace refrax::test
