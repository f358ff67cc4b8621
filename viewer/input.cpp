#include "viewer/input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>

#include <cmath>

#include "engine/view/view_camera.h"

namespace refrax {
namespace {

void onScroll(GLFWwindow* w, double, double dy) {
  static_cast<Input*>(glfwGetWindowUserPointer(w))->wheel += float(dy);
  ImGui_ImplGlfw_ScrollCallback(w, 0, dy);
}

void handleKeys(GLFWwindow* window, Input& input, ViewerState& state, FlyCamera& camera, const ViewScene* scene, float dt,
                const std::function<void()>& leaveSnap) {
  RenderSettings& rs = state.render;
  auto key = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
  auto pressed = [&](int k) {
    bool d = glfwGetKey(window, k) == GLFW_PRESS, was = input.down[k];
    input.down[k] = d;
    return d && !was;
  };
  float f = key(GLFW_KEY_W) - key(GLFW_KEY_S), r = key(GLFW_KEY_D) - key(GLFW_KEY_A), u = key(GLFW_KEY_E) - key(GLFW_KEY_Q);
  if (f != 0 || r != 0 || u != 0) {
    leaveSnap();
    flyMove(camera, f, r, u, dt);
  }
  if (pressed(GLFW_KEY_R)) state.resetView = true;
  if (pressed(GLFW_KEY_P)) state.screenshot = true;
  if (pressed(GLFW_KEY_O)) camera.orbit = !camera.orbit;
  if (pressed(GLFW_KEY_H)) rs.compose.mode = rs.compose.mode == ComposeMode::Colour ? ComposeMode::HitHeatMap : ComposeMode::Colour;
  if (pressed(GLFW_KEY_1)) rs.water = WaterMode::Kept;
  if (pressed(GLFW_KEY_2)) rs.water = WaterMode::Removed;
  if (pressed(GLFW_KEY_3)) rs.water = WaterMode::Swapped;
  if (pressed(GLFW_KEY_C) && scene && !scene->cameras.empty())
    state.snappedCamera = (state.snappedCamera + 1) % int(scene->cameras.size());
}

}  // namespace

void attachInput(GLFWwindow* window, Input& input) {
  glfwSetWindowUserPointer(window, &input);
  glfwSetScrollCallback(window, onScroll);
}

void handleInput(GLFWwindow* window, Input& input, ViewerState& state, FlyCamera& camera, const ViewScene* scene, float dt) {
  ImGuiIO& io = ImGui::GetIO();
  auto leaveSnap = [&] {
    if (state.snappedCamera < 0 || !scene) return;
    camera = flyFromCamera(scene->cameras[size_t(state.snappedCamera)].second, camera);
    state.snappedCamera = -1;
  };
  if (!io.WantCaptureKeyboard) handleKeys(window, input, state, camera, scene, dt, leaveSnap);
  double mx, my;
  glfwGetCursorPos(window, &mx, &my);
  bool rightDown = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS && !io.WantCaptureMouse;
  if (rightDown && input.looking && (mx != input.lastX || my != input.lastY)) {
    leaveSnap();
    flyLook(camera, -float(mx - input.lastX) * 0.005f, -float(my - input.lastY) * 0.005f);
  }
  input.looking = rightDown;
  input.lastX = mx;
  input.lastY = my;
  if (input.wheel != 0 && !io.WantCaptureMouse) camera.speed *= std::pow(1.2f, input.wheel);
  input.wheel = 0;
}

}  // namespace refrax
