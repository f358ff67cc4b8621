#pragma once
// The synthetic dataset presets: analogs of NeRFrac's synthetic scenes (3 x 3 downward rig,
// IOR 1.1, sine-based water) and of RefracGS's scenes (1.5 m x 1.5 m x 1 m, IOR 1.33, a
// rippled surface drawn from a wave spectrum, surround rings plus a downward variant).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/synth/scene_builder.h"
#include "engine/synth/synth_camera.h"
#include "engine/synth/wave_surface.h"

namespace refrax::synth {

enum class SynthSize { Tiny, Full };

struct SynthPreset {
  std::string name;
  std::string description;
  std::string surfaceDescription;  // how the water was made, for water.json
  double ior = 1.33;
  WaveSurface water;
  SynthScene scene;
  std::vector<SynthCamera> train, test, air;  // air: water-removal views (rendered without water)
  // More test views, between the training cameras of a 3 x 3 rig (the diagonal midpoints), so
  // a table's row is more than the one held-out centre view; evaluated apart from the test
  // split, whose centre view is the NeRFrac protocol's (empty for the ring presets, which hold
  // out six test views already).
  std::vector<SynthCamera> between;
  bool writeLlff = false;                     // NeRFrac's poses_bounds.npy + images/ layout
  int samplesPerAxis = 2;
  int heightMapSize = 512;  // samples per side of water_gt_height.npy
  int meshGridSize = 257;   // vertices per side of water_gt.gltf
  // The NeRFrac-like 3 x 3 downward rig can be tilted (--tilt) about the horizontal x axis
  // through rigPivot, the centre of the pool floor, which its centre camera looks at.
  bool tiltableRig = false;
  glm::dvec3 rigPivot{0.0};
  double rigSpacing = 0;  // that rig's camera spacing (m); --rig-spacing replaces it
  // A drawn scene's parameters as JSON text (synth_random.h; empty for the presets): written
  // as scene.json and into water.json's "scene_parameters", so a table can say what it was.
  std::string parametersJson;
};

std::vector<std::string> synthPresetNames();
bool isSynthPreset(const std::string& name);
// Builds the named preset; textures are read from textureDir (assets/textures).
// refrax::Error on an unknown name or a missing texture.
SynthPreset makeSynthPreset(const std::string& name, SynthSize size, uint64_t seed, const std::string& textureDir);
// A preset varied for sweeps and for regimes the defaults do not reach (refrax synth --width,
// --wave-amplitude, --wavelength, --rig-spacing, --tilt, --ior): every camera resized to
// `width` pixels wide (0: kept; the field of view and aspect kept), every wave's amplitude
// times amplitudeScale and wavelength times wavelengthScale (directions and phases kept), the
// tiltable rig's cameras moved rigSpacing apart when given (heights and view axes kept), then
// rotated rigidly by tiltDeg from the vertical about the pool-floor centre, the IOR replaced
// by `ior` when given. refrax::Error for a scale <= 0 or non-finite, a width outside 8..8192,
// waves that would reach the scene, a spacing outside (0, 0.6] m, a tilt outside 0..60, a
// spacing or a tilt on a preset without the rig, a camera that the tilt would put under the
// wave crests, or an IOR outside (1, 2]. cameraModel then gives every camera a lens, the
// pixel count kept: "opencv" OpenCV's barrel distortion k1 = -0.25 at the same focal length;
// "fisheye" an equidistant fisheye whose diagonal spans 180 degrees (the principal point at the
// centre); NeRFrac's LLFF layout, which has no lens, is then not written.
struct SynthVariation {
  int width = 0;
  double amplitudeScale = 1, wavelengthScale = 1;
  double tiltDeg = 0;
  std::optional<double> rigSpacing;
  std::optional<double> ior;
  std::string cameraModel = "pinhole";  // or "opencv" (k1 = -0.25) or "fisheye" (180 degrees across the diagonal)
};
void applySynthVariation(SynthPreset& preset, const SynthVariation& variation);
// refrax::Error unless every triangle over the water's domain (its x-y extent overlapping the
// domain's interior) lies below the lowest trough; outside the domain (a rim) anything goes.
void checkSceneBelowWater(const SynthPreset& preset);
// Textures by file stem from textureDir, as RGB.
SynthTexture loadSynthTexture(const std::string& textureDir, const std::string& stem);
// Materials for a scene: one per get(), each texture file loaded once (by stem, from dir).
struct MaterialSet {
  SynthScene& scene;
  std::string dir;
  std::map<std::string, int> textureIndex;
  int get(const std::string& stem, glm::dvec2 uvScale = {1, 1}, glm::dvec3 tint = {1, 1, 1});
};

}  // namespace refrax::synth
