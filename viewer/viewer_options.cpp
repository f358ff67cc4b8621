#include "viewer/viewer_options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

#include "engine/base/error.h"

namespace refrax {
namespace {

struct ViewerOptionRow {
  cli::Option option;
  std::function<void(ViewerOptions&, const cli::Args&)> read;  // called when the flag is given
};

std::string shown(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::optional<SurfaceDomain> parseDomain(const std::string& text) {
  SurfaceDomain d;
  char tail;
  if (std::sscanf(text.c_str(), "%f,%f,%f,%f%c", &d.x0, &d.y0, &d.x1, &d.y1, &tail) != 4) fail("--domain must be x0,y0,x1,y1");
  return d;
}

// Every flag but the device's (cli::deviceOptions), in --help's order (a declarative table).
std::vector<ViewerOptionRow> viewerOptionTable() {
  const ViewerOptions d;
  using Args = cli::Args;
  using O = ViewerOptions;
  std::vector<ViewerOptionRow> t;
  auto row = [&t](std::string name, std::string metavar, std::string help, std::string fallback,
                  std::function<void(O&, const Args&)> read) {
    t.push_back({{std::move(name), std::move(metavar), std::move(help), std::move(fallback)}, std::move(read)});
  };
  row("ply", "FILE", "view a 3DGS PLY instead of a run folder", "", [](O& o, const Args& a) { o.ply = a.get("ply"); });
  row("water", "MODE", "keep, remove, flat[:height], sine|triangle[:height:amplitude:wavelength:direction] or a .gltf/.glb mesh",
      "keep (run), remove (PLY)", [](O& o, const Args& a) { o.water = a.get("water"); });
  row("exact-water", "", "trace the water's subdivided proxy surface as training and refrax render do (slower)", "",
      [](O& o, const Args&) { o.exactWater = true; });
  row("bake-cells", "N", "cells per side of the baked water mesh (learned or built-in surface)",
      "a run's grid cells << subdivision levels (its finest lattice), else 256", [](O& o, const Args& a) {
        long cells = a.getInt("bake-cells", 256);
        if (cells < 1 || cells > 4096) fail("--bake-cells must be between 1 and 4096");
        o.bakeCells = uint32_t(cells);
      });
  row("domain", "x0,y0,x1,y1", "with --ply: the water's extent", "the Gaussians' xy bounds + 10%",
      [](O& o, const Args& a) { o.domain = parseDomain(a.get("domain")); });
  row("water-height", "Z", "with --ply: the water level of swapped-in surfaces", shown(d.waterHeight),
      [](O& o, const Args& a) { o.waterHeight = float(a.getDouble("water-height", 0)); });
  row("ior", "N", "index of refraction of the water", "the run's (" + shown(kPlyIor) + " for a PLY)",
      [](O& o, const Args& a) { o.ior = float(a.getDouble("ior", kPlyIor)); });
  row("levels", "K", "with --exact-water: subdivision levels of the water surface (0-8)", "the run's",
      [](O& o, const Args& a) { o.levels = uint32_t(std::clamp(a.getInt("levels", 2), 0L, 8L)); });
  row("gaussian-trace", "KIND",
      "tiles: each 8x8 pixel tile lists the Gaussians its rays can reach and its rays test only those (the same image, faster on "
      "CPU devices); bvh: a ray-query traversal per ray, as training and refrax render",
      d.tiledTrace ? "tiles" : "bvh", [](O& o, const Args& a) {
        std::string v = a.get("gaussian-trace");
        if (v != "tiles" && v != "bvh") fail("--gaussian-trace must be tiles or bvh");
        o.tiledTrace = v == "tiles";
      });
  row("water-trace", "KIND",
      "grid: the baked water (a height grid) is walked cell by cell; bvh: a ray query per ray through its BVH (the same "
      "triangles; a glTF mesh always takes the BVH)",
      d.walkGrid ? "grid" : "bvh", [](O& o, const Args& a) {
        std::string v = a.get("water-trace");
        if (v != "grid" && v != "bvh") fail("--water-trace must be grid or bvh");
        o.walkGrid = v == "grid";
      });
  row("k", "N", "k-buffer size of the Gaussian tracer (1-64)", "the run's, at least " + std::to_string(kDefaultKBuffer),
      [](O& o, const Args& a) {
        long k = a.getInt("k", long(kDefaultKBuffer));
        if (k < 1 || k > 64) fail("--k must be between 1 and 64");
        o.k = k;
      });
  row("sh", "DEGREE", "spherical-harmonics degree (0-3)", "the checkpoint's",
      [](O& o, const Args& a) { o.shDegree = uint32_t(std::clamp(a.getInt("sh", 3), 0L, 3L)); });
  row("min-transmittance", "T", "stop blending a ray once its transmittance is below T (faster, less exact)", shown(d.minTransmittance),
      [](O& o, const Args& a) {
        o.minTransmittance = float(a.getDouble("min-transmittance", o.minTransmittance));
        if (!(o.minTransmittance >= 0 && o.minTransmittance < 1)) fail("--min-transmittance must be in [0, 1)");
      });
  row("heatmap", "", "show the hit-count heat map instead of colour", "", [](O& o, const Args&) { o.heatmap = true; });
  row("heat-scale", "HITS", "hits per pixel shown at the heat map's top colour", shown(d.heatScale), [](O& o, const Args& a) {
    o.heatScale = float(a.getDouble("heat-scale", o.heatScale));
    if (!(o.heatScale > 0)) fail("--heat-scale must be a positive number of hits");
  });
  row("view", "SPLIT:INDEX", "start at a dataset camera (e.g. test:0)", "", [](O& o, const Args& a) { o.view = a.get("view"); });
  row("mode", "MODE", "gaussians, normals or wireframe (the last two: the surface alone)", "gaussians (normals without a scene)",
      [](O& o, const Args& a) {
        o.mode = a.get("mode");
        if (o.mode != "gaussians" && o.mode != "normals" && o.mode != "wireframe") fail("--mode must be gaussians, normals or wireframe");
      });
  row("surface", "KIND", "without a scene: built-in surface flat, sine or triangle", d.surface,
      [](O& o, const Args& a) { o.surface = a.get("surface"); });
  row("camera", "x,y,z,tx,ty,tz", "start camera position and target", d.camera, [](O& o, const Args& a) {
    o.camera = a.get("camera");
    o.cameraGiven = true;
  });
  row("fov", "DEG", "vertical field of view", shown(std::round(3600.0 / M_PI * std::atan(FlyCamera{}.tanHalfFovY)) / 10.0),
      [](O& o, const Args& a) {
        double fov = a.getDouble("fov", 45);
        if (!(fov > 0 && fov < 180)) fail("--fov must be in (0, 180) degrees");
        o.home.tanHalfFovY = float(std::tan(fov * M_PI / 360));
      });
  row("width", "PIXELS", "window width", std::to_string(d.width),
      [](O& o, const Args& a) { o.width = int(a.getIntIn("width", o.width, 1, 8192)); });
  row("height", "PIXELS", "window height", std::to_string(d.height),
      [](O& o, const Args& a) { o.height = int(a.getIntIn("height", o.height, 1, 8192)); });
  row("size", "PIXELS", "square window of this side (overrides --width/--height)", "",
      [](O& o, const Args& a) { o.width = o.height = int(a.getIntIn("size", 0, 1, 8192)); });
  row("frames", "N", "render N frames, then exit", "", [](O& o, const Args& a) {
    o.frames = a.getInt("frames", 0);
    if (o.frames < 0) fail("--frames must be positive");
  });
  row("screenshot", "FILE", "with --frames: save the last render as PNG", "", [](O& o, const Args& a) { o.screenshot = a.get("screenshot"); });
  row("benchmark", "", "with --frames: print FPS and GPU ms per stage (after a warm-up)", "", [](O& o, const Args&) { o.benchmark = true; });
  row("auto-resolution", "on|off", "scale the render's resolution each frame to hold --target-fps", "on for a CPU device in a window, off with --frames",
      [](O& o, const Args& a) {
        const std::string v = a.get("auto-resolution");
        if (v != "on" && v != "off") fail("--auto-resolution must be on or off, got " + v);
        o.autoResolution = v == "on";
      });
  row("target-fps", "FPS", "the frame rate --auto-resolution holds", shown(d.targetFps), [](O& o, const Args& a) {
    o.targetFps = a.getDouble("target-fps", o.targetFps);
    if (!(o.targetFps >= 1 && o.targetFps <= 1000)) fail("--target-fps must be between 1 and 1000");
  });
  row("min-seconds", "S", "with --frames: keep rendering until S seconds after the first frame (e.g. to see a training run's next checkpoint)",
      shown(d.minSeconds), [](O& o, const Args& a) {
        o.minSeconds = a.getDouble("min-seconds", 0.0);
        if (!(o.minSeconds >= 0.0 && o.minSeconds <= 86400.0)) fail("--min-seconds must be between 0 and 86400");
      });
  return t;
}

}  // namespace

std::vector<cli::Option> viewerOptionList() {
  std::vector<cli::Option> list = cli::deviceOptions();
  for (const ViewerOptionRow& r : viewerOptionTable()) list.push_back(r.option);
  return list;
}

ViewerOptions parseViewerOptions(const cli::Args& args) {
  ViewerOptions o;
  if (args.positional.size() > 1) fail("refrax-view takes one run folder");
  if (!args.positional.empty()) o.runDir = args.positional[0];
  o.device = args.get("device");
  o.trace = args.get("trace");
  o.validation = args.has("validation");
  // --size after --width and --height (the table's order), so it overrides them.
  for (const ViewerOptionRow& r : viewerOptionTable())
    if (args.has(r.option.name)) r.read(o, args);
  if (!o.runDir.empty() && !o.ply.empty()) fail("give a run folder or --ply FILE, not both");
  if (o.mode == "gaussians" && o.runDir.empty() && o.ply.empty()) fail("--mode gaussians needs a run folder or --ply");
  if (!o.screenshot.empty() && o.frames == 0) fail("--screenshot needs --frames N");
  if (o.benchmark && o.frames == 0) fail("--benchmark needs --frames N");
  // Scripts that watch a training run need wall time, not a frame count: a fast device renders
  // any fixed count before the 1 s checkpoint poll comes round.
  if (o.minSeconds > 0.0 && o.frames == 0) fail("--min-seconds needs --frames N");
  float tanHalfFovY = o.home.tanHalfFovY;
  o.home = parseLookAt(o.camera);
  o.home.tanHalfFovY = args.has("fov") ? tanHalfFovY : o.home.tanHalfFovY;
  return o;
}

}  // namespace refrax
