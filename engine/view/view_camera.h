#pragma once
// Between the viewer's fly camera (engine/view/fly_camera.h) and the pinhole Camera the trainer's
// ray stage takes (engine/camera/camera.h), so the viewer traces the same rays as `refrax render`
// (a look-at camera, or a dataset camera scaled to the window).
#include "engine/camera/camera.h"
#include "engine/view/fly_camera.h"
#include "engine/gaussian/water_removal.h"  // cameraFromFly: the fly camera as a pinhole Camera

namespace refrax {

// The fly camera looking where `camera` looks (roll is lost: fly cameras keep +z up), with
// its vertical field of view; orbit target one unit ahead; speed kept from `like`.
FlyCamera flyFromCamera(const Camera& camera, const FlyCamera& like);
// The same camera at another image size: focal lengths and principal point scaled per axis.
Camera resizedCamera(const Camera& camera, int width, int height);

}  // namespace refrax
