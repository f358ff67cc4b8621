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

CheckpointContents checkpointContents(TrainSession& s) {
  pushWaterGradient(s);  // the water's pending gradient is saved as the parameters' (heightGrad, planeGrad)
  Context& ctx = *s.model.ctx;
  pullGaussians(s);  // the device steps them: the host's copy as of this step
  CheckpointContents c;
  c.model = waterModelName(s.model.config.model);
  c.step = int32_t(s.model.step);
  c.trainingSeconds = s.model.trainingSeconds;
  std::ostringstream rng;
  rng << s.state.rng;
  c.rng = rng.str();
  c.viewOrder = s.state.viewOrder;
  c.viewCursor = s.state.viewCursor;
  c.gaussians = s.model.gaussians.count();
  c.params = s.model.gaussians.params;
  c.adamM = s.state.gaussianAdam.m;
  c.adamV = s.state.gaussianAdam.v;
  for (const auto& g : s.state.gaussianAdam.groups) c.groupSteps.push_back(int32_t(g.step));
  c.densifyStats = s.state.densifyStats;
  c.heightCount = s.model.height ? s.model.height->parameterCount : 0;
  if (s.model.height) {
    c.heightWeights = downloadWeights(ctx, *s.model.height);
    c.heightM = downloadVector<float>(ctx, s.water.heightAdam.m, c.heightCount);
    c.heightV = downloadVector<float>(ctx, s.water.heightAdam.v, c.heightCount);
    c.heightStep = int32_t(s.water.heightAdam.step);
    c.heightGrad = downloadVector<float>(ctx, s.water.heightGrad, c.heightCount);
  }
  c.planeHeight = s.model.planeHeight;
  if (!s.water.planeAdam.m.empty()) {  // the flat-water model's Adam
    c.planeM = s.water.planeAdam.m[0];
    c.planeV = s.water.planeAdam.v[0];
    c.planeStep = int32_t(s.water.planeAdam.groups[0].step);
  }
  c.planeGrad = s.water.planeGrad;
  return c;
}

void saveCheckpoint(TrainSession& s, const std::string& runDir) {
  const std::string bytes = encodeCheckpoint(checkpointContents(s));

  std::filesystem::create_directories(std::filesystem::path(runDir) / "checkpoints");
  writeFileAtomic(checkpointPath(runDir, s.model.step), bytes.data(), bytes.size());
  // Keep the newest kKept checkpoints.
  std::vector<int> steps;
  for (const auto& e : std::filesystem::directory_iterator(std::filesystem::path(runDir) / "checkpoints")) {
    int k = checkpointStep(e.path().string());
    if (k >= 0) steps.push_back(k);
  }
  std::sort(steps.begin(), steps.end());
  for (size_t i = 0; i + kKept < steps.size(); i++) std::filesystem::remove(checkpointPath(runDir, steps[i]));
}

void restoreCheckpointContents(TrainSession& s, CheckpointContents c) {
  // Read and checked before anything is installed: a bad RNG text leaves the session as it was.
  std::istringstream rng(c.rng);
  std::mt19937 restored;
  rng >> restored;
  if (rng.fail()) fail("checkpoint: unreadable RNG state");
  // The model's parameters first (the Gaussians uploaded, the water lifted and anchored), then
  // the training state.
  installModelParameters(s.model, c, s.dataset.split("train"));
  Context& ctx = *s.model.ctx;
  s.state.rng = restored;
  s.state.viewOrder = std::move(c.viewOrder);
  s.state.viewCursor = c.viewCursor;
  s.state.gaussianAdam.m = std::move(c.adamM);
  s.state.gaussianAdam.v = std::move(c.adamV);
  for (size_t g = 0; g < c.groupSteps.size(); g++) s.state.gaussianAdam.groups[g].step = c.groupSteps[g];
  allocateGaussianBuffers(s);
  s.state.densifyStats = std::move(c.densifyStats);
  if (s.model.height) {
    upload(ctx, s.water.heightAdam.m, c.heightM.data(), c.heightM.size() * 4);
    upload(ctx, s.water.heightAdam.v, c.heightV.data(), c.heightV.size() * 4);
    s.water.heightAdam.step = c.heightStep;
    upload(ctx, s.water.heightGrad, c.heightGrad.data(), c.heightGrad.size() * 4);
  }
  if (!s.water.planeAdam.m.empty()) {
    s.water.planeAdam.m[0] = float(c.planeM);
    s.water.planeAdam.v[0] = float(c.planeV);
    s.water.planeAdam.groups[0].step = c.planeStep;
  }
  s.water.planeGrad = c.planeGrad;
}

void loadCheckpoint(TrainSession& s, const std::string& path) {
  restoreCheckpointContents(s, decodeCheckpoint(readFile(path), path, checkpointShapeFor(s.model, s.dataset)));
}

}  // namespace refrax
