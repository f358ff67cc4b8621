#pragma once
// A COLMAP sparse model as COLMAP writes it (cameras, images, points3D; the text `.txt` and the
// binary `.bin` formats), read and written apart from any device so it can be fuzzed and
// tested alone. Values are as in the files: COLMAP's world frame, world-to-camera poses with
// the camera looking down its +Z, x right, y down (OpenCV), pixel centres at integer + 0.5.
// The dataset loader (engine/dataset/colmap.cpp) turns them into Refrax cameras.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace refrax {

struct ColmapCamera {
  uint32_t id = 0;
  std::string model;           // "PINHOLE", "SIMPLE_PINHOLE", "OPENCV", ...
  uint64_t width = 0, height = 0;
  std::vector<double> params;  // as COLMAP orders them for the model
};

struct ColmapImage {
  uint32_t id = 0;
  glm::dvec4 q{1, 0, 0, 0};  // world-to-camera rotation, (w, x, y, z)
  glm::dvec3 t{0};           // world-to-camera translation
  uint32_t cameraId = 0;
  std::string name;          // relative to the image folder
};

struct ColmapPoint {
  glm::dvec3 position{0};
  glm::dvec3 colour{0};  // 0..1
  double error = 0;
  uint32_t views = 0;    // track length: in how many images it was matched
};

struct ColmapModel {
  std::map<uint32_t, ColmapCamera> cameras;
  std::vector<ColmapImage> images;
  std::vector<ColmapPoint> points;
};

// The parameter count of each COLMAP camera model (0: unknown model).
size_t colmapParamCount(const std::string& model);

// Reads `folder`/cameras, images and points3D, each `.bin` when present, else `.txt`
// (points3D may be absent: no points). refrax::Error naming the file on anything malformed.
ColmapModel readColmapModel(const std::string& folder);
// Whether `folder` holds a model (cameras.bin or cameras.txt).
bool hasColmapModel(const std::string& folder);
// Writes the model in one of the two formats (the tests' and the synthesiser's way to make one).
void writeColmapModel(const std::string& folder, const ColmapModel& model, bool binary);

// The world-to-camera rotation of a unit quaternion (w, x, y, z), as COLMAP's qvec2rotmat.
glm::dmat3 colmapRotation(const glm::dvec4& q);
// The unit quaternion (w, x, y, z) of a rotation matrix, w >= 0 (the inverse of colmapRotation).
glm::dvec4 colmapQuaternion(const glm::dmat3& rotation);

}  // namespace refrax
