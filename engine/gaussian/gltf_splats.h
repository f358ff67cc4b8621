#pragma once
// Gaussians in KHR_gaussian_splatting's terms (the ratified glTF extension: a POINTS primitive
// whose attributes are each splat's position, rotation, scale, opacity and SH coefficients):
// activated values in glTF axes, ready to be written as accessors (engine/model/scene_glb.h).
//
// Axes: glTF (x, y, z) = Refrax (x, z, -y), a rotation of -90 degrees about x
// (engine/io/gltf_axes.h). The data are turned, not the node: positions and
// rotations by the rotation, and each SH degree by its rotation matrix, so viewers that ignore
// a node's rotation for the SH (the extension says they SHOULD apply it) still colour right.
// Values: scale exp(log sigma), opacity sigmoid(logit density), rotation the unit quaternion
// as x y z w, SH coefficients as trained (the renderer adds the 0.5 bias, as Refrax does).
#include <cstdint>
#include <vector>

#include "engine/gaussian/gaussians.h"
#include "engine/io/gltf_axes.h"

namespace refrax {

struct GltfSplats {
  size_t count = 0;
  uint32_t shDegree = 0;
  std::vector<float> positions;        // xyz per splat
  std::vector<float> rotations;        // xyzw per splat, unit
  std::vector<float> scales;           // linear sigma per local axis
  std::vector<float> opacities;        // one per splat, in [0, 1]
  std::vector<std::vector<float>> sh;  // (shDegree + 1)^2 coefficients, each rgb per splat
  std::vector<float> colors;           // rgba per splat: the diffuse colour (clamped) and opacity, for COLOR_0
};

// The set's Gaussians with SH up to `shDegree` (0-3; higher coefficients are dropped).
GltfSplats gltfSplatsFrom(const GaussianSet& set, uint32_t shDegree);

// For SH degree l, the (2l+1) x (2l+1) matrix T (row-major) that takes a colour channel's
// degree-l coefficients in Refrax axes to glTF axes: the colour seen along R d from the
// turned coefficients is the colour seen along d from the old (R: Refrax -> glTF axes).
std::vector<double> shRotationToGltf(uint32_t degree);

}  // namespace refrax
