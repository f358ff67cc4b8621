#include "engine/model/open_model.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/base/error.h"
#include "engine/base/number_text.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/gaussian/gaussian_adam.h"
#include "engine/run/checkpoint_files.h"
#include "engine/run/train_views.h"
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

namespace {

bool near(double a, double b, double tolerance) { return std::abs(a - b) <= tolerance; }

}  // namespace

std::vector<std::string> sceneMismatches(const TrainConfig& c, const Dataset& run, const Dataset& other) {
  std::vector<std::string> out;
  // Lengths to a millionth of the scene (the run's written values round-trip far closer).
  const double length = 1e-6 * std::max(1.0, c.extent);
  if (!near(other.water.ior, c.ior, 1e-9)) out.push_back("its IOR is " + numberText(other.water.ior) + ", the run's " + numberText(c.ior));
  if (other.water.height && !near(*other.water.height, c.waterHeight, length))
    out.push_back("its water height is " + numberText(*other.water.height) + ", the run's " + numberText(c.waterHeight));
  if (const auto& d = other.water.domain;
      d && !(near(d->xMin, c.domain.xMin, length) && near(d->xMax, c.domain.xMax, length) && near(d->yMin, c.domain.yMin, length) &&
             near(d->yMax, c.domain.yMax, length)))
    out.push_back("its water domain is x " + numberText(d->xMin) + ".." + numberText(d->xMax) + ", y " + numberText(d->yMin) + ".." + numberText(d->yMax) +
                  ", the run's x " + numberText(c.domain.xMin) + ".." + numberText(c.domain.xMax) + ", y " + numberText(c.domain.yMin) + ".." +
                  numberText(c.domain.yMax));
  if (!other.splits.count("train") || !run.splits.count("train")) return out;
  const std::vector<View>& mine = run.split("train");
  const std::vector<View>& theirs = other.split("train");
  if (mine.size() != theirs.size()) {
    out.push_back("it has " + std::to_string(theirs.size()) + " training views, the run " + std::to_string(mine.size()));
    return out;
  }
  for (size_t i = 0; i < mine.size(); i++) {
    const Camera &a = mine[i].camera, &b = theirs[i].camera;
    // Positions to a thousandth of the scene, axes to a milliradian, the horizontal field of
    // view to a thousandth: the same rig rendered at another size passes, another rig does not.
    const bool same = glm::length(a.position() - b.position()) <= 1e-3 * std::max(1.0, c.extent) &&
                      glm::dot(glm::normalize(a.back()), glm::normalize(b.back())) >= std::cos(1e-3) &&
                      glm::dot(glm::normalize(a.up()), glm::normalize(b.up())) >= std::cos(1e-3) &&
                      near(a.fx / a.width, b.fx / b.width, 1e-3 * a.fx / a.width) && a.lens.kind == b.lens.kind;
    if (!same) {
      const glm::dvec3 p = b.position(), q = a.position();
      out.push_back("its training view " + std::to_string(i) + " (" + theirs[i].name + ") is a camera at (" + numberText(p.x) + ", " + numberText(p.y) +
                    ", " + numberText(p.z) + "), the run's at (" + numberText(q.x) + ", " + numberText(q.y) + ", " + numberText(q.z) + ") or looking elsewhere");
      break;  // one camera says it; the rest would repeat it
    }
  }
  return out;
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
