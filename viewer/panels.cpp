#include "viewer/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace refrax {

namespace {

void statsSection(const std::string& deviceName, const ViewScene& scene, const FrameStats& stats) {
  ImGui::Text("%s", deviceName.c_str());
  ImGui::Text("%.1f FPS (%.1f ms)  render %ux%u", stats.fps, stats.frameMs, stats.width, stats.height);
  double total = 0;
  for (const auto& s : stats.stageMs) {
    ImGui::Text("  %-10s %8.2f ms", s.first.c_str(), s.second);
    total += s.second;
  }
  ImGui::Text("  %-10s %8.2f ms", "GPU total", total);
  ImGui::Text("%u Gaussians", sceneGaussianCount(scene));
  if (sceneStep(scene) >= 0) ImGui::Text("step %d  %s", sceneStep(scene), scene.status.c_str());
  else ImGui::Text("%s", scene.status.c_str());
}

void waterSection(const ViewScene& scene, ViewerState& st) {
  RenderSettings& r = st.render;
  int water = int(r.water);
  bool learned = learnedWater(scene).has_value();
  ImGui::RadioButton("water kept", &water, int(WaterMode::Kept));
  ImGui::SameLine();
  ImGui::RadioButton("removed", &water, int(WaterMode::Removed));
  ImGui::SameLine();
  ImGui::RadioButton("swapped", &water, int(WaterMode::Swapped));
  r.water = WaterMode(water);
  if (r.water == WaterMode::Kept && !learned) ImGui::TextDisabled("(this model has no learned water)");
  if (r.water == WaterMode::Swapped) {
    const char* kinds[] = {"flat", "sine", "triangle", "glTF mesh"};
    int kind = !r.swapMesh.empty() ? 3 : r.swap.kind == "sine" ? 1 : r.swap.kind == "triangle" ? 2 : 0;
    static char path[512] = "";
    if (ImGui::Combo("surface", &kind, kinds, 4)) {
      if (kind < 3) {
        r.swap.kind = kinds[kind];
        r.swapMesh.clear();
      } else if (path[0]) {
        r.swapMesh = path;
      }
    }
    ImGui::InputText("glTF file", path, sizeof path);
    ImGui::SameLine();
    if (ImGui::Button("load") && path[0]) r.swapMesh = path;
    if (!r.swapMesh.empty()) ImGui::TextDisabled("%s", r.swapMesh.c_str());
    ImGui::SliderFloat("water level", &r.swap.height, scene.waterHeight - 0.5f, scene.waterHeight + 0.5f);
    if (r.swap.kind != "flat") {
      ImGui::SliderFloat("amplitude", &r.swap.amplitude, 0.0f, 0.2f);
      ImGui::SliderFloat("wavelength", &r.swap.wavelength, 0.05f, 2.0f);
      ImGui::SliderFloat("direction", &r.swap.directionDeg, 0.0f, 180.0f);
    }
  }
  ImGui::SliderFloat("IOR", &r.ior, 1.0f, 2.0f);
  ImGui::Checkbox("exact water (subdivided, as training)", &r.exactWater);
  if (r.exactWater) {
    int levels = int(r.subdivisionLevels);
    if (ImGui::SliderInt("subdivision levels", &levels, 0, 4)) r.subdivisionLevels = uint32_t(levels);
  } else {
    int cells = int(r.bakeCells);
    if (ImGui::SliderInt("baked cells per side", &cells, 16, 1024, "%d", ImGuiSliderFlags_Logarithmic)) r.bakeCells = uint32_t(cells);
  }
}

void renderSection(const ViewScene& scene, ViewerState& st) {
  RenderSettings& r = st.render;
  ImGui::SliderInt("K (k-buffer)", &st.K, 1, 32);
  ImGui::SliderFloat("min transmittance", &r.minTransmittance, 1e-4f, 0.5f, "%.4f", ImGuiSliderFlags_Logarithmic);
  ImGui::Checkbox("tiled trace (off: a BVH traversal per ray)", &r.tiledTrace);
  int sh = int(r.shDegree);
  if (ImGui::SliderInt("SH degree", &sh, 0, int(scene.maxShDegree))) r.shDegree = uint32_t(sh);
  bool heat = r.compose.mode == ComposeMode::HitHeatMap;
  if (ImGui::Checkbox("hit-count heat map", &heat)) r.compose.mode = heat ? ComposeMode::HitHeatMap : ComposeMode::Colour;
  if (heat) ImGui::SliderFloat("hits at top colour", &r.compose.heatFullScale, 1.0f, 256.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
  const char* shows[] = {"Gaussians", "surface normals", "surface wireframe"};
  int show = int(st.show);
  if (ImGui::Combo("show", &show, shows, 3)) st.show = ShowMode(show);
  ImGui::Checkbox("auto resolution", &st.autoResolution);
  if (st.autoResolution) ImGui::SliderFloat("target ms", &st.targetFrameMs, 16.0f, 1000.0f, "%.0f", ImGuiSliderFlags_Logarithmic);
  else ImGui::SliderFloat("resolution", &st.resolutionScale, 0.1f, 1.0f);
}

void cameraSection(const ViewScene& scene, ViewerState& st, FlyCamera& camera) {
  ImGui::SliderFloat("speed", &camera.speed, 0.01f, 10.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
  ImGui::Checkbox("orbit (O)", &camera.orbit);
  if (!scene.cameras.empty()) {
    const char* current = st.snappedCamera >= 0 ? scene.cameras[size_t(st.snappedCamera)].first.c_str() : "(fly camera)";
    if (ImGui::BeginCombo("dataset camera", current)) {
      for (size_t i = 0; i < scene.cameras.size(); i++)
        if (ImGui::Selectable(scene.cameras[i].first.c_str(), int(i) == st.snappedCamera)) st.snappedCamera = int(i);
      ImGui::EndCombo();
    }
  }
  if (ImGui::Button("reset view (R)")) st.resetView = true;
  ImGui::SameLine();
  if (ImGui::Button("screenshot (P)")) st.screenshot = true;
  if (!scene.runDir.empty()) ImGui::Checkbox("follow checkpoints", &st.followCheckpoints);
}

}  // namespace

void drawPanel(const std::string& deviceName, ViewScene& scene, ViewerState& state, FlyCamera& camera, const FrameStats& stats) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::Begin("Refrax");
  statsSection(deviceName, scene, stats);
  ImGui::Separator();
  waterSection(scene, state);
  ImGui::Separator();
  renderSection(scene, state);
  ImGui::Separator();
  cameraSection(scene, state, camera);
  ImGui::End();
}

void drawSurfacePanel(const std::string& deviceName, BuiltinSurface& surface, ViewerState& state, const FrameStats& stats) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::Begin("Refrax");
  ImGui::Text("%s", deviceName.c_str());
  ImGui::Text("%.1f FPS (%.1f ms)  render %ux%u", stats.fps, stats.frameMs, stats.width, stats.height);
  const char* kinds[] = {"flat", "sine", "triangle"};
  int kind = surface.kind == "flat" ? 0 : surface.kind == "sine" ? 1 : 2;
  if (ImGui::Combo("surface", &kind, kinds, 3)) surface.kind = kinds[kind];
  ImGui::SliderFloat("amplitude", &surface.amplitude, 0.0f, 0.2f);
  ImGui::SliderFloat("wavelength", &surface.wavelength, 0.05f, 2.0f);
  int show = int(state.show) - 1;
  const char* modes[] = {"normals", "wireframe"};
  if (ImGui::Combo("show", &show, modes, 2)) state.show = ShowMode(show + 1);
  if (ImGui::Button("reset view (R)")) state.resetView = true;
  ImGui::End();
}

float nextResolutionScale(float scale, double frameMs, float targetMs) {
  if (!(frameMs > 0)) return scale;
  // pixels ~ time: the side scales with the square root, at most 20% per frame
  float ratio = float(targetMs / frameMs);
  return std::clamp(scale * std::clamp(std::sqrt(ratio), 0.8f, 1.2f), 0.1f, 1.0f);
}

}  // namespace refrax
