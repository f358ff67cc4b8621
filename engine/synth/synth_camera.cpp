#include "engine/synth/synth_camera.h"

#include <cmath>

#include "engine/camera/lens_math.h"

namespace refrax::synth {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;

SynthCamera withIntrinsics(int width, int height, double fovX) {
  SynthCamera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.5 * width / std::tan(0.5 * fovX);
  c.cx = 0.5 * width;
  c.cy = 0.5 * height;
  return c;
}

void setAxes(SynthCamera& c, const glm::dvec3& right, const glm::dvec3& up, const glm::dvec3& back, const glm::dvec3& eye) {
  c.cameraToWorld = glm::dmat4(glm::dvec4(right, 0), glm::dvec4(up, 0), glm::dvec4(back, 0), glm::dvec4(eye, 1));
}
}  // namespace

glm::dvec3 cameraCentre(const SynthCamera& cam) { return glm::dvec3(cam.cameraToWorld[3]); }

glm::dvec3 cameraRayDirection(const SynthCamera& cam, double px, double py) {
  const glm::dmat4& m = cam.cameraToWorld;
  return f64::cameraDirection(glm::dvec3(m[0]), glm::dvec3(m[1]), glm::dvec3(m[2]), glm::dvec4(cam.fx, cam.fy, cam.cx, cam.cy), int(cam.lens.kind),
                              cam.lens.radial, cam.lens.extra, glm::dvec2(px, py));
}

SynthCamera lookAtCamera(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& worldUp, int width, int height, double fovX) {
  SynthCamera c = withIntrinsics(width, height, fovX);
  glm::dvec3 back = glm::normalize(eye - target);
  glm::dvec3 right = glm::normalize(glm::cross(worldUp, back));
  glm::dvec3 up = glm::cross(back, right);
  setAxes(c, right, up, back, eye);
  return c;
}

SynthCamera downwardCamera(const glm::dvec3& eye, int width, int height, double fovX) {
  SynthCamera c = withIntrinsics(width, height, fovX);
  setAxes(c, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, eye);
  return c;
}

std::vector<SynthCamera> ringCameras(int count, double polarDeg, double radius, double azimuthDeg, const glm::dvec3& target, int width,
                                     int height, double fovX) {
  std::vector<SynthCamera> cams;
  for (int i = 0; i < count; i++) {
    double phi = (azimuthDeg + 360.0 * i / count) * kDeg, theta = polarDeg * kDeg;
    glm::dvec3 eye = target + radius * glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    cams.push_back(lookAtCamera(eye, target, {0, 0, 1}, width, height, fovX));
  }
  return cams;
}

std::vector<SynthCamera> gridCameras(double cx, double cy, double z, double spacing, int width, int height, double fovX) {
  std::vector<SynthCamera> cams;
  for (int row = 0; row < 3; row++)
    for (int col = 0; col < 3; col++)
      cams.push_back(downwardCamera({cx + (col - 1) * spacing, cy + (1 - row) * spacing, z}, width, height, fovX));
  return cams;
}

std::vector<SynthCamera> betweenCameras(double cx, double cy, double z, double spacing, int width, int height, double fovX) {
  std::vector<SynthCamera> cams;
  for (double dy : {0.5, -0.5})
    for (double dx : {-0.5, 0.5}) cams.push_back(downwardCamera({cx + dx * spacing, cy + dy * spacing, z}, width, height, fovX));
  return cams;
}

SynthCamera tiltedAboutX(const SynthCamera& cam, const glm::dvec3& pivot, double angleDeg) {
  double c = std::cos(angleDeg * kDeg), s = std::sin(angleDeg * kDeg);
  // Columns: x kept, y -> (0, c, s), z -> (0, -s, c): +Z (a camera's back axis when it looks
  // down) turns towards -y, so the eye above the pivot moves to -y and looks towards +y.
  glm::dmat3 r(glm::dvec3(1, 0, 0), glm::dvec3(0, c, s), glm::dvec3(0, -s, c));
  SynthCamera t = cam;
  glm::dvec3 axes[3];
  for (int i = 0; i < 3; i++) axes[i] = r * glm::dvec3(cam.cameraToWorld[i]);
  setAxes(t, axes[0], axes[1], axes[2], pivot + r * (cameraCentre(cam) - pivot));
  return t;
}

}  // namespace refrax::synth
