#pragma once
// Rendering a trained model and measuring it: a view through the learned water (camera rays
// refracted at the surface, then the Gaussians), with the water removed (straight rays), or
// through another surface swapped in (a closed-form one: flat or sine, engine/height/analytic_height.h;
// or any triangle mesh, engine/surface/mesh_surface.h);
// and the metrics of a run against a dataset (test PSNR/SSIM, surface RMSE against the ground
// truth, water-removal PSNR against the air images).
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "engine/height/analytic_height.h"
#include "engine/camera/camera.h"
#include "engine/io/image_io.h"
#include "engine/surface/mesh_surface.h"
#include "engine/loss/metrics.h"
#include "engine/dataset/dataset.h"
#include "engine/model/model.h"

namespace refrax {

enum class WaterView { Keep, Remove, Swap };

struct RenderedView {
  Image image;
  std::vector<glm::dvec3> surfacePoints;  // hits on the water (Keep / Swap)
  std::vector<glm::dvec3> planePoints;    // the same pixels' hits on the initial flat water plane
  uint32_t missed = 0;                    // rays that missed the surface domain
};

// The surface WaterView::Swap puts in the water's place: exactly one of the two. A closed-form
// surface is lifted into the model's proxy-surface configuration (its own surface is built
// for the call); a mesh is traced as it is (closest hit, its interpolated vertex normals).
struct SwapSurface {
  const AnalyticHeightField* analytic = nullptr;
  const MeshSurface* mesh = nullptr;
};

// What a render computes beside the image, and where its time goes.
struct RenderOptions {
  // The water's hits (RenderedView's surfacePoints and planePoints), for the surface's metrics:
  // three readbacks of a ray per pixel. An image alone (kImageOnly) leaves them out, and is
  // one submission where the water's trace is one (the camera rays, the water, the Gaussians and
  // the results' copy for the host, no wait between; a mesh swapped in takes the stages' path).
  bool surfacePoints = true;
  // When given: milliseconds per stage of this render, added to. An image alone: the device's
  // timestamps ("camera rays", "water", "gaussians", "image readback") and the host's
  // "image (host)"; else host wall milliseconds ("camera rays", "water", "surface points",
  // "gaussians", "image"), each stage waited for.
  std::vector<std::pair<std::string, double>>* stageMs = nullptr;
};

// An image alone (the views an evaluation only compares): no surface points, one submission
// where the water's trace is one.
inline const RenderOptions kImageOnly{false, nullptr};

// `swap` is used for WaterView::Swap only.
RenderedView renderView(Model& model, const Camera& camera, WaterView water, const SwapSurface& swap, const RenderOptions& options = {});
inline RenderedView renderView(Model& model, const Camera& camera, WaterView water, const AnalyticHeightField* swap = nullptr) {
  return renderView(model, camera, water, SwapSurface{swap, nullptr});
}

// Any rays (not a camera's) through the model: refracted at the learned water first (Keep, where
// the model has water) or straight to the Gaussians (Remove); the scene's background, its SH
// degree at the model's step, and `depthAtOpacity` (TraceOptions) for the results' depth. In
// chunks the model's ray buffers hold. `hitWater` (Keep), when given: per ray, whether it met
// the water inside its domain.
std::vector<GpuTraceResult> traceModelRays(Model& model, const std::vector<GpuRay>& rays, WaterView water, float depthAtOpacity = 0.0f,
                                           std::vector<uint8_t>* hitWater = nullptr);

// A look-at camera: position, target, world up +z, vertical field of view (radians).
Camera lookAtCamera(const glm::dvec3& position, const glm::dvec3& target, int width, int height, double fovY);

// Metrics of the model on `dataset` (its test split; its ground-truth surface and
// air split when present); when rendersDir is not empty, writes test_NNN.png and
// test_NNN_air.png there.
nlohmann::json evaluateModel(Model& model, const Dataset& dataset, const std::string& rendersDir);

}  // namespace refrax
