#pragma once
// Random synthetic scenes (`refrax synth random --seed N`, issue 45): a scene drawn from wide
// ranges of water, rig, image size and floor, so that a benchmark can measure the method on
// scenes nobody tuned its settings to. Drawing and building are apart: drawRandomScene gives a
// plain struct of every drawn number (cheap, no textures; what the tests check over hundreds
// of seeds), buildRandomScene turns it into a SynthPreset for generateSynthDataset (the same
// writer as the presets: water.json, water_gt_height.npy, the --dry copy), and
// randomSceneJson records it (scene.json, and water.json's "scene_parameters"), so a table can
// say what each scene was.
//
// Determinism: every draw comes from SynthRng (synth_rng.h: splitMix64, integer arithmetic)
// and is combined with + - * / and sqrt only, which IEEE 754 rounds exactly, so the same seed
// gives the same choices and drawn values, bit for bit, on every machine and standard library
// (no std:: distribution, no exp or pow in the drawing). What follows from the cameras'
// geometry (the domain, the square the test views see, and the object positions scaled to it)
// goes through sin / cos and agrees to their rounding, as the renders do.
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/synth/synth_presets.h"

namespace refrax::synth {

// The ranges the draw covers (issue 45's list). The tests check every drawn value against the
// issue's numbers written out, not against these, so a changed range here fails them.
struct RandomSceneRanges {
  static constexpr int kMinWaveComponents = 1, kMaxWaveComponents = 4;  // directional sines and radial ripples together
  // The surface's slope bound (water.json's slope_bound): the stability chart's slope sweep
  // (bench/stability.sh) spans 0.08 (--medium's nearly flat x0.25) to 0.75 (x2.4).
  static constexpr double kMinSlopeBound = 0.08, kMaxSlopeBound = 0.75;
  static constexpr double kMinSineWavelength = 0.15, kMaxSineWavelength = 0.8;      // m
  static constexpr double kMinRippleWavelength = 0.15, kMaxRippleWavelength = 0.5;  // m
  static constexpr double kMinRippleSigma = 0.2, kMaxRippleSigma = 0.6;             // m, the ripple's envelope
  static constexpr double kMinIor = 1.1, kMaxIor = 1.5;
  static constexpr double kMinCameraHeight = 0.8, kMaxCameraHeight = 1.6;  // m above the mean water
  static constexpr double kMinFovDeg = 40, kMaxFovDeg = 60;                // horizontal field of view
  static constexpr int kMinGridSide = 3, kMaxGridSide = 5;                 // top-down n x n grids
  static constexpr double kMinBaseline = 0.05, kMaxBaseline = 0.5;         // grid spacing / camera height
  static constexpr int kMinRingViews = 12, kMaxRingViews = 30;
  static constexpr double kMinRingTiltDeg = 15, kMaxRingTiltDeg = 50;  // from the vertical
  static constexpr int kMinWidth = 96, kMaxWidth = 400;                // px
  static constexpr double kMinFloorDepth = 0.3, kMaxFloorDepth = 0.9;  // m under the mean water
  static constexpr int kMinObjects = 1, kMaxObjects = 6;
  static constexpr double kMinRimFraction = 0.55, kMaxRimFraction = 0.9;  // rim opening / water half-width
  static constexpr int kTinyWidth = 64;  // --size tiny caps the width (CI)
};

enum class RandomRig { Grid, Ring };

// One term of the water: a directional sine (wave_surface.h's DirectionalWave) or a radial
// ripple (RadialRipple). slopeShare: its part of the surface's slope bound.
struct RandomWaveDraw {
  bool ripple = false;
  double slopeShare = 0;
  double amplitude = 0, wavelength = 0, phase = 0;
  double directionDeg = 0;           // sines: the direction of travel
  double cx = 0, cy = 0, sigma = 0;  // ripples: centre and envelope
};

enum class RandomObjectKind { Box, Sphere, Cylinder };

struct RandomObjectDraw {
  RandomObjectKind kind = RandomObjectKind::Box;
  double x = 0, y = 0;  // centre on the floor
  double size = 0;      // half extent (box), radius (sphere, cylinder)
  double top = 0;       // z of its highest point (below the lowest trough)
  double yawDeg = 0;
  int texture = 0, capTexture = 0;  // indices into randomSceneTextures()
  double tint[3] = {1, 1, 1};
};

struct RandomSceneParams {
  uint64_t seed = 0;
  int redraws = 0;  // draws discarded before this one (deterministic, see drawRandomScene)
  // Water: z = 0 + the terms over [-domainHalf, domainHalf]^2 (before a rim shrinks it).
  std::vector<RandomWaveDraw> waves;
  double slopeBound = 0;   // the drawn slope bound the terms share
  double heightBound = 0;  // the sum of their amplitudes
  double ior = 1.33;
  // Cameras.
  RandomRig rig = RandomRig::Grid;
  double cameraHeight = 1;  // above the mean water (a ring's cameras all at this height)
  double fovDeg = 50;
  int width = 0, height = 0;  // as drawn (--size tiny and --width resize afterwards)
  int gridSide = 3;
  double baseline = 0.2;  // grid: spacing between neighbouring cameras / cameraHeight
  int ringViews = 0;
  double ringTiltDeg = 0, ringAzimuthDeg = 0;
  // What the rig sees, from the cameras (derived, recorded): the water's domain covers every
  // view's footprint on the mean water (capped), and the test views see the whole square
  // +-testViewHalf around the centre (the region objects are placed in, and the surface scored on).
  double domainHalf = 1, testViewHalf = 0.4;
  // Floor: at -floorDepth, with a relief of two crossed sines (amplitude reliefAmplitude) that
  // fades to the flat floor at the domain's edge.
  double floorDepth = 0.5;
  double reliefAmplitude = 0, reliefWavelength = 0.5, reliefPhase[2] = {0, 0}, reliefDirectionDeg = 0;
  int floorTexture = 0;
  double floorRepeats = 4;  // texture repeats across the relief
  double floorTint[3] = {1, 1, 1};
  std::vector<RandomObjectDraw> objects;
  bool rim = false;
  double rimHalf = 0;  // the rim's opening (synth_rim.h): the water shrinks to +-rimHalf
};

// The textures (assets/textures stems) the floor and objects draw from.
const std::vector<std::string>& randomSceneTextures();
// How many of them (from the front) a floor may use: the ones that tile.
int randomFloorTextureCount();

// The scene of seed `seed`. A draw whose scene would not lie below the lowest trough (it
// cannot by the ranges, but checkSceneBelowWater is the rule) is replaced by the next one
// from the same seed (redraws counts them), so a seed always gives one and the same scene.
RandomSceneParams drawRandomScene(uint64_t seed);
// Empty when every triangle over the water will lie below the lowest trough with margin;
// otherwise why not (what drawRandomScene redraws on).
std::string randomSceneProblem(const RandomSceneParams& params);
// The dataset preset of a draw: cameras (train / test / air), water, floor, objects and rim.
// Tiny: the width capped at kTinyWidth, coarser tessellation and ground truth. Textures from
// textureDir. The preset's description and parametersJson say what was drawn.
SynthPreset buildRandomScene(const RandomSceneParams& params, SynthSize size, const std::string& textureDir);
// Every drawn number, named, for scene.json.
nlohmann::json randomSceneJson(const RandomSceneParams& params);
// One line for a table: rig, views, waves, slope, IOR, width, rim.
std::string randomSceneSummary(const RandomSceneParams& params);

}  // namespace refrax::synth
