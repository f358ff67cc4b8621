#pragma once
// A training run on disk: RUN/config.json (the resolved configuration), RUN/checkpoints/,
// RUN/evaluations.json (with --eval-every), RUN/surface_watch.json (the refraction model's
// roughening watch, engine/surface/surface_watch.h),
// and at the end point_cloud.ply, water_height.npy (+ height_field.bin), renders/ and
// metrics.json. Every file is written atomically; a bad dataset fails before RUN is created.
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/model/open_model.h"
#include "engine/run/train_config.h"
#include "engine/train/train_session.h"

namespace refrax {

struct Context;

// Fills the water and scene values of `config` from the dataset (water.json and options,
// else derived from the cameras: engine/dataset/scene_bounds.h) and resolves the schedule.
// refrax::Error when the water height is unknown.
void resolveSceneConfig(TrainConfig& config, const Dataset& dataset);

struct TrainProgress {
  std::function<void(const std::string&)> line;  // progress lines (stderr in the CLI)
  bool profile = false;  // progress lines end with the step's three costliest stages (--profile)
  double timeLimitSeconds = 0;  // > 0: stop after the step that reaches this much training time (--time-limit)
};

// Trains from the session's current step to totalSteps(config), writing checkpoints, then the
// final outputs. runDir must exist and hold config.json.
nlohmann::json trainToEnd(TrainSession& session, const std::string& runDir, const TrainProgress& progress);

// RUN/evaluations.json: one entry per --eval-every evaluation, {step, seconds (training
// wall time up to that step, evaluations excluded), psnr, ssim, surface_rmse (when the
// dataset has a ground-truth surface)}, written as training goes; entries past `upToStep`
// (left by a run resumed from an earlier checkpoint) are dropped. Empty when absent.
nlohmann::json readEvaluations(const std::string& runDir, int upToStep);

// Writes the final outputs of the session into runDir. metrics.json's "evaluations" is the
// run's evaluations (above) followed by the final one, the accuracy-against-time curve.
nlohmann::json writeRunOutputs(TrainSession& session, const std::string& runDir);

// A run's training session restored from its newest checkpoint, to train on (resume) or
// differentiate (gradcheck); what only draws or measures the model opens it with openModel
// (engine/model/open_model.h, which also reads config.json: readRunConfig).
std::unique_ptr<TrainSession> openRun(Context& ctx, const std::string& runDir, bool requireCheckpoint = true);

}  // namespace refrax
