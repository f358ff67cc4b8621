// refrax preview: a water surface (built-in) rendered by itself, shaded by normal or as a
// wireframe, to PNG — the headless twin of refrax-view's surface view.
#include <cstdio>

#include "engine/surface/builtin_surfaces.h"
#include "engine/base/error.h"
#include "engine/surface/grid_mesh.h"
#include "engine/surface/surface_preview.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

int runPreview(const cli::Args& args) {
  std::string out = args.get("output");
  if (out.empty()) fail("refrax preview needs -o/--output FILE.png");
  BuiltinSurface s;
  s.kind = args.get("surface", "sine");
  s.amplitude = float(args.getDouble("amplitude", 0.03));
  s.wavelength = float(args.getDouble("wavelength", 0.6));
  s.directionDeg = float(args.getDouble("direction", 30));
  uint32_t w = uint32_t(args.getInt("width", 400)), h = uint32_t(args.getInt("height", 300));
  if (w == 0 || h == 0 || w > 16384 || h > 16384) fail("image size must be 1..16384 pixels");
  std::string mode = args.get("mode", "normals");
  if (mode != "normals" && mode != "wireframe") fail("--mode must be normals or wireframe");
  FlyCamera cam = parseLookAt(args.get("camera", "0,-2.2,1.6,0,0,0"));
  auto heights = surfaceHeightFunction(s);  // validates the surface before any device work

  auto ctx = cli::openContext(args);
  GridMesh mesh = makeGridMesh(128, 128, -1, -1, 1, 1, heights);
  SurfacePreview preview = createSurfacePreview(*ctx, mesh.vertices, mesh.indices);
  Buffer pixels = createBuffer(*ctx, size_t(w) * h * 4);
  const float background[3] = {0.05f, 0.05f, 0.08f};
  submitAndWait(*ctx, [&](VkCommandBuffer cb) {
    cmdRenderSurfacePreview(cb, preview, cam, w, h, mode == "wireframe" ? PreviewMode::Wireframe : PreviewMode::Normals, background,
                            pixels);
  });
  writePng(out, rgba8ToImage(downloadVector<uint32_t>(*ctx, pixels, size_t(w) * h), w, h));
  std::printf("wrote %s (%ux%u)\n", out.c_str(), w, h);
  return 0;
}

std::vector<cli::Option> previewOptions() {
  auto o = cli::deviceOptions();
  o.insert(o.begin(), {{"output", "FILE", "PNG to write", ""},
                       {"surface", "KIND", "flat, sine or triangle", "sine"},
                       {"amplitude", "A", "wave amplitude", "0.03"},
                       {"wavelength", "L", "wavelength", "0.6"},
                       {"direction", "DEG", "wave direction in the xy plane", "30"},
                       {"mode", "MODE", "normals or wireframe", "normals"},
                       {"camera", "x,y,z,tx,ty,tz", "camera position and target", "0,-2.2,1.6,0,0,0"},
                       {"width", "PIXELS", "image width", "400"},
                       {"height", "PIXELS", "image height", "300"}});
  return o;
}

REFRAX_COMMAND({"preview", "render a built-in water surface by itself (normals or wireframe) to PNG",
                "refrax preview -o FILE.png [--surface flat|sine|triangle] [--camera x,y,z,tx,ty,tz] [options]", previewOptions(),
                runPreview});

}  // namespace
}  // namespace refrax
