#include "engine/train/checkpoint.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/train/checkpoint_format.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {
namespace {

constexpr int kKept = 2;

int stepOfName(const std::string& name) {
  if (name.rfind("step_", 0) != 0 || name.size() < 11 || name.substr(name.size() - 5) != ".ckpt") return -1;
  std::string digits = name.substr(5, name.size() - 10);
  if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(digits);
}

}  // namespace

std::string checkpointPath(const std::string& runDir, int step) {
  char name[32];
  std::snprintf(name, sizeof name, "step_%07d.ckpt", step);
  return (std::filesystem::path(runDir) / "checkpoints" / name).string();
}

std::string latestCheckpoint(const std::string& runDir) {
  std::filesystem::path dir = std::filesystem::path(runDir) / "checkpoints";
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec)) return "";
  int best = -1;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) best = std::max(best, stepOfName(e.path().filename().string()));
  return best < 0 ? "" : checkpointPath(runDir, best);
}

int checkpointStep(const std::string& path) { return stepOfName(std::filesystem::path(path).filename().string()); }

std::string intactCheckpointBefore(const std::string& runDir, int step) {
  std::filesystem::path dir = std::filesystem::path(runDir) / "checkpoints";
  std::error_code ec;
  std::vector<int> steps;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) {
    int k = stepOfName(e.path().filename().string());
    if (k >= 0 && k < step) steps.push_back(k);
  }
  std::sort(steps.rbegin(), steps.rend());
  for (int k : steps) {
    try {
      verifyCheckpointFile(checkpointPath(runDir, k));
      return checkpointPath(runDir, k);
    } catch (const Error&) {
    }
  }
  return "";
}

void saveCheckpoint(TrainSession& s, const std::string& runDir) {
  pushWaterGradient(s);  // the water's pending gradient is saved as the parameters' (heightGrad, planeGrad)
  Context& ctx = *s.ctx;
  CheckpointContents c;
  c.model = waterModelName(s.config.model);
  c.step = int32_t(s.step);
  c.trainingSeconds = s.trainingSeconds;
  std::ostringstream rng;
  rng << s.rng;
  c.rng = rng.str();
  c.viewOrder = s.viewOrder;
  c.viewCursor = s.viewCursor;
  c.gaussians = s.gaussians.count();
  c.params = s.gaussians.params;
  c.adamM = s.gaussianAdam.m;
  c.adamV = s.gaussianAdam.v;
  for (const auto& g : s.gaussianAdam.groups) c.groupSteps.push_back(int32_t(g.step));
  c.densifyStats = s.densifyStats;
  c.heightCount = s.height ? s.height->parameterCount : 0;
  if (s.height) {
    c.heightWeights = downloadWeights(ctx, *s.height);
    c.heightM = downloadVector<float>(ctx, s.heightAdam.m, c.heightCount);
    c.heightV = downloadVector<float>(ctx, s.heightAdam.v, c.heightCount);
    c.heightStep = int32_t(s.heightAdam.step);
    c.heightGrad = downloadVector<float>(ctx, s.heightGrad, c.heightCount);
  }
  c.planeHeight = s.planeHeight;
  if (!s.planeAdam.m.empty()) {  // the flat-water model's Adam
    c.planeM = s.planeAdam.m[0];
    c.planeV = s.planeAdam.v[0];
    c.planeStep = int32_t(s.planeAdam.groups[0].step);
  }
  c.planeGrad = s.planeGrad;
  const std::string bytes = encodeCheckpoint(c);

  std::filesystem::create_directories(std::filesystem::path(runDir) / "checkpoints");
  writeFileAtomic(checkpointPath(runDir, s.step), bytes.data(), bytes.size());
  // Keep the newest kKept checkpoints.
  std::vector<int> steps;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(runDir) / "checkpoints")) {
    int k = stepOfName(e.path().filename().string());
    if (k >= 0) steps.push_back(k);
  }
  std::sort(steps.begin(), steps.end());
  for (size_t i = 0; i + kKept < steps.size(); i++) std::filesystem::remove(checkpointPath(runDir, steps[i]));
}

void verifyCheckpointFile(const std::string& path) { verifyCheckpointBytes(readFile(path), path); }

void loadCheckpoint(TrainSession& s, const std::string& path) {
  CheckpointShape shape;
  shape.model = waterModelName(s.config.model);
  shape.trainViews = s.dataset.split("train").size();
  shape.adamGroups = s.gaussianAdam.groups.size();
  shape.heightCount = s.height ? s.height->parameterCount : 0;
  CheckpointContents c = decodeCheckpoint(readFile(path), path, shape);
  std::istringstream rng(c.rng);
  std::mt19937 restored;
  rng >> restored;

  // Everything read and checked: install it.
  Context& ctx = *s.ctx;
  s.step = c.step;
  s.trainingSeconds = c.trainingSeconds;
  s.rng = restored;
  s.viewOrder = c.viewOrder;
  s.viewCursor = c.viewCursor;
  s.gaussians.params = std::move(c.params);
  s.gaussianAdam.m = std::move(c.adamM);
  s.gaussianAdam.v = std::move(c.adamV);
  for (size_t g = 0; g < c.groupSteps.size(); g++) s.gaussianAdam.groups[g].step = c.groupSteps[g];
  syncGaussians(s, true);
  s.densifyStats = std::move(c.densifyStats);
  if (s.height) {
    uploadWeights(ctx, *s.height, c.heightWeights);
    s.height->config.encodingWindow = encodingWindowAfterStep(s.config, s.step, surfaceBatchSteps(s));
    upload(ctx, s.heightAdam.m, c.heightM.data(), c.heightM.size() * 4);
    upload(ctx, s.heightAdam.v, c.heightV.data(), c.heightV.size() * 4);
    s.heightAdam.step = c.heightStep;
    upload(ctx, s.heightGrad, c.heightGrad.data(), c.heightGrad.size() * 4);
  }
  s.planeHeight = c.planeHeight;
  if (!s.planeAdam.m.empty()) {
    s.planeAdam.m[0] = float(c.planeM);
    s.planeAdam.v[0] = float(c.planeV);
    s.planeAdam.groups[0].step = c.planeStep;
  }
  s.planeGrad = c.planeGrad;
  s.plane.waves.base = float(c.planeHeight);
  if (s.surface) {
    HeightSource src = currentHeightSource(s);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *s.surface, src); });
    if (s.step > s.config.schedule.surfaceFreeze) anchorMeanHeight(s);  // as the uninterrupted run left it
  }
}

}  // namespace refrax
