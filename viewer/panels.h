#pragma once
// The viewer's Dear ImGui panel: stats (device, FPS, GPU ms per stage, Gaussian count, the
// loaded checkpoint) and controls (water kept / removed / swapped, IOR, subdivision levels,
// K, SH degree, colour or hit heat map, surface-only views, resolution scale with an automatic
// mode, camera: speed, orbit, snap to a dataset camera, reset).
#include <string>
#include <utility>
#include <vector>

#include "engine/view/fly_camera.h"
#include "engine/frame/frame_renderer.h"
#include "engine/frame/view_scene.h"

namespace refrax {

enum class ShowMode : int { Gaussians = 0, SurfaceNormals = 1, SurfaceWireframe = 2 };

struct ViewerState {
  RenderSettings render;
  ShowMode show = ShowMode::Gaussians;
  int K = 16;
  float resolutionScale = 1.0f;
  bool autoResolution = false;
  float targetFrameMs = 100.0f;
  int snappedCamera = -1;  // index into scene.cameras while the view is a dataset camera's
  bool followCheckpoints = true;
  bool resetView = false, screenshot = false;
};

struct FrameStats {
  double fps = 0, frameMs = 0;
  uint32_t width = 0, height = 0;
  std::vector<std::pair<std::string, double>> stageMs;
};

void drawPanel(const std::string& deviceName, ViewScene& scene, ViewerState& state, FlyCamera& camera, const FrameStats& stats);
// With nothing loaded: the built-in surface by itself, its shape and how it is shown.
void drawSurfacePanel(const std::string& deviceName, BuiltinSurface& surface, ViewerState& state, const FrameStats& stats);

// Auto resolution: scales the rendered pixel count towards the target frame time.
float nextResolutionScale(float scale, double frameMs, float targetMs);

}  // namespace refrax
