#pragma once
// Writes a synthetic preset as a dataset folder: Blender transforms (train / test / air),
// PNG renders with and without water, masks, water.json, the ground-truth surface as glTF
// and as a height map, for NeRFrac-like presets the LLFF layout (poses_bounds.npy), and for a
// drawn scene (synth_random.h) its parameters as scene.json.
#include <atomic>
#include <cstdint>
#include <string>

#include "engine/synth/synth_presets.h"

namespace refrax::synth {

struct SynthWriteOptions {
  uint64_t seed = 1;
  std::string sizeName = "full";
  bool progress = false;  // one line per view with an ETA
  // Checked between views; when it becomes true the generation stops with refrax::Error and
  // generateSynthDataset removes its temporary folder (the CLI sets it on SIGINT / SIGTERM).
  const std::atomic<bool>* cancel = nullptr;
  int threads = 2;
  // The dry control (refrax synth --dry): the training and test views rendered with the water
  // removed (same cameras, scene and jitter), so that straight-ray training on them shows what
  // the Gaussians reach at a budget without the water. water.json, the ground truth and the
  // air views are as without it; no masks (they mark where the water is seen).
  bool dry = false;
};

// Writes every file into `dir`, which must exist (and should be empty).
void writeSynthDataset(const SynthPreset& preset, const std::string& dir, const SynthWriteOptions& options);

// Renders into a temporary sibling folder and renames it to `outDir` only when everything is
// written, so `outDir` is never left half-written. Fails if outDir exists and is not empty.
void generateSynthDataset(const SynthPreset& preset, const std::string& outDir, const SynthWriteOptions& options);

// Fails (refrax::Error) unless outDir can be created: it must not exist as a file or a
// non-empty folder, and its parent must be (or become) a writable folder.
void checkSynthOutputDir(const std::string& outDir);

// The LLFF pose row of a camera: [R|t|hwf] in LLFF's [down, right, back] columns, 15 values
// row-major, then near and far.
std::vector<double> llffPoseRow(const SynthCamera& cam, double nearDepth, double farDepth);

}  // namespace refrax::synth
