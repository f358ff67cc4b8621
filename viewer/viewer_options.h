#pragma once
// refrax-view's options: one table row per flag (its help, and how its value is read and
// checked), with every default written once, in ViewerOptions' member initialisers, and shown
// in --help from there. parseViewerOptions checks everything that needs no window, so a bad
// flag is one clear error before a window opens.
#include <optional>
#include <string>
#include <vector>

#include "engine/app/cli.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/surface/water_surface.h"
#include "engine/view/fly_camera.h"

namespace refrax {

// The water's index of refraction for a PLY (a run has its own).
constexpr float kPlyIor = 1.33f;

struct ViewerOptions {
  std::string runDir;  // the positional run folder
  std::string ply;     // --ply FILE
  std::string device, trace;
  bool validation = false;
  std::string water;  // --water; empty: keep for a run, remove for a PLY
  bool exactWater = false;
  uint32_t bakeCells = 0;  // 0: a run's finest lattice (grid cells << levels), else 256
  std::optional<SurfaceDomain> domain;
  float waterHeight = 0;
  std::optional<float> ior;         // empty: the run's (1.33 for a PLY)
  std::optional<uint32_t> levels;   // empty: the run's
  bool tiledTrace = true;           // --gaussian-trace tiles (bvh: false)
  bool walkGrid = true;             // --water-trace grid (bvh: false)
  std::optional<long> k;            // empty: the larger of the default and the run's
  std::optional<uint32_t> shDegree; // empty: the checkpoint's
  float minTransmittance = TraceOptions{}.minTransmittance;
  bool heatmap = false;
  float heatScale = 64;
  std::string view;  // SPLIT:INDEX
  std::string mode;  // empty: gaussians with a scene, normals without
  std::string surface = "sine";
  std::string camera = "0,-2.2,1.6,0,0,0";
  bool cameraGiven = false;
  FlyCamera home;  // --camera and --fov, parsed
  int width = 800, height = 600;
  long frames = 0;
  std::string screenshot;
  bool benchmark = false;
  double minSeconds = 0;
  // The render's resolution scaled each frame to hold targetFps (the image stretched to the
  // window). Empty: on for a CPU device (lavapipe) in an interactive window, off otherwise and
  // with --frames (screenshots and benchmarks keep the window's size).
  std::optional<bool> autoResolution;
  double targetFps = 10;
};

// The flags with their help and shown defaults, for cli::Command.
std::vector<cli::Option> viewerOptionList();
// Reads and checks every flag; refrax::Error naming the flag otherwise.
ViewerOptions parseViewerOptions(const cli::Args& args);

}  // namespace refrax
