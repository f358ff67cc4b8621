#pragma once
// A model of a scene under water (docs/method.md §1): the Gaussians and their ray-tracing
// proxies, the water, and the buffers that trace camera rays through both. This is what
// `refrax render`, `refrax eval` and the viewer load from a run (engine/model/open_model.h),
// and what a training session (engine/train/train_session.h) holds beside its optimisers,
// loss and batch buffers.
//
// The water, by config.model:
//   refraction    `height`: the MLP height field (engine/height/height_field.h)
//   flat-water    `plane`: an analytic field with no waves at the one learned `planeHeight`
//   known-water   `plane`: the dataset's ground-truth waves (water.json), fixed; or, where
//                 they have no closed form AnalyticWaves holds, `trueGrid`: its height map
//   no-refraction no water: camera rays go straight to the Gaussians
// and, for the first three, `surface`: the proxy mesh lifted from that height source, which
// refracts rays (engine/surface/water_surface.h).
//
// Not movable (height sources refer to its members): it lives in a unique_ptr.
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/camera/camera_rays.h"
#include "engine/dataset/dataset.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/height/analytic_height.h"
#include "engine/height/grid_height.h"
#include "engine/height/height_field.h"
#include "engine/loss/metrics.h"
#include "engine/surface/water_surface.h"
#include "engine/run/train_config.h"

namespace refrax {

struct Context;

struct Model {
  Model() = default;
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;
  ~Model() = default;

  Context* ctx = nullptr;
  TrainConfig config;          // the run's resolved configuration (its config.json)
  int step = 0;                // training steps the parameters have taken
  double trainingSeconds = 0;  // wall time those steps took (carried across resumes)

  // The Gaussians: the host table, its device copy, the tracer and its proxies.
  GaussianSet gaussians;
  DeviceGaussians device;
  GaussianTracer tracer;
  ProxyKind proxyKind = ProxyKind::AabbBlas;
  GaussianProxies proxies;

  // The water (see above).
  std::optional<HeightField> height;
  AnalyticHeightField plane;
  double planeHeight = 0;
  std::optional<GridHeightField> trueGrid;  // known-water from a height map: on the device,
  std::optional<HeightGrid> trueGridHost;   // and in double for the host's samples
  std::optional<WaterSurface> surface;

  // Rays of one pass (up to `capacity`): from the camera, as they leave the water, the
  // surface's per-ray records, and the Gaussians' results.
  uint32_t capacity = 0;
  CameraRayPipelines rayPipelines;
  Buffer rays, refracted, records, results;
  Buffer resultsReadback;  // where an image's render copies the results for the host (renderView)
};

// The device objects of config's model: tracer, ray buffers for the dataset's largest image,
// and the water in its initial state (the MLP drawn from config.seed at the water height, the
// plane at the water height, or the dataset's ground-truth waves), lifted into the surface.
// No Gaussians yet: set m.gaussians, then uploadModelGaussians.
void initModel(Model& m, Context& ctx, const TrainConfig& config, const Dataset& dataset);

// After m.gaussians changed in count or wholesale: upload them and build new proxies.
void uploadModelGaussians(Model& m);

// The height source the surface is lifted from (the MLP or the plane); the model has water.
HeightSource currentHeightSource(const Model& m);
// Lifts the surface from the current height source again (after the parameters changed).
void liftSurface(Model& m);
// The height MLP's initialisation seed, from the run's seed.
uint32_t heightFieldSeed(const TrainConfig& config);
// The height MLP back to its initial weights and level (the run's flat start; its encoding
// window as it is now), and the surface lifted from it.
void restartHeightField(Model& m);
// The proxy-surface configuration (domain, grid, levels, IOR, ray capacity).
WaterSurfaceConfig surfaceConfigFor(const Model& m);
// Makes room for `rays` rays per pass (a render larger than the dataset's images): new ray
// buffers and a new surface. The surface must hold no pending gradient (training pushes it
// into the parameters first).
void growModelRayCapacity(Model& m, uint32_t rays);

// SH degree in force at step t (1-based), from the schedule.
uint32_t shDegreeAt(const TrainConfig& config, int step);

// Per coarse grid slot ((cellsX + 3) x (cellsY + 3), border ring included at weight 0): how
// many of `views` see the interior vertex at the flat water height.
std::vector<double> viewWeights(const Model& m, const std::vector<View>& views);
// With config.anchorMeanHeight, for the MLP: sets the height field's constant so that the
// mean height the views see (each coarse vertex weighted by viewWeights) is
// config.waterHeight, and lifts the surface again. Water every view sees counts most, a corner
// one camera sees counts little, unseen water not at all (an unweighted mean let the border
// carry the shift the seen centre needed: on the strong-wave tiny preset the centre sat 2-6 cm
// low). A function of the weights alone, so a reloaded model recomputes the constant (to float
// rounding: training reaches it by one shift per surface step).
void anchorMeanHeight(Model& m, const std::vector<double>& weights);
// The shift anchorMeanHeight adds to the constant, from the coarse grid's lifted `heights` (0
// where no weighted height is finite). Training reads the heights its step's submission copied.
double meanHeightShift(const Model& m, const std::vector<float>& heights, const std::vector<double>& weights);

// The water's heights on an nx x ny grid over the domain, rows along y (water_height.npy's
// layout, engine/dataset/ground_truth.h); the water height everywhere without water.
std::vector<double> sampleWaterHeights(Model& m, uint32_t nx, uint32_t ny);

}  // namespace refrax
