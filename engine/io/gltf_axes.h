#pragma once
// Refrax's world is +Z up (x, y horizontal, water heights along z); glTF is +Y up
// (right-handed, metres):
//     glTF (x, y, z) = Refrax (x, z, -y)        Refrax (x, y, z) = glTF (x, -z, y)
// a rotation of -90 degrees about x (proper: handedness and triangle winding are kept). Every
// glTF reader and writer of Refrax turns points and directions with these.
#include <glm/glm.hpp>

namespace refrax {

inline glm::dvec3 toGltfAxes(glm::dvec3 p) { return {p.x, p.z, -p.y}; }
inline glm::dvec3 fromGltfAxes(glm::dvec3 p) { return {p.x, -p.z, p.y}; }
inline void toGltfAxes(const float* in, float* out) {
  const float x = in[0], y = in[1], z = in[2];
  out[0] = x, out[1] = z, out[2] = -y;
}

}  // namespace refrax
