// refrax render RUN -o DIR: renders a trained run's views (a dataset split or one look-at
// camera) with the learned water kept, removed, or swapped for a built-in surface or for any
// triangle mesh from a glTF file, through the viewer's frame (engine/frame/frame_renderer.h):
// the water baked once per run, a frame one submission; --exact-water traces the trainer's
// subdivided surface instead, as training and `refrax eval` do.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "engine/base/error.h"
#include "engine/surface/gltf_surface.h"
#include "engine/io/image_io.h"
#include "engine/io/staged_folder.h"
#include "engine/surface/mesh_surface.h"
#include "engine/model/render_model.h"
#include "engine/model/open_model.h"
#include "engine/frame/frame_renderer.h"
#include "engine/frame/view_scene.h"
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

// Every view again, `benchmark` times, after the renders built the pipelines and baked the
// water: the frame time of a headless render (the frame and its pixels' copy to the host, the
// host's image) on this device, where it goes, its submissions, and the Gaussian trace alone.
void printRenderBenchmark(Context& ctx, FrameRenderer& renderer, ViewScene& scene, const RenderSettings& rs,
                          const std::vector<std::pair<std::string, Camera>>& cameras, long benchmark, const std::string& water,
                          const std::atomic<bool>& interrupted) {
  std::vector<std::pair<std::string, double>> stages;
  auto t0 = std::chrono::steady_clock::now();
  for (long k = 0; k < benchmark; k++) {
    if (interrupted.load()) fail("render: interrupted during --benchmark (the images in the output folder are complete)");
    for (const auto& [name, cam] : cameras) renderFrameImage(renderer, scene, cam, rs, &stages);
  }
  const double frames = double(benchmark * long(cameras.size()));
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / frames;
  const char* path = renderer.path == FrameRenderer::Path::Straight ? "none" : renderer.path == FrameRenderer::Path::Mesh ? "baked" : "exact";
  std::printf("benchmark: %s, %dx%d, water %s (%s), %zu views x %ld: %.2f ms per frame (%.1f FPS), %s trace, Gaussian trace %s\n",
              ctx.caps.name.c_str(), cameras.front().second.width, cameras.front().second.height, water.c_str(), path, cameras.size(), benchmark,
              ms, 1000.0 / ms, traceBackendName(ctx.trace), rs.tiledTrace ? "tiles" : "bvh");
  std::string breakdown;
  for (const auto& [stage, total] : stages) {
    char part[96];
    std::snprintf(part, sizeof part, "%s%s %.2f", breakdown.empty() ? "" : ", ", stage.c_str(), total / frames);
    breakdown += part;
  }
  // One frame more, its submissions counted (a profiler's own readbacks kept out of the times above).
  GpuProfiler counter;
  attachProfiler(ctx, counter);
  renderFrameImage(renderer, scene, cameras.front().second, rs);
  detachProfiler(ctx);
  std::printf("benchmark: per frame (ms): %s (the device's timestamps, the host's image); %llu submission%s a frame\n", breakdown.c_str(),
              static_cast<unsigned long long>(counter.submits), counter.submits == 1 ? "" : "s");
  // The same rays through the frame's Gaussian stage alone: how much of a frame is not the trace.
  double alone = 0;
  for (const auto& [name, cam] : cameras) alone += frameTraceMs(renderer, scene, cam, rs, int(benchmark));
  alone /= double(cameras.size());
  std::printf("benchmark: the Gaussian trace alone %.2f ms per frame; the frame %.2fx it\n", alone, ms / alone);
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
  const std::string trace = args.get("gaussian-trace", "tiles");
  if (trace != "tiles" && trace != "bvh") fail("--gaussian-trace must be tiles or bvh (got '" + trace + "')");
  TrainConfig config = readRunConfig(run);
  {
    // The spec checked (and a mesh read) before anything is opened or written.
    RenderSettings checked;
    try {
      applyWaterSpec(water, float(config.waterHeight), checked);
    } catch (const Error& e) {
      fail(std::string("--water: ") + e.what() + " (keep, remove, a built-in surface or a .gltf/.glb mesh)");
    }
    if (!checked.swapMesh.empty()) {
      SurfaceMesh mesh = readSurfaceGltf(water);
      meshUnitNormals(mesh);
    }
  }
  std::vector<std::pair<std::string, Camera>> cameras;
  std::string split = args.get("split", "test");
  StagedFolder folder(out, "-o");  // the images appear in `out` all at once, or not at all
  auto ctx = cli::openContext(args);
  // K changes only the speed, not the image: at least the viewer's default (as refrax-view opens a run).
  auto scene = openRunScene(*ctx, run, std::max(kDefaultKBuffer, config.kBuffer));
  if (args.has("camera")) {
    auto v = parseList(args.get("camera"), 6, "camera");
    long w = args.getInt("width", 256), h = args.getInt("height", 256);
    if (w <= 0 || h <= 0 || w > 8192 || h > 8192) fail("--width/--height must be between 1 and 8192");
    double fov = args.getDouble("fov", 45.0);
    cameras.push_back({"camera.png", lookAtCamera({v[0], v[1], v[2]}, {v[3], v[4], v[5]}, int(w), int(h), fov * M_PI / 180)});
  } else {
    const auto& views = scene->dataset.split(split);
    for (size_t i = 0; i < views.size(); i++) {
      char name[48];
      std::snprintf(name, sizeof name, "%s_%03zu.png", split.c_str(), i);
      Camera c = views[i].camera;
      if (args.has("undistort")) c.lens = Lens{};  // the same focal length and principal point, straight lines straight
      cameras.push_back({name, c});
    }
  }
  // The run's settings (as the viewer opens it), then the water and trace asked for.
  RenderSettings rs = sceneRenderSettings(*scene);
  applyWaterSpec(water, float(config.waterHeight), rs);
  rs.exactWater = args.has("exact-water");
  rs.tiledTrace = trace == "tiles";
  FrameRenderer renderer = createFrameRenderer(*ctx);
  for (const auto& [name, cam] : cameras) {
    if (interrupted.load()) fail("render: interrupted; nothing was written to " + out);
    writePng((fs::path(folder.path) / name).string(), renderFrameImage(renderer, *scene, cam, rs));
  }
  folder.commit();
  for (const auto& [name, cam] : cameras) std::printf("wrote %s\n", (fs::path(out) / name).string().c_str());
  if (benchmark > 0) printRenderBenchmark(*ctx, renderer, *scene, rs, cameras, benchmark, water, interrupted);
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
                                 "keep, remove, flat[:height], sine[:height:amplitude:wavelength:direction], triangle[:...], or PATH.gltf / "
                                 "PATH.glb: any triangle mesh (glTF axes, +Y up) refracting the camera rays in the water's place",
                                 "keep"},
                                {"exact-water", "",
                                 "trace the trainer's subdivided surface (as training and refrax eval do) instead of the water baked once on "
                                 "its finest lattice (the viewer's frame; at most a few levels of 8 bits apart)",
                                 ""},
                                {"gaussian-trace", "KIND", "tiles (candidate lists per 8x8 tile, as the viewer) or bvh (a traversal per ray): the same image", "tiles"},
                                {"benchmark", "N", "after writing the images, render every view N more times and print the mean frame time", "0"}};
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"render", "render a trained run with the water kept, removed or swapped", "refrax render RUN -o DIR [options]",
                renderOptions(), runRender});

}  // namespace
}  // namespace refrax
