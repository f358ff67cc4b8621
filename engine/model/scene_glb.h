#pragma once
// One binary glTF (.glb) with what a run learned, for viewers that are not Refrax
// (PlayCanvas, three.js, Babylon, Cesium): the Gaussians as a KHR_gaussian_splatting POINTS
// primitive (engine/gaussian/gltf_splats.h: activated values, glTF axes, COLOR_0 as the
// point-cloud fallback) and, optionally, the learned water as a triangle mesh with a
// refractive material (KHR_materials_transmission, KHR_materials_ior, KHR_materials_volume).
// The extensions are used, not required: a viewer without them shows a point cloud and an
// opaque sheet. Written atomically.
#include <optional>
#include <string>

#include "engine/gaussian/gltf_splats.h"
#include "engine/surface/gltf_surface.h"

namespace refrax {

struct GlbWater {
  SurfaceMesh mesh;      // Refrax axes
  double ior = 1.33;     // the water's refractive index
  double thickness = 0;  // m, the depth the volume's rays cross (KHR_materials_volume's thicknessFactor)
};

// refrax::Error for a path not ending in .glb, no splats, or a water mesh that is not one.
void writeSceneGlb(const std::string& path, const GltfSplats& splats, const std::optional<GlbWater>& water);

}  // namespace refrax
