// refrax render RUN -o DIR: renders a trained run's views (a dataset split or one look-at
// camera) with the learned water kept, removed, or swapped for a built-in surface or for any
// triangle mesh from a glTF file.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "engine/surface/builtin_surface_spec.h"
#include "engine/base/error.h"
#include "engine/surface/gltf_surface.h"
#include "engine/io/image_io.h"
#include "engine/io/staged_folder.h"
#include "engine/surface/mesh_surface.h"
#include "engine/model/render_model.h"
#include "engine/model/open_model.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

std::vector<double> parseList(const std::string& text, size_t count, const char* option) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    double d = std::strtod(item.c_str(), &end);
    if (item.empty() || *end || !std::isfinite(d)) fail(std::string("--") + option + " expects " + std::to_string(count) + " comma-separated numbers");
    v.push_back(d);
  }
  if (v.size() != count) fail(std::string("--") + option + " expects " + std::to_string(count) + " comma-separated numbers");
  return v;
}

// flat[:HEIGHT] or sine[:HEIGHT:AMPLITUDE:WAVELENGTH:DIRECTION_DEG] (engine/surface/builtin_surface_spec.h)
// as the closed-form surface the tracer lifts.
AnalyticWaves builtinWaves(const std::string& spec, double defaultHeight) {
  std::string kind = spec.substr(0, spec.find(':'));
  if (kind != "flat" && kind != "sine")
    fail("--water must be keep, remove, flat[:height], sine[:height:amplitude:wavelength:direction] or a .gltf/.glb mesh (got '" +
         spec + "')");
  return builtinSurfaceWaves(parseBuiltinSurface(spec, float(defaultHeight)));
}

// `--water` names a glTF mesh when it ends in .gltf or .glb (any case).
bool isGltfPath(const std::string& spec) {
  std::string lower = spec;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  auto endsWith = [&](const std::string& ext) { return lower.size() > ext.size() && lower.compare(lower.size() - ext.size(), ext.size(), ext) == 0; };
  return endsWith(".gltf") || endsWith(".glb");
}

int runRender(const cli::Args& args) {
  namespace fs = std::filesystem;
  if (args.positional.size() != 1) fail("refrax render needs one run folder");
  if (!args.has("output")) fail("refrax render needs -o DIR");
  std::string run = args.positional[0], out = args.get("output");
  // Ctrl-C or a kill from here on stops the render between views (the check in the loop), so
  // the staged folder is removed rather than left behind.
  const std::atomic<bool>& interrupted = cli::catchInterrupts();
  // As train -o: a render never mixes its images with a folder's older files.
  cli::checkNewOrEmptyFolder(out, "-o", "render into a new folder, or remove it first");
  std::string water = args.get("water", "keep");
  const long benchmark = args.getIntIn("benchmark", 0, 0, 100000);
  TrainConfig config = readRunConfig(run);
  WaterView mode = water == "keep" ? WaterView::Keep : water == "remove" ? WaterView::Remove : WaterView::Swap;
  std::optional<AnalyticWaves> waves;
  std::optional<SurfaceMesh> mesh;  // read (and checked) before anything is opened or written
  if (mode == WaterView::Swap && isGltfPath(water)) {
    mesh = readSurfaceGltf(water);
    meshUnitNormals(*mesh);  // validates
  } else if (mode == WaterView::Swap) {
    waves = builtinWaves(water, config.waterHeight);
  }
  std::vector<std::pair<std::string, Camera>> cameras;
  bool single = args.has("camera");
  std::string split = args.get("split", "test");
  StagedFolder folder(out, "-o");  // the images appear in `out` all at once, or not at all
  auto ctx = cli::openContext(args);
  const Dataset dataset = loadRunDataset(config);
  auto model = openModel(*ctx, run, dataset);
  if (single) {
    auto v = parseList(args.get("camera"), 6, "camera");
    long w = args.getInt("width", 256), h = args.getInt("height", 256);
    if (w <= 0 || h <= 0 || w > 8192 || h > 8192) fail("--width/--height must be between 1 and 8192");
    double fov = args.getDouble("fov", 45.0);
    cameras.push_back({"camera.png", lookAtCamera({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, int(w), int(h), fov * M_PI / 180)});
  } else {
    const auto& views = dataset.split(split);
    for (size_t i = 0; i < views.size(); i++) {
      char name[48];
      std::snprintf(name, sizeof name, "%s_%03zu.png", split.c_str(), i);
      Camera c = views[i].camera;
      if (args.has("undistort")) c.lens = Lens{};  // the same focal length and principal point, straight lines straight
      cameras.push_back({name, c});
    }
  }
  std::optional<AnalyticHeightField> swap;
  if (waves) swap.emplace(createAnalyticHeightField(*ctx, *waves));
  std::optional<MeshSurface> swapMesh;
  if (mesh) swapMesh.emplace(createMeshSurface(*ctx, *mesh));
  const SwapSurface swapSurface{swap ? &*swap : nullptr, swapMesh ? &*swapMesh : nullptr};
  for (const auto& [name, cam] : cameras) {
    if (interrupted.load()) fail("render: interrupted; nothing was written to " + out);
    RenderedView r = renderView(*model, cam, mode, swapSurface, RenderOptions{false, nullptr});  // the image only
    writePng((fs::path(folder.path) / name).string(), r.image);
  }
  folder.commit();
  for (const auto& [name, cam] : cameras) std::printf("wrote %s\n", (fs::path(out) / name).string().c_str());
  if (benchmark > 0) {
    // Every view again, `benchmark` times, after the renders above built the pipelines: the
    // frame time of a headless render (camera rays, water, Gaussians, the results' copy to the
    // host and the host's image) on this device.
    std::vector<std::pair<std::string, double>> stages;
    auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < benchmark; k++) {
      if (interrupted.load()) fail("render: interrupted during --benchmark (the images in " + out + " are complete)");
      for (const auto& [name, cam] : cameras) renderView(*model, cam, mode, swapSurface, RenderOptions{false, &stages});
    }
    const double frames = double(benchmark * cameras.size());
    double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / frames;
    std::printf("benchmark: %s, %dx%d, water %s, %zu views x %ld: %.2f ms per frame (%.1f FPS), %s trace\n", ctx->caps.name.c_str(),
                cameras.front().second.width, cameras.front().second.height, water.c_str(), cameras.size(), benchmark, ms, 1000.0 / ms,
                traceBackendName(ctx->trace));
    std::string breakdown;
    for (const auto& [stage, total] : stages) {
      char part[96];
      std::snprintf(part, sizeof part, "%s%s %.2f", breakdown.empty() ? "" : ", ", stage.c_str(), total / frames);
      breakdown += part;
    }
    // One frame more, its submissions counted (a profiler's own readbacks kept out of the times above).
    GpuProfiler counter;
    attachProfiler(*ctx, counter);
    renderView(*model, cameras.front().second, mode, swapSurface, RenderOptions{false, nullptr});
    detachProfiler(*ctx);
    std::printf("benchmark: per frame (ms): %s (the device's timestamps, the host's image); %llu submission%s a frame\n", breakdown.c_str(),
                static_cast<unsigned long long>(counter.submits), counter.submits == 1 ? "" : "s");
    if (mode != WaterView::Swap) {
      // The same rays through the Gaussians alone: how much of a frame is not the trace.
      double trace = 0;
      for (const auto& [name, cam] : cameras) trace += gaussianTraceMs(*model, cam, mode, int(benchmark));
      trace /= double(cameras.size());
      std::printf("benchmark: the Gaussian trace alone %.2f ms per frame; the frame %.2fx it\n", trace, ms / trace);
    }
  }
  return 0;
}

std::vector<cli::Option> renderOptions() {
  std::vector<cli::Option> o = {{"output", "DIR", "folder for the PNGs (-o); must not exist or be empty; appears only once every image is written", ""},
                                {"split", "NAME", "dataset split to render (test, train, air, ...)", "test"},
                                {"undistort", "", "draw the split's views through a pinhole of the same focal length and principal point instead of their lens (a distorted or fisheye camera's view with straight lines straight)", ""},
                                {"camera", "x,y,z,tx,ty,tz", "one look-at camera instead of a split (world up +z)", ""},
                                {"width", "PIXELS", "image width with --camera", "256"},
                                {"height", "PIXELS", "image height with --camera", "256"},
                                {"fov", "DEG", "vertical field of view with --camera", "45"},
                                {"water", "MODE",
                                 "keep, remove, flat[:height], sine[:height:amplitude:wavelength:direction], or PATH.gltf / PATH.glb: "
                                 "any triangle mesh (glTF axes, +Y up) refracting the camera rays in the water's place",
                                 "keep"},
                                {"benchmark", "N", "after writing the images, render every view N more times and print the mean frame time", "0"}};
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"render", "render a trained run with the water kept, removed or swapped", "refrax render RUN -o DIR [options]",
                renderOptions(), runRender});

}  // namespace
}  // namespace refrax
