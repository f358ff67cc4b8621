#pragma once
// Textured primitives (planes, boxes, spheres, cylinders) tessellated into one triangle
// list for the synthetic scenes under the water.
#include <glm/glm.hpp>
#include <vector>

#include "engine/synth/synth_texture.h"
#include "engine/synth/triangle_bvh.h"

namespace refrax::synth {

struct SynthMaterial {
  int texture;
  glm::dvec2 uvScale{1, 1};  // texture repeats over the primitive's natural UV range
  glm::dvec3 tint{1, 1, 1};
};

struct SynthScene {
  std::vector<SynthTexture> textures;
  std::vector<SynthMaterial> materials;
  TriangleBvh bvh;
  glm::dvec3 background{0.5, 0.55, 0.6};   // rays that meet nothing
  glm::dvec3 lightDirection{0.36, 0.24, 0.9};  // towards the light; Lambert plus ambient
  double ambient = 0.45;
  // Set when something stands out of the water beside it (synth_rim.h): a camera ray can then
  // meet the scene before the water, so the renderer looks for that (otherwise it need not).
  bool geometryAboveWater = false;
};

struct SceneBuilder {
  std::vector<MeshTriangle> triangles;

  // Axis-aligned horizontal rectangle at height z, UV (0..1) across it.
  void floorRect(double xmin, double ymin, double xmax, double ymax, double z, int material);
  // Box with half extents `half`, rotated by yaw (radians) about +Z; each face UV 0..1.
  void box(const glm::dvec3& centre, const glm::dvec3& half, double yaw, int material, int topMaterial = -1);
  void sphere(const glm::dvec3& centre, double radius, int material, int segments);
  // Upright cylinder standing on baseCentre, with caps; side u around, v up.
  void cylinder(const glm::dvec3& baseCentre, double radius, double height, int material, int segments, int capMaterial = -1);
  void quad(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d, int material);
};

}  // namespace refrax::synth
