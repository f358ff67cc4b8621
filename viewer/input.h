#pragma once
// The viewer's keyboard and mouse, read once per frame (ignored while Dear ImGui has them):
// WASD/QE fly, right-drag looks, the wheel scales the speed, and the keys of the header of
// viewer/main.cpp. Moving leaves a dataset camera for the fly camera at the same place.
#include <functional>
#include <map>

#include "engine/view/fly_camera.h"
#include "viewer/panels.h"
#include "engine/frame/view_scene.h"

struct GLFWwindow;

namespace refrax {

struct Input {
  bool looking = false;
  double lastX = 0, lastY = 0;
  float wheel = 0;
  std::map<int, bool> down;  // keys held last frame (edge detection)
};

// Makes `input` the window's scroll target (the wheel), chained to Dear ImGui's.
void attachInput(GLFWwindow* window, Input& input);
// One frame's input over dt seconds; scene may be null (a built-in surface alone).
void handleInput(GLFWwindow* window, Input& input, ViewerState& state, FlyCamera& camera, const ViewScene* scene, float dt);

}  // namespace refrax
