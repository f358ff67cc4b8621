#include "viewer/surface_view.h"

#include <cstdio>

#include "engine/surface/grid_mesh.h"
#include "engine/surface/gltf_surface.h"
#include "engine/model/open_model.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {
constexpr uint32_t kCells = 128;  // per side: fine enough to see the learned waves' shape

std::string describe(const BuiltinSurface& b, const SurfaceDomain& d) {
  char text[200];
  std::snprintf(text, sizeof text, "%s %.9g %.9g %.9g %.9g | %.9g %.9g %.9g %.9g", b.kind.c_str(), b.height, b.amplitude, b.wavelength,
                b.directionDeg, d.x0, d.y0, d.x1, d.y1);
  return text;
}
}  // namespace

const SurfacePreview& surfaceViewFor(Context& ctx, SurfaceView& view, ViewScene* scene, const RenderSettings& settings,
                                     const BuiltinSurface& fallback) {
  std::string key;
  GridMesh mesh;
  bool learned = scene && effectiveWater(*scene, settings) == WaterMode::Kept;
  bool gltf = scene && !learned && settings.water == WaterMode::Swapped && !settings.swapMesh.empty();
  if (learned) key = "learned " + std::to_string(scene->generation);
  else if (gltf) key = "gltf " + settings.swapMesh;
  else if (scene) key = describe(settings.swap, scene->domain);
  else key = describe(fallback, SurfaceDomain{});
  if (view.preview && view.key == key) return *view.preview;
  if (learned) {
    const SurfaceDomain& d = scene->domain;
    std::vector<double> h = sampleWaterHeights(*scene->model, kCells + 1, kCells + 1);
    mesh = makeGridMesh(kCells, kCells, d.x0, d.y0, d.x1, d.y1);
    for (uint32_t i = 0; i < mesh.vertexCount(); i++) mesh.vertices[3 * i + 2] = float(h[i]);
  } else if (gltf) {
  } else if (scene) {
    const SurfaceDomain& d = scene->domain;
    mesh = makeGridMesh(kCells, kCells, d.x0, d.y0, d.x1, d.y1, surfaceHeightFunction(settings.swap));
  } else {
    mesh = makeGridMesh(kCells, kCells, -1, -1, 1, 1, surfaceHeightFunction(fallback));
  }
  vkDeviceWaitIdle(ctx.device);
  view.preview.reset();
  if (gltf) {
    SurfaceMesh m = readSurfaceGltf(settings.swapMesh);
    view.preview.emplace(createSurfacePreview(ctx, m.positions, m.indices));
  } else {
    view.preview.emplace(createSurfacePreview(ctx, mesh.vertices, mesh.indices));
  }
  view.key = key;
  return *view.preview;
}

}  // namespace refrax
