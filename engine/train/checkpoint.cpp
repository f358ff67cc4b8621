#include "engine/train/checkpoint.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/model/open_model.h"
#include "engine/run/checkpoint_format.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {
namespace {

constexpr int kKept = 2;

}  // namespace

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
    int k = checkpointStep(e.path().string());
    if (k >= 0) steps.push_back(k);
  }
  std::sort(steps.begin(), steps.end());
  for (size_t i = 0; i + kKept < steps.size(); i++) std::filesystem::remove(checkpointPath(runDir, steps[i]));
}

void loadCheckpoint(TrainSession& s, const std::string& path) {
  CheckpointContents c = decodeCheckpoint(readFile(path), path, checkpointShapeFor(s, s.dataset));
  std::istringstream rng(c.rng);
  std::mt19937 restored;
  rng >> restored;

  // Everything read and checked: install it. The model's parameters first (the Gaussians
  // uploaded, the water lifted and anchored), then the training state.
  installModelParameters(s, c, s.dataset.split("train"));
  Context& ctx = *s.ctx;
  s.rng = restored;
  s.viewOrder = c.viewOrder;
  s.viewCursor = c.viewCursor;
  s.gaussianAdam.m = std::move(c.adamM);
  s.gaussianAdam.v = std::move(c.adamV);
  for (size_t g = 0; g < c.groupSteps.size(); g++) s.gaussianAdam.groups[g].step = c.groupSteps[g];
  allocateGaussianBuffers(s);
  s.densifyStats = std::move(c.densifyStats);
  if (s.height) {
    upload(ctx, s.heightAdam.m, c.heightM.data(), c.heightM.size() * 4);
    upload(ctx, s.heightAdam.v, c.heightV.data(), c.heightV.size() * 4);
    s.heightAdam.step = c.heightStep;
    upload(ctx, s.heightGrad, c.heightGrad.data(), c.heightGrad.size() * 4);
  }
  if (!s.planeAdam.m.empty()) {
    s.planeAdam.m[0] = float(c.planeM);
    s.planeAdam.v[0] = float(c.planeV);
    s.planeAdam.groups[0].step = c.planeStep;
  }
  s.planeGrad = c.planeGrad;
}

}  // namespace refrax
