#pragma once
// What the viewer shows: a training run's model (its newest checkpoint, loaded by openModel,
// engine/model/open_model.h, with its learned water and its dataset's cameras) or a 3DGS PLY
// on its own. A run is followed: pollRunCheckpoint reloads when a newer checkpoint appears
// (checkpoints are written atomically, so a file that exists is complete).
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/camera/camera.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/gaussian/gaussians.h"
#include "engine/height/height_source.h"
#include "engine/train/checkpoint_watch.h"
#include "engine/model/model.h"
#include "engine/surface/water_surface.h"

namespace refrax {

struct Context;

struct ViewScene {
  Context* ctx = nullptr;
  std::string source;  // the run folder or the PLY path (for the title and messages)

  // A run: its dataset (cameras, training views) and its model at the loaded checkpoint.
  std::string runDir;
  Dataset dataset;
  std::unique_ptr<Model> model;
  CheckpointWatch watch;
  std::chrono::steady_clock::time_point lastPoll{};
  uint64_t generation = 0;  // +1 per (re)load: the viewer rebuilds what depends on the model
  std::string status;       // the last reload's outcome (shown in the panel)

  // A PLY: its Gaussians and their proxies (built with `tracer`).
  GaussianSet plyGaussians;
  DeviceGaussians plyDevice;
  GaussianProxies plyProxies;

  GaussianTracer tracer;  // the viewer's (its own K)
  ProxyKind proxyKind = ProxyKind::AabbBlas;

  // Where the water is and what it is made of (a run's config; a PLY's --domain / --water).
  SurfaceDomain domain;
  float waterHeight = 0;
  float ior = 1.33f;
  float background[3] = {0, 0, 0};
  uint32_t maxShDegree = 3;
  std::vector<std::pair<std::string, Camera>> cameras;  // dataset cameras ("test 003", ...)
};

// refrax::Error (one message) for a folder that is not a run, has no checkpoint, or whose
// dataset is missing (its cameras and training views are part of the model's loading).
std::unique_ptr<ViewScene> openRunScene(Context& ctx, const std::string& runDir, uint32_t K);
// `gaussians`: read from plyPath (readGaussiansPly, before any window opens). domain: the water's extent; empty = the Gaussians' xy bounds, padded by a tenth per side.
std::unique_ptr<ViewScene> openPlyScene(Context& ctx, const std::string& plyPath, GaussianSet gaussians, uint32_t K, std::optional<SurfaceDomain> domain,
                                        float waterHeight, float ior);

// For a run, at most once per `interval`: reloads when the run's newest checkpoint is another
// file or newer than the loaded one. Returns true when it reloaded. A checkpoint that fails to
// load (e.g. removed by the trainer between listing and reading) keeps the current model and
// sets `status`; the next poll tries again.
bool pollRunCheckpoint(ViewScene& scene, std::chrono::milliseconds interval = std::chrono::milliseconds(1000));

const DeviceGaussians& sceneGaussians(const ViewScene& scene);
const GaussianProxies& sceneProxies(const ViewScene& scene);
uint32_t sceneGaussianCount(const ViewScene& scene);
// The learned water of a run (MLP height field or flat plane); none for a PLY or a run
// trained without refraction.
std::optional<HeightSource> learnedWater(const ViewScene& scene);
// The model's step (a run) or -1 (a PLY).
int sceneStep(const ViewScene& scene);
// A new k-buffer size: a new tracer (the proxies stay).
void setTracerK(ViewScene& scene, uint32_t K);

}  // namespace refrax
