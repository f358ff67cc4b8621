#pragma once
// Between the viewer's fly camera (engine/view/fly_camera.h) and the pinhole Camera the trainer's
// ray stage takes (engine/camera/camera.h), so the viewer traces the same rays as `refrax render`
// (a look-at camera, or a dataset camera scaled to the window).
#include "engine/camera/camera.h"
#include "engine/view/fly_camera.h"

namespace refrax {

// A look-at camera (viewer, CLI) as a dataset-convention pinhole camera of width x height
// pixels, square pixels, vertical half-fov tangent cam.tanHalfFovY.
Camera cameraFromFly(const FlyCamera& cam, int width, int height);

// The fly camera looking where `camera` looks (roll is lost: fly cameras keep +z up), with
// its vertical field of view; orbit target one unit ahead; speed kept from `like`.
FlyCamera flyFromCamera(const Camera& camera, const FlyCamera& like);
// The same camera at another image size: focal lengths and principal point scaled per axis.
Camera resizedCamera(const Camera& camera, int width, int height);

}  // namespace refrax
