#pragma once
// One frame of the Gaussians, the viewer's and `refrax render`'s: camera rays -> (water kept or
// swapped: refraction at the surface) -> Gaussian forward trace (tiled by default) -> RGBA8
// pixels (colour or hit heat map). refrax-view presents the pixels; renderFrameImage reads them
// back for a PNG, so a screenshot equals `refrax render`'s image.
//
// Two ways through the water:
//  - baked (the default, the fast path): the water as a triangle mesh (engine/surface/mesh_surface.h):
//    the learned height field baked once per loaded checkpoint on a bakeCells^2 grid over its
//    domain (the paper's surface precomputed at render resolution), a built-in surface on the
//    same grid, or a glTF mesh; one ray query per ray, recorded in the frame's command buffer
//    with everything else (no host round trip);
//  - exact: the trainer's subdivided proxy surface (traceSurface, as training, `refrax eval` and
//    renderView trace it), which submits and reads back once per subdivision level, so
//    prepareFrame runs the rays and the surface before the frame's command buffer.
// A triangle wave or a glTF mesh has no height field to subdivide: it is always a mesh.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/height/analytic_height.h"
#include "engine/surface/builtin_surfaces.h"
#include "engine/camera/camera.h"
#include "engine/camera/camera_rays.h"
#include "engine/surface/mesh_surface.h"
#include "engine/gaussian/tiled_trace.h"
#include "engine/io/image_io.h"
#include "engine/view/view_compose.h"
#include "engine/vk/vk_timer.h"
#include "engine/surface/water_surface.h"
#include "engine/frame/view_scene.h"

namespace refrax {

enum class WaterMode : int { Kept = 0, Removed = 1, Swapped = 2 };

struct RenderSettings {
  WaterMode water = WaterMode::Kept;
  BuiltinSurface swap;    // the surface swapped in: flat, sine or triangle ...
  std::string swapMesh;   // ... or this glTF mesh when not empty
  bool exactWater = false;   // the subdivided proxy surface instead of the baked mesh
  uint32_t bakeCells = 256;  // cells per side of the baked grid (a run: gridCells << levels, its finest lattice)
  float ior = 1.33f;
  uint32_t subdivisionLevels = 2;
  uint32_t gridCells = 64;
  uint32_t shDegree = 3;
  float minTransmittance = TraceOptions{}.minTransmittance;
  // The Gaussian trace in 8x8 tiles of candidate lists (engine/gaussian/tiled_trace.h; the same image)
  // instead of a BVH traversal per ray; off: the BVH, as training and `refrax render` trace.
  bool tiledTrace = true;
  // A baked learned or built-in surface (a height grid) found by walking its cells (engine/
  // mesh_surface.h HeightGridLayout) instead of a ray query per ray through its BVH; the same
  // triangles. A glTF mesh always takes the BVH.
  bool walkGrid = true;
  ComposeOptions compose;
};

struct FrameRenderer {
  Context* ctx = nullptr;
  CameraRayPipelines rayPipelines;
  ComputePipeline compose;
  uint32_t capacity = 0;
  Buffer rays, refracted, records, flags, results, pixels;
  Buffer readback;  // the pixels where the host reads them (renderFrameImage), grown as needed
  std::optional<TileCandidates> tiles;  // sized for the last frame's image (tiled trace)

  enum class Path { Straight, Subdivided, Mesh } path = Path::Straight;  // this frame's way through the water
  std::optional<MeshSurface> mesh;
  std::string meshKey;  // what the mesh was built from

  std::optional<WaterSurface> surface;
  std::optional<AnalyticHeightField> swapField;
  std::string surfaceShape;    // domain, cells, levels, capacity the surface was created for
  std::string surfaceHeights;  // what its coarse heights were lifted from (source + model generation)
  std::vector<std::pair<std::string, double>> surfaceMs;  // GPU ms of the last traceSurface
};

FrameRenderer createFrameRenderer(Context& ctx);

// Water modes that need no surface fall back to Removed: a PLY or a run without refraction
// has no water to keep. Returns the mode that will be rendered.
WaterMode effectiveWater(const ViewScene& scene, const RenderSettings& settings);

// Sizes the buffers for camera.width * camera.height rays and, with water, traces the
// camera rays through the surface (submits and waits).
void prepareFrame(FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& settings);
// Records the rest of the frame into cb (camera rays when there is no water, the Gaussian
// trace, the compose into r.pixels), stamping `timer` after each stage.
void cmdRenderFrame(VkCommandBuffer cb, FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& settings,
                    GpuTimer& timer);

// --water as refrax render and refrax-view take it: keep, remove, a built-in surface
// (flat|sine|triangle[:height:amplitude:wavelength:direction]) or a .gltf/.glb mesh (any case)
// to swap in; refrax::Error naming the spec for an unknown one. A mesh is read when a frame is
// prepared (callers read it first to fail before opening anything).
bool isMeshPath(const std::string& path);
void applyWaterSpec(const std::string& spec, float level, RenderSettings& settings);

// The settings a run or PLY opens with: its IOR, lattice (the baked mesh on the trainer's finest
// lattice) and SH degree at its step, its water kept where it has one (else removed).
RenderSettings sceneRenderSettings(const ViewScene& scene);

// One image, as the viewer draws it: prepareFrame, then the frame and the pixels' copy to the
// host in one command buffer (the baked water's frame is that one submission). `stageMs`, when
// given, gets each stage's milliseconds added: the device's timestamps ("rays", "water",
// "cull", "gaussians", "compose", "image readback"; the exact water's "surface"), and the host's
// "image (host)".
Image renderFrameImage(FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& settings,
                       std::vector<std::pair<std::string, double>>* stageMs = nullptr);

// The frame's Gaussian stage alone (its kind, its K) on the rays the frame traces, waited for,
// mean milliseconds over `repeats`: what `refrax render --benchmark` compares a frame with.
double frameTraceMs(FrameRenderer& r, ViewScene& scene, const Camera& camera, const RenderSettings& settings, int repeats);

}  // namespace refrax
