#pragma once
// A point cloud's vertices from a PLY file (ascii or binary_little_endian): x, y, z of any
// scalar type, and red, green, blue when present (uchar 0..255, or a float type as 0..1),
// as nerfstudio's ns-process-data writes its sparse points (sparse_pc.ply).
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace refrax {

struct PlyPoint {
  glm::dvec3 position{0.0};
  glm::dvec3 colour{0.5};  // 0..1; grey when the file has none
};

// refrax::Error naming the file on a malformed or truncated file, a missing x, y or z, or a
// coordinate that is not finite.
std::vector<PlyPoint> readPlyPoints(const std::string& path);
// Binary little-endian: x, y, z as float, red, green, blue as uchar (colour clamped to 0..1);
// written atomically. What CloudCompare, MeshLab and PDAL open as a coloured point cloud.
void writePlyPoints(const std::string& path, const std::vector<PlyPoint>& points);

}  // namespace refrax
