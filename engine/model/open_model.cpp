#include "engine/model/open_model.h"

#include <filesystem>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/optim/table_adam.h"
#include "engine/train/checkpoint_files.h"
#include "engine/train/train_views.h"
#include "engine/vk/vk_commands.h"

namespace refrax {

TrainConfig readRunConfig(const std::string& runDir) {
  std::string path = (std::filesystem::path(runDir) / "config.json").string();
  if (!fileExists(path)) fail(runDir + " is not a training run (no config.json)");
  return trainConfigFromJson(readJson(path), path);
}

Dataset loadRunDataset(const TrainConfig& c) {
  Dataset dataset = loadDataset(c.dataset, c.datasetOptions);
  keepTrainViews(dataset, c.trainViews);
  return dataset;
}

CheckpointShape checkpointShapeFor(const Model& m, const Dataset& dataset) {
  CheckpointShape shape;
  shape.model = waterModelName(m.config.model);
  shape.trainViews = dataset.split("train").size();
  shape.adamGroups = createGaussianAdam(1.0, 1, 0).groups.size();  // the file holds the Gaussians' Adam groups
  shape.heightCount = m.height ? m.height->parameterCount : 0;
  return shape;
}

void installModelParameters(Model& m, CheckpointContents& c, const std::vector<View>& trainViews) {
  m.step = c.step;
  m.trainingSeconds = c.trainingSeconds;
  m.gaussians.params = std::move(c.params);
  validateGaussians(m.gaussians, "the checkpoint");
  uploadModelGaussians(m);
  if (m.height) {
    uploadWeights(*m.ctx, *m.height, c.heightWeights);
    m.height->config.encodingWindow = encodingWindowAfterStep(m.config, m.step, surfaceBatchSteps(m.config, trainViews.size()));
  }
  m.planeHeight = c.planeHeight;
  m.plane.waves.base = float(c.planeHeight);
  if (m.surface) {
    liftSurface(m);
    if (m.step > m.config.schedule.surfaceFreeze) anchorMeanHeight(m, viewWeights(m, trainViews));
  }
}

void loadModelCheckpoint(Model& m, const std::string& path, const Dataset& dataset) {
  CheckpointContents c = decodeCheckpoint(readFile(path), path, checkpointShapeFor(m, dataset));
  installModelParameters(m, c, dataset.split("train"));
}

std::unique_ptr<Model> openModel(Context& ctx, const std::string& runDir, const Dataset& dataset) {
  auto m = std::make_unique<Model>();
  initModel(*m, ctx, readRunConfig(runDir), dataset);
  std::string ckpt = latestCheckpoint(runDir);
  if (ckpt.empty()) fail(runDir + " has no checkpoint yet");
  loadModelCheckpoint(*m, ckpt, dataset);
  return m;
}

}  // namespace refrax
