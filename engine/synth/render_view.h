#pragma once
// Renders one view of a synthetic scene seen through the analytic water surface (or with the
// water removed), with jittered stratified antialiasing, on a fixed number of std::threads.
// Each pixel's samples depend only on (seed, view key, pixel), so the result is identical
// for any thread count.
#include <cstdint>
#include <vector>

#include "engine/synth/scene_builder.h"
#include "engine/synth/synth_camera.h"
#include "engine/synth/wave_surface.h"

namespace refrax::synth {

struct RenderSettings {
  int samplesPerAxis = 2;  // samplesPerAxis^2 jittered samples per pixel
  uint64_t seed = 1;
  int threads = 2;
};

struct RenderedView {
  int width = 0, height = 0;
  std::vector<float> rgb;   // row-major, 3 per pixel, [0, 1]
  std::vector<float> mask;  // 1 where every sample met the water surface inside its domain
  double nearDepth = 0, farDepth = 0;  // range of camera-space depths of the scene points seen
  size_t samplesMissingWater = 0;
};

// Colour and water hit of one camera ray. water == nullptr renders the scene in air.
struct RayResult {
  glm::dvec3 colour;
  bool metWater;
  bool hitScene;
  glm::dvec3 scenePoint;
};
RayResult shadeCameraRay(const SynthScene& scene, const WaveSurface* water, double ior, const glm::dvec3& origin, const glm::dvec3& dir);

RenderedView renderView(const SynthScene& scene, const WaveSurface* water, double ior, const SynthCamera& cam, const RenderSettings& settings,
                        uint64_t viewKey);

}  // namespace refrax::synth
