#pragma once
// Cameras and the camera rigs of the synthetic datasets (NeRF/Blender convention:
// camera-to-world, the camera looks down its -Z with +Y up; pixel centres at i + 0.5); a
// pinhole unless --camera-model gives them a lens (engine/camera/lens.h).
#include <glm/glm.hpp>
#include <vector>

#include "engine/camera/lens.h"

namespace refrax::synth {

struct SynthCamera {
  glm::dmat4 cameraToWorld{1.0};
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Lens lens;
};

glm::dvec3 cameraCentre(const SynthCamera& cam);
// Unit world-space direction through image point (px, py) in pixels (y down), through the lens
// (the same math as Refrax's own rays: shaders/include/camera_direction.glsl).
glm::dvec3 cameraRayDirection(const SynthCamera& cam, double px, double py);
// Camera at eye looking at target; its +Y is as close to worldUp as possible.
SynthCamera lookAtCamera(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& worldUp, int width, int height, double fovX);
// Straight down, image +Y (up) along world +Y.
SynthCamera downwardCamera(const glm::dvec3& eye, int width, int height, double fovX);
// `count` cameras on a circle at polar angle `polarDeg` from +Z, distance `radius` from target,
// all looking at target; the first at azimuth `azimuthDeg`.
std::vector<SynthCamera> ringCameras(int count, double polarDeg, double radius, double azimuthDeg, const glm::dvec3& target, int width,
                                     int height, double fovX);
// 3 x 3 grid of downward cameras at height z, centred on (cx, cy), `spacing` apart; row-major
// from (-x, +y), so index 4 is the centre.
std::vector<SynthCamera> gridCameras(double cx, double cy, double z, double spacing, int width, int height, double fovX);
// The four downward cameras half way between that grid's centre and its corners, (+-s/2, +-s/2)
// about (cx, cy): views between the training cameras, as far from each as a rig's views can be.
std::vector<SynthCamera> betweenCameras(double cx, double cy, double z, double spacing, int width, int height, double fovX);
// The camera turned rigidly by angleDeg about the world x axis through `pivot` (positive: its
// centre moves towards -y, a downward view axis tips towards +y). Turning a whole downward rig
// keeps its cameras parallel, each view axis angleDeg from the vertical, and a camera that
// looked at the pivot still looks at it.
SynthCamera tiltedAboutX(const SynthCamera& cam, const glm::dvec3& pivot, double angleDeg);

}  // namespace refrax::synth
