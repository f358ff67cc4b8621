#pragma once
// A trained run's model, loaded without a training session: RUN/config.json (the resolved
// configuration, engine/run/train_config.h), the dataset it names (for the cameras, the
// training views the mean height is anchored over, and known water's waves), and the
// parameters of the run's newest checkpoint (the Gaussians, the MLP's weights or the plane's
// height; the optimisers' state, the RNG and the view order are left in the file).
#include <memory>
#include <string>
#include <vector>

#include "engine/dataset/dataset.h"
#include "engine/model/model.h"
#include "engine/run/checkpoint_format.h"

namespace refrax {

// config.json of a run (refrax::Error when the folder is not a run).
TrainConfig readRunConfig(const std::string& runDir);
// The run's dataset as it trained on it (its --train-views applied).
Dataset loadRunDataset(const TrainConfig& config);

// How `other` (a dataset to evaluate the run against) differs from the scene the run learned:
// its IOR, water height or domain against the run's config.json, its training cameras
// (count, positions, view directions, fields of view) against the run's dataset's. Empty when
// it is the same scene (its own dry copy, the same views at another resolution, other test
// views). Each entry says what differs, with both values.
std::vector<std::string> sceneMismatches(const TrainConfig& config, const Dataset& run, const Dataset& other);

// The run's model at its newest checkpoint (refrax::Error when it has none); `dataset` is the
// run's (loadRunDataset).
std::unique_ptr<Model> openModel(Context& ctx, const std::string& runDir, const Dataset& dataset);
// Replaces the model's parameters with a checkpoint's (the viewer's reload). Everything is
// read and checked before anything changes.
void loadModelCheckpoint(Model& model, const std::string& path, const Dataset& dataset);

// What a checkpoint's decoding must expect of a model trained on `dataset`.
CheckpointShape checkpointShapeFor(const Model& model, const Dataset& dataset);
// Installs a decoded checkpoint's parameters (moved out of `c`): the Gaussians uploaded with
// new proxies, the MLP's weights and encoding window or the plane's height, the surface lifted
// and, once the surface has learned, its mean height anchored over `trainViews` as the
// uninterrupted run left it.
void installModelParameters(Model& model, CheckpointContents& c, const std::vector<View>& trainViews);

}  // namespace refrax
