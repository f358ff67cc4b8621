#pragma once
// What the reference code sets by hand per scene, derived from the cameras instead:
//  - the height field's domain: the bounding rectangle of the cameras' footprints on the
//    initial (flat) water plane z = height (each camera's four image-corner rays and its
//    centre ray intersected with the plane), grown by `margin` (a fraction of each side);
//  - the initial Gaussians' box: those corner and centre rays refracted at the flat plane
//    (air to water, n = (0, 0, 1), Snell with the IOR) and followed down to z = height - depth;
//    the box bounds the points on the plane and at that depth;
//  - the depth under the water, when water.json does not give it: from the LLFF far bounds
//    (COLMAP's depths ignore refraction, so the deepest point seen below the plane at apparent
//    depth a lies at about ior * a: the paraxial apparent-depth law), else the cameras' mean
//    height above the water (a guess: scenes are photographed from about as far as they reach);
//  - the scene extent (3DGS's getNerfppNorm): 1.1 * the largest distance of a camera centre from
//    their mean, which scales the position learning rate and the densification thresholds.
// Every camera must look down at the plane from above it with its whole image (a corner ray
// that never meets the plane means the horizon is in view): otherwise one refrax::Error. A
// fisheye's rays (engine/camera/lens.h) count only out to 75 degrees from the nadir: beyond
// that each is taken at 75 degrees in its own azimuth, so a 180-degree lens has bounds too.
#include <vector>

#include <glm/glm.hpp>

#include "engine/camera/camera.h"
#include "engine/dataset/dataset.h"

namespace refrax {

struct Box {
  glm::dvec3 min{0.0}, max{0.0};
};

Rect surfaceDomainFromCameras(const std::vector<Camera>& cameras, double waterHeight, double margin = 0.05);
Box gaussianBoxFromRefractedFrusta(const std::vector<Camera>& cameras, double waterHeight, double ior, double depth);
double estimateWaterDepth(const std::vector<View>& views, double waterHeight, double ior);
double sceneExtent(const std::vector<Camera>& cameras);

// The image-corner and centre rays' hits on the plane z = height (5 per camera), for the above.
std::vector<glm::dvec3> footprintOnPlane(const Camera& camera, double waterHeight, std::vector<glm::dvec3>* directions = nullptr);

}  // namespace refrax
