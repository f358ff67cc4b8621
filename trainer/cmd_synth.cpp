// refrax synth: generates a synthetic dataset with ground-truth water (NeRFrac-like and
// RefracGS-like presets, or `random`: a scene drawn from its seed, engine/synth/synth_random.h)
// on the CPU, with a renderer that shares no code with the trainer.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>

#include "engine/base/error.h"
#include "engine/synth/synth_dataset.h"
#include "engine/synth/synth_presets.h"
#include "engine/synth/synth_random.h"
#include "engine/synth/synth_rim.h"
#include "engine/app/cli.h"

namespace fs = std::filesystem;

namespace refrax {
namespace {

std::string presetList() {
  std::string s;
  for (const auto& n : synth::synthPresetNames()) s += (s.empty() ? "" : ", ") + n;
  return s + ", random";
}

bool hasTextures(const fs::path& dir) { return fs::exists(dir / "astronaut.png"); }

// --textures, then REFRAX_TEXTURES, then assets/textures next to or above the executable,
// then the source tree this binary was built from.
std::string findTextureDir(const cli::Args& args) {
  if (args.has("textures")) return args.get("textures");
  if (const char* env = std::getenv("REFRAX_TEXTURES")) return env;
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    for (fs::path d = exe.parent_path(); !d.empty() && d != d.parent_path(); d = d.parent_path())
      if (hasTextures(d / "assets" / "textures")) return (d / "assets" / "textures").string();
  fs::path source = fs::path(__FILE__).parent_path().parent_path() / "assets" / "textures";
  if (hasTextures(source)) return source.string();
  fail("synth: cannot find assets/textures; pass --textures DIR or set REFRAX_TEXTURES");
}

int runSynth(const cli::Args& args) {
  // The shared parser maps `-o DIR` to --output DIR.
  std::vector<std::string> names;
  std::string out = args.get("output");
  for (const auto& p : args.positional) {
    if (p.size() > 1 && p[0] == '-') fail("synth: unknown option " + p + " (see --help)");
    names.push_back(p);
  }
  if (names.size() != 1) fail("synth: expected one preset name (" + presetList() + ")");
  const std::string name = names[0];
  const bool drawn = name == "random";  // a scene drawn from --seed, not a preset
  if (!drawn && !synth::isSynthPreset(name)) fail("synth: unknown preset '" + name + "' (known: " + presetList() + ")");
  if (out.empty()) fail("synth: -o DIR is required");
  std::string size = args.get("size", "full");
  if (size != "tiny" && size != "full") fail("synth: --size must be tiny or full, got '" + size + "'");
  long seed = args.getInt("seed", 1);
  if (seed < 0) fail("synth: --seed must be a non-negative integer");
  synth::checkSynthOutputDir(out);

  auto start = std::chrono::steady_clock::now();
  const std::string textureDir = findTextureDir(args);
  const synth::SynthSize synthSize = size == "tiny" ? synth::SynthSize::Tiny : synth::SynthSize::Full;
  // A random scene draws its own rim (or none): --rim would change what the seed stands for.
  if (drawn && args.has("rim")) fail("synth: random scenes draw their own rim (scene.json's \"rim\"); --rim is for the presets");
  synth::SynthPreset preset = drawn ? synth::buildRandomScene(synth::drawRandomScene(uint64_t(seed)), synthSize, textureDir)
                                    : synth::makeSynthPreset(name, synthSize, uint64_t(seed), textureDir);
  if (drawn) std::printf("synth random: %s\n", preset.description.c_str());
  synth::SynthVariation variation;
  if (args.has("width")) variation.width = int(args.getIntIn("width", 0, 8, 8192));  // 0 is the size's own, never asked for
  variation.amplitudeScale = args.getDouble("wave-amplitude", 1.0);
  variation.wavelengthScale = args.getDouble("wavelength", 1.0);
  variation.tiltDeg = args.getDouble("tilt", 0.0);
  if (args.has("rig-spacing")) variation.rigSpacing = args.getDouble("rig-spacing", 0.0);
  if (args.has("ior")) variation.ior = args.getDouble("ior", 0.0);
  variation.cameraModel = args.get("camera-model", "pinhole");
  // A random scene sizes its water's domain to its pinhole views' footprint.
  if (drawn && variation.cameraModel != "pinhole") fail("synth: --camera-model is for the presets; random scenes use pinhole cameras");
  synth::applySynthVariation(preset, variation);
  if (args.has("rim")) synth::addSynthRim(preset, args.getDouble("rim", 0.0), textureDir);
  synth::SynthWriteOptions o;
  o.seed = uint64_t(seed);
  o.sizeName = size;
  o.progress = size == "full";
  o.dry = args.has("dry");
  // Stop between views on Ctrl-C so the temporary folder is removed rather than left behind.
  o.cancel = &cli::catchInterrupts();
  const std::string between = preset.between.empty() ? "" : ", " + std::to_string(preset.between.size()) + " between";
  std::printf("synth %s (%s, seed %ld): %zu train, %zu test%s, %zu air views, %d x %d px, %zu triangles -> %s\n", name.c_str(), size.c_str(),
              seed, preset.train.size(), preset.test.size(), between.c_str(), preset.air.size(), preset.train.front().width,
              preset.train.front().height, preset.scene.bvh.triangles.size(), out.c_str());
  std::fflush(stdout);
  synth::generateSynthDataset(preset, out, o);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("synth %s: done in %.1f s\n", name.c_str(), seconds);
  return 0;
}

REFRAX_COMMAND({"synth", "generate a synthetic refraction dataset with ground-truth water (CPU)",
                "refrax synth <preset> -o DIR [--size tiny|full] [--seed N] [--camera-model pinhole|opencv|fisheye] [--rim HALF] [--dry] [--textures DIR]\n"
                "       presets: nerfrac-primary-sine nerfrac-second-sine nerfrac-hybrid desk kitchen toys desk-topdown kitchen-topdown toys-topdown\n"
                "       random: a scene drawn from --seed N (1-4 sines and ripples, slope bound 0.08-0.75, IOR 1.1-1.5, a 3x3-5x5\n"
                "               top-down grid or a ring of 12-30 views at 15-50 deg, 96-400 px, floor relief, 1-6 objects, a dry rim\n"
                "               or none); the same seed gives the same scene, recorded in scene.json; --size tiny caps it at 64 px",
                {{"output", "DIR", "(or -o DIR) output folder; must not exist or be empty; appears only when complete", ""},
                 {"size", "tiny|full", "tiny: small images and simple geometry for CI", "full"},
                 {"seed", "N", "seed for the wave phases / spectrum and the antialiasing jitter; for random, the whole scene", "1"},
                 {"width", "N", "image width in pixels (height and field of view follow); default: the size's", ""},
                 {"wave-amplitude", "X", "every wave's amplitude times X (wave-slope sweeps)", "1"},
                 {"wavelength", "X", "every wavelength times X", "1"},
                 {"rig-spacing", "M", "NeRFrac-like presets: the 3 x 3 rig's cameras M (0..0.6) apart instead of 0.2, same height and view axes (baseline sweeps)", "0.2"},
                 {"tilt", "DEG", "NeRFrac-like presets: the 3 x 3 rig turned rigidly DEG (0..60) from the vertical about the pool-floor centre, which the centre camera keeps looking at (camera-tilt sweeps)", "0"},
                 {"ior", "X", "index of refraction of the water, 1 < X <= 2 (recorded in water.json)", "the preset's (1.1 NeRFrac-like, 1.33 RefracGS-like)"},
                 {"camera-model", "pinhole|opencv|fisheye", "every camera through a lens, the pixel count kept: opencv = OpenCV's barrel distortion k1 = -0.25 at the same focal length, fisheye = an equidistant fisheye spanning 180 deg across the diagonal; written as transforms.json's camera_model and k1..k4, p1, p2 (nerfstudio's fields), traced as such by train, render and eval; no LLFF layout", "pinhole"},
                 {"rim", "HALF", "a dry textured rim (a pool's edge) around the water, visible from every view so that structure from motion (COLMAP) can pose them: the water shrinks to +-HALF m around the domain's centre, the rim reaches out to +-2 HALF m, its top just above the highest crest (water.json's domain and ground truth follow)", ""},
                 {"dry", "", "the dry control: the same dataset (cameras, scene, water.json) with the training and test views rendered without the water; train it with --no-refraction for the Gaussians' own ceiling", ""},
                 {"textures", "DIR", "texture folder (also REFRAX_TEXTURES); default: the repository's assets/textures", ""}},
                runSynth});

}  // namespace
}  // namespace refrax
