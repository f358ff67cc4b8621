// refrax render-gaussians: Gaussians from a 3DGS PLY rendered along straight camera rays,
// i.e. the scene with the water removed (no refraction at any surface).
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "engine/view/fly_camera.h"
#include "engine/view/view_camera.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/io/image_io.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/vk/vk_context.h"
#include "engine/gaussian/water_removal.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

std::vector<float> parseFloats(const std::string& text, size_t count, const char* option) {
  std::vector<float> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t used = 0;
      v.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      fail(std::string("--") + option + " expects " + std::to_string(count) + " comma-separated numbers, got '" + text + "'");
    }
  }
  if (v.size() != count) fail(std::string("--") + option + " expects " + std::to_string(count) + " comma-separated numbers, got '" + text + "'");
  return v;
}

int runRenderGaussians(const cli::Args& args) {
  if (args.positional.size() != 1) fail("refrax render-gaussians needs one Gaussian PLY file");
  if (!args.has("out")) fail("refrax render-gaussians needs --out FILE.png");
  if (!hasPngExtension(args.get("out"))) fail("--out must name a .png file (render-gaussians writes PNG), got '" + args.get("out") + "'");
  GaussianSet set = readGaussiansPly(args.positional[0]);
  FlyCamera cam = parseLookAt(args.get("camera", "0,-2,1.2,0,0,-0.5"));
  auto bg = parseFloats(args.get("background", "0,0,0"), 3, "background");
  long width = args.getInt("width", 392), height = args.getInt("height", 392);
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) fail("--width/--height must be between 1 and 16384");
  double tanHalf = args.getDouble("tan-half-fov", 0.36);
  if (!(tanHalf > 0 && tanHalf < 100)) fail("--tan-half-fov must be positive");
  cam.tanHalfFovY = float(tanHalf);
  long degree = args.getInt("sh-degree", 3);
  if (degree < 0 || degree > 3) fail("--sh-degree must be 0..3");

  auto ctx = cli::openContext(args);
  GaussianTracer tracer = createGaussianTracer(*ctx, uint32_t(args.getInt("k", kDefaultKBuffer)));
  ProxyKind kind = proxyKindFor(args.get("proxy", "auto"), ctx->caps);
  DeviceGaussians dev = uploadGaussians(*ctx, set);
  GaussianProxies proxies = buildGaussianProxies(*ctx, tracer, dev, set, kind, false);
  if (proxies.clamped)
    std::fprintf(stderr, "refrax: %u of %zu Gaussians are larger than any scene: their proxy boxes were clamped to +-%.0e m\n",
                 proxies.clamped, set.count(), double(f64::kMaxProxyHalfExtent));
  TraceOptions opt;
  for (int c = 0; c < 3; c++) opt.background[c] = bg[c];
  opt.shDegree = uint32_t(degree);
  CameraRayPipelines cameraPipelines = createCameraRayPipelines(*ctx);
  auto results = renderWithoutWater(*ctx, tracer, cameraPipelines, proxies, dev, cameraFromFly(cam, int(width), int(height)), opt);
  Image img;
  img.width = int(width);
  img.height = int(height);
  img.channels = 3;
  img.pixels.resize(results.size() * 3);
  double hits = 0;
  for (size_t i = 0; i < results.size(); i++) {
    for (int c = 0; c < 3; c++) img.pixels[3 * i + c] = results[i].rgb[c];
    hits += results[i].hits;
  }
  writePng(args.get("out"), img);
  std::printf("%zu Gaussians, %s proxies, %ldx%ld: %.1f hits per ray; wrote %s\n", set.count(), proxyKindName(kind), width, height,
              hits / double(results.size()), args.get("out").c_str());
  return 0;
}

std::vector<cli::Option> renderOptions() {
  std::vector<cli::Option> o = {{"out", "FILE", "PNG to write", ""},
                                {"camera", "x,y,z,tx,ty,tz", "camera position and target (world up is +z)", "0,-2,1.2,0,0,-0.5"},
                                {"tan-half-fov", "T", "tangent of half the vertical field of view", "0.36"},
                                {"width", "PIXELS", "image width", "392"},
                                {"height", "PIXELS", "image height", "392"},
                                {"background", "R,G,B", "background colour", "0,0,0"},
                                {"sh-degree", "D", "SH degree used (0..3)", "3"},
                                {"k", "K", "k-buffer size", std::to_string(kDefaultKBuffer)},
                                {"proxy", "KIND", "Gaussian proxies: aabb, instanced or auto", "auto"}};
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"render-gaussians", "render a Gaussian PLY along straight camera rays (the scene with the water removed)",
                "refrax render-gaussians SCENE.ply --out IMAGE.png [options]", renderOptions(), runRenderGaussians});

}  // namespace
}  // namespace refrax
