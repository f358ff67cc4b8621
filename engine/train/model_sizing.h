#pragma once
// The model's size from the data (issue 29: model no more than a scene needs): the Gaussian
// budget, the height field's frequency-encoding octaves and the water proxy mesh, derived from
// the training views (their pixel count and what one pixel covers on the water), each with the
// reason, printed in the run's log and written to RUN/config.json ("model_sizing").
//
// The chain of rules (the numbers are the reasons' "why"; docs/training.md "Model size"):
//   footprint s   the median size of a training pixel on the water plane (metres)
//   octaves L     the finest octave's period D / 2^(L-1) (D the domain's longer side) is at most
//                 the shortest wave the views can tell apart, kResolvableWaveInPixels footprints
//   coarse cells  2^L per side: two coarse vertices (MLP evaluations) per finest-octave period
//   levels K      subdivision until the finest triangles are about kFinestCellInPixels footprints
//   Gaussians     one per kPixelsPerGaussian pixels of a training image, drawn at the start (and
//                 at each restart) and kept as densification's cap: the whole budget from step 0
// The MLP's width and depth are not derived: the model-size study found them within its noise.
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/camera/camera.h"
#include "engine/dataset/dataset.h"

namespace refrax {

// A wave shorter than two SSIM windows (11 px each) moves the texture under it by different
// amounts within one window, so the loss sees its blur, not its shape.
constexpr double kResolvableWaveInPixels = 22;
// Tracing finer than a pixel buys nothing; the full-size presets' 64 x 2 mesh (finest cell
// 2.5 footprints) was the model-size study's best, so about two footprints.
constexpr double kFinestCellInPixels = 2;
// The budget is the old cap (one per 64 pixels to start, 8x that by densification). Drawn whole
// at the start, on the full-size dry controls with the table's settings: nerfrac-primary-sine
// 28.19 dB against 25.35, desk 23.70 / SSIM 0.495 against 23.17 / 0.409 (one run each): the
// restarts redraw the initial count, and from an eighth of the cap 3DGS did not regrow in the
// steps after the last one (docs/experiments/2026-11-28-mcmc-dry-control.md).
constexpr double kPixelsPerGaussian = 8;
constexpr uint32_t kMinOctaves = 2, kMaxOctaves = 8, kMaxSubdivision = 4;
// The floor holds small images (under 8,000 pixels): fixed-step runs need Gaussians to start
// from. On the tiny nerfrac-primary-sine (64 px, 1,500 steps; bench/results/sizing) 500 reached
// 19.3 dB and 1,000 reached 22.2.
constexpr uint32_t kMinGaussians = 1000, kMaxGaussians = 1600000;

// The config keys (train_options.cpp) the sizing may set.
const std::vector<std::string>& sizedConfigKeys();

struct SizeChoice {
  std::string key;     // the config key (and, with '-' for '_', near the flag: docs name both)
  double value = 0;
  std::string reason;  // one line: the rule and the numbers it used
};

struct ModelSizing {
  double pixelFootprint = 0;   // metres per training pixel on the water plane (median)
  uint64_t pixelsPerView = 0;  // the largest training image's pixel count
  size_t views = 0;
  uint32_t initialGaussians = 0, maxGaussians = 0, mlpOctaves = 0, gridCells = 0, subdivisionLevels = 0;
  std::vector<SizeChoice> choices;  // every derived value with its reason, in sizedConfigKeys' order
};

// The median linear size of a pixel on the plane z = waterHeight (the square root of the area
// its four corners' rays cut), over a 9 x 9 sample of each camera's pixels whose centre ray
// meets the plane inside the domain. 0 when no sampled ray does.
double medianPixelFootprint(const std::vector<Camera>& cameras, double waterHeight, const Rect& domain);

// Every rule above. Refuses (refrax::Error) cameras that see no part of the water's domain.
ModelSizing sizeModelFromData(const std::vector<Camera>& cameras, double waterHeight, const Rect& domain);

struct TrainConfig;
// Sets each of config.sizeFromData's keys from sizeModelFromData and records the choices and
// their reasons in config.modelSizing (empties sizeFromData). A cap left to the data stays at
// least a given initial count, an initial count left to it at most a given cap, and the coarse
// octaves follow the octaves while coarse-to-fine is off.
void applyModelSizing(TrainConfig& config, const std::vector<Camera>& trainCameras);

}  // namespace refrax
