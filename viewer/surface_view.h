#pragma once
// The surface-only views (normals, wireframe): the water the viewer would refract through as
// triangles (the learned heights of a run on a 128^2 grid, the swapped-in built-in surface or
// glTF mesh, or the window's built-in surface when nothing is loaded), rebuilt when it changes.
#include <optional>
#include <string>

#include "engine/surface/builtin_surfaces.h"
#include "engine/surface/surface_preview.h"
#include "engine/frame/frame_renderer.h"
#include "engine/frame/view_scene.h"

namespace refrax {

struct SurfaceView {
  std::optional<SurfacePreview> preview;
  std::string key;  // what it was built from
};

// scene may be null (then `fallback` over [-1, 1]^2).
const SurfacePreview& surfaceViewFor(Context& ctx, SurfaceView& view, ViewScene* scene, const RenderSettings& settings,
                                     const BuiltinSurface& fallback);

}  // namespace refrax
