// refrax-view: an interactive window over Refrax renders. Opens a training run (its newest
// checkpoint, followed as training writes new ones) or a 3DGS PLY, and traces the Gaussians
// through the learned water, with the water removed, or through a built-in surface swapped in.
// Fly camera (WASD/QE, right-drag to look, wheel for speed), O orbit, R reset, C next dataset
// camera, 1/2/3 water kept/removed/swapped, H hit-count heat map, P screenshot; Dear ImGui
// panels with the controls and per-stage GPU timings. `--frames N` renders N frames and exits
// (with `--screenshot FILE` saving the last render as PNG, with `--benchmark` printing FPS and
// GPU ms per stage).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "engine/surface/builtin_surface_spec.h"
#include "engine/base/error.h"
#include "engine/view/fly_camera.h"
#include "engine/surface/gltf_surface.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/model/open_model.h"
#include "engine/view/frame_clock.h"
#include "engine/view/view_camera.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_timer.h"
#include "engine/app/cli.h"
#include "viewer/frame_renderer.h"
#include "viewer/panels.h"
#include "viewer/present.h"
#include "viewer/surface_view.h"
#include "viewer/swapchain.h"

using namespace refrax;

namespace {

struct Input {
  bool looking = false;
  double lastX = 0, lastY = 0;
  float wheel = 0;
  std::map<int, bool> down;  // keys held last frame (edge detection)
};

void onScroll(GLFWwindow* w, double, double dy) {
  static_cast<Input*>(glfwGetWindowUserPointer(w))->wheel += float(dy);
  ImGui_ImplGlfw_ScrollCallback(w, 0, dy);
}

// Per-stage GPU ms and wall time of the frames after a warm-up (lavapipe compiles each
// pipeline on first use), for --benchmark.
struct Benchmark {
  long warmup = 0, frames = 0;
  double wallMs = 0;
  std::map<std::string, double> stageMs;
  std::vector<std::string> order;
};

void addStages(Benchmark& b, const std::vector<std::pair<std::string, double>>& stages) {
  for (const auto& [name, ms] : stages) {
    if (!b.stageMs.count(name)) b.order.push_back(name);
    b.stageMs[name] += ms;
  }
}

// A dataset camera named SPLIT:INDEX.
int findCamera(const ViewScene& scene, const std::string& spec) {
  auto colon = spec.find(':');
  if (colon == std::string::npos) fail("--view must be SPLIT:INDEX (e.g. test:0)");
  char* end = nullptr;
  long index = std::strtol(spec.c_str() + colon + 1, &end, 10);
  if (colon + 1 == spec.size() || *end || index < 0) fail("--view must be SPLIT:INDEX (e.g. test:0)");
  char name[64];
  std::snprintf(name, sizeof name, "%s %03ld", spec.substr(0, colon).c_str(), index);
  for (size_t i = 0; i < scene.cameras.size(); i++)
    if (scene.cameras[i].first == name) return int(i);
  fail("--view " + spec + ": the dataset has no such camera");
}

std::optional<SurfaceDomain> parseDomain(const std::string& text) {
  if (text.empty()) return std::nullopt;
  SurfaceDomain d;
  char tail;
  if (std::sscanf(text.c_str(), "%f,%f,%f,%f%c", &d.x0, &d.y0, &d.x1, &d.y1, &tail) != 4) fail("--domain must be x0,y0,x1,y1");
  return d;
}

bool isMeshFile(const std::string& path) {
  auto ends = [&](const char* e) { return path.size() > std::strlen(e) && path.compare(path.size() - std::strlen(e), std::strlen(e), e) == 0; };
  return ends(".gltf") || ends(".glb");
}

// --water: keep, remove, a built-in surface or a glTF mesh to swap in.
void applyWaterOption(const std::string& water, float level, RenderSettings& r) {
  if (water == "keep") r.water = WaterMode::Kept;
  else if (water == "remove") r.water = WaterMode::Removed;
  else if (isMeshFile(water)) {
    r.water = WaterMode::Swapped;
    r.swapMesh = water;
  } else {
    r.water = WaterMode::Swapped;
    r.swap = parseBuiltinSurface(water, level);
  }
}

int runViewer(const cli::Args& args) {
  namespace fs = std::filesystem;
  // Everything about the inputs that can be checked without a window, first.
  std::string runDir = args.positional.empty() ? "" : args.positional[0], ply = args.get("ply");
  if (args.positional.size() > 1) fail("refrax-view takes one run folder");
  if (!runDir.empty() && !ply.empty()) fail("give a run folder or --ply FILE, not both");
  long defaultK = long(kDefaultKBuffer);
  // K changes only the speed, not the image: a run trained with a smaller K opens at the default.
  if (!runDir.empty()) defaultK = std::max(defaultK, long(readRunConfig(runDir).kBuffer));  // also one clear error for a folder that is not a run
  std::optional<GaussianSet> plyGaussians;
  if (!ply.empty()) plyGaussians = readGaussiansPly(ply);
  if (isMeshFile(args.get("water"))) readSurfaceGltf(args.get("water"));  // one clear error before the window
  const long frames = args.getInt("frames", 0);
  const std::string screenshot = args.get("screenshot");
  const bool benchmark = args.has("benchmark");
  if (frames < 0) fail("--frames must be positive");
  if (!screenshot.empty() && frames == 0) fail("--screenshot needs --frames N");
  if (benchmark && frames == 0) fail("--benchmark needs --frames N");
  // Scripts that watch a training run need wall time, not a frame count: a fast device renders
  // any fixed count before the 1 s checkpoint poll comes round.
  const double minSeconds = args.getDouble("min-seconds", 0.0);
  if (!(minSeconds >= 0.0 && minSeconds <= 86400.0)) fail("--min-seconds must be between 0 and 86400");
  if (minSeconds > 0.0 && frames == 0) fail("--min-seconds needs --frames N");
  const std::string gaussianTrace = args.get("gaussian-trace", "tiles");
  if (gaussianTrace != "tiles" && gaussianTrace != "bvh") fail("--gaussian-trace must be tiles or bvh");
  const bool tiledTrace = gaussianTrace == "tiles";
  const std::string waterTrace = args.get("water-trace", "grid");
  if (waterTrace != "grid" && waterTrace != "bvh") fail("--water-trace must be grid or bvh");
  long K = args.getInt("k", defaultK);
  if (K < 1 || K > 64) fail("--k must be between 1 and 64");
  if (args.has("size")) args.getIntIn("size", 0, 1, 8192);  // --size 0 is an error, not the default window
  long size = args.getInt("size", 0);
  int winW = int(size > 0 ? size : args.getIntIn("width", 800, 1, 8192)), winH = int(size > 0 ? size : args.getIntIn("height", 600, 1, 8192));
  FlyCamera home = parseLookAt(args.get("camera", "0,-2.2,1.6,0,0,0"));
  if (args.has("fov")) {
    double fov = args.getDouble("fov", 45);
    if (!(fov > 0 && fov < 180)) fail("--fov must be in (0, 180) degrees");
    home.tanHalfFovY = float(std::tan(fov * M_PI / 360));
  }
  FlyCamera camera = home;

  if (!glfwInit())
    fail("no display to open a window on (set DISPLAY, or run under xvfb-run); for images without a window use `refrax render`");
  struct GlfwGuard {
    ~GlfwGuard() { glfwTerminate(); }
  } glfwGuard;
  if (!glfwVulkanSupported()) fail("GLFW found no Vulkan loader for windows");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  GLFWwindow* window = glfwCreateWindow(winW, winH, "refrax-view", nullptr, nullptr);
  if (!window) fail("could not open a window");

  ContextOptions co;
  co.device = args.get("device");
  co.trace = args.get("trace");
  co.validation = args.has("validation");
  co.verbose = true;
  uint32_t nExt = 0;
  const char** ext = glfwGetRequiredInstanceExtensions(&nExt);
  co.extraInstanceExtensions.assign(ext, ext + nExt);
  co.extraDeviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  auto ctx = createContext(co);

  // The scene, and the render settings it starts from.
  std::unique_ptr<ViewScene> scene;
  ViewerState state;
  state.K = int(K);
  if (!runDir.empty()) scene = openRunScene(*ctx, runDir, uint32_t(K));
  if (!ply.empty())
    scene = openPlyScene(*ctx, ply, std::move(*plyGaussians), uint32_t(K), parseDomain(args.get("domain")), float(args.getDouble("water-height", 0)),
                         float(args.getDouble("ior", 1.33)));
  BuiltinSurface fallbackSurface{"sine", 0.0f, 0.03f, 0.6f, 30.0f};
  if (args.has("surface")) fallbackSurface.kind = args.get("surface");
  surfaceHeightFunction(fallbackSurface);
  RenderSettings& rs = state.render;
  rs.swap = BuiltinSurface{"flat", 0.0f, 0.02f, 0.5f, 0.0f};
  if (scene) {
    rs.swap.height = scene->waterHeight;
    rs.ior = float(args.getDouble("ior", scene->ior));
    rs.shDegree = scene->model ? shDegreeAt(scene->model->config, std::max(1, scene->model->step)) : scene->maxShDegree;
    if (scene->model) {
      rs.gridCells = scene->model->config.gridCells;
      rs.subdivisionLevels = scene->model->config.subdivisionLevels;
      // The baked mesh's vertices on the finest lattice the trainer's subdivision evaluates H at.
      rs.bakeCells = scene->model->config.gridCells << scene->model->config.subdivisionLevels;
    }
    applyWaterOption(args.get("water", scene->model ? "keep" : "remove"), scene->waterHeight, rs);
    if (args.has("view")) state.snappedCamera = findCamera(*scene, args.get("view"));
    // Without a camera given, open where the test views are seen from (a free camera outside
    // a top-down rig sees a trained scene's floaters): the first test camera, else the first.
    else if (!args.has("camera") && !scene->cameras.empty()) {
      state.snappedCamera = 0;
      for (size_t i = 0; i < scene->cameras.size(); i++)
        if (scene->cameras[i].first == "test 000") state.snappedCamera = int(i);
    }
  }
  if (args.has("levels")) rs.subdivisionLevels = uint32_t(std::clamp(args.getInt("levels", 2), 0L, 8L));
  if (args.has("sh")) rs.shDegree = uint32_t(std::clamp(args.getInt("sh", 3), 0L, 3L));
  if (args.has("min-transmittance")) {
    rs.minTransmittance = float(args.getDouble("min-transmittance", 1e-3));
    if (!(rs.minTransmittance >= 0 && rs.minTransmittance < 1)) fail("--min-transmittance must be in [0, 1)");
  }
  rs.exactWater = args.has("exact-water");
  rs.tiledTrace = tiledTrace;
  rs.walkGrid = waterTrace == "grid";
  if (args.has("bake-cells")) {
    long cells = args.getInt("bake-cells", 256);
    if (cells < 1 || cells > 4096) fail("--bake-cells must be between 1 and 4096");
    rs.bakeCells = uint32_t(cells);
  }
  if (args.has("heatmap")) rs.compose.mode = ComposeMode::HitHeatMap;
  rs.compose.heatFullScale = float(args.getDouble("heat-scale", 64));
  if (!(rs.compose.heatFullScale > 0)) fail("--heat-scale must be a positive number of hits");
  std::string show = args.get("mode", scene ? "gaussians" : "normals");
  if (show == "gaussians" && !scene) fail("--mode gaussians needs a run folder or --ply");
  state.show = show == "gaussians" ? ShowMode::Gaussians : show == "wireframe" ? ShowMode::SurfaceWireframe : show == "normals" ? ShowMode::SurfaceNormals
                                                                                                                    : (fail("--mode must be gaussians, normals or wireframe"), ShowMode::Gaussians);

  Swapchain sc;
  createSurface(*ctx, window, sc);
  createSwapchain(*ctx, window, sc);

  // Dear ImGui with its Vulkan backend, its entry points loaded through volk's instance.
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplVulkan_LoadFunctions(
      [](const char* name, void* inst) { return vkGetInstanceProcAddr(*static_cast<VkInstance*>(inst), name); }, &ctx->instance);
  ImGui_ImplGlfw_InitForVulkan(window, true);
  VkDescriptorPool imguiPool;
  VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8};
  VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  dpi.maxSets = 8;
  dpi.poolSizeCount = 1;
  dpi.pPoolSizes = &poolSize;
  REFRAX_VK(vkCreateDescriptorPool(ctx->device, &dpi, nullptr, &imguiPool));
  ImGui_ImplVulkan_InitInfo ii{};
  ii.Instance = ctx->instance;
  ii.PhysicalDevice = ctx->physical;
  ii.Device = ctx->device;
  ii.QueueFamily = ctx->queueFamily;
  ii.Queue = ctx->queue;
  ii.DescriptorPool = imguiPool;
  ii.MinImageCount = sc.minImageCount;
  ii.ImageCount = uint32_t(sc.images.size());
  ii.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  ImGui_ImplVulkan_Init(&ii, sc.overlayPass);
  submitAndWait(*ctx, [](VkCommandBuffer cb) { ImGui_ImplVulkan_CreateFontsTexture(cb); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();

  Input input;
  glfwSetWindowUserPointer(window, &input);
  glfwSetScrollCallback(window, onScroll);

  FrameSync frame = createFrameSync(*ctx);
  GpuTimer timer;
  createTimer(*ctx, timer, 16);
  RenderTarget target;
  FrameRenderer renderer = createFrameRenderer(*ctx);
  SurfaceView surfaceView;
  Buffer surfacePixels;
  FrameStats stats;
  Benchmark bench;
  bench.warmup = std::min<long>(5, frames / 4);
  long frameIndex = 0;
  auto firstFrameShown = std::chrono::steady_clock::now();  // --min-seconds counts from the first frame, after pipeline compiles
  const float background[3] = {0.05f, 0.05f, 0.08f};
  auto last = std::chrono::steady_clock::now();
  FrameClock frameClock;

  while (!glfwWindowShouldClose(window)) {
    glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    float dt = std::chrono::duration<float>(now - last).count();
    last = now;
    addFrameInterval(frameClock, dt * 1e3);  // engine/view/frame_clock.h: skips the setup's interval
    stats.frameMs = frameClock.meanMs;
    stats.fps = frameClock.fps();
    if (frameIndex == bench.warmup) bench.wallMs = 0;
    else if (frameIndex > bench.warmup) bench.wallMs += dt * 1e3;

    // ---- input (ignored while ImGui has the mouse/keyboard); moving leaves a dataset camera
    ImGuiIO& io = ImGui::GetIO();
    auto leaveSnap = [&] {
      if (state.snappedCamera < 0 || !scene) return;
      camera = flyFromCamera(scene->cameras[size_t(state.snappedCamera)].second, camera);
      state.snappedCamera = -1;
    };
    if (!io.WantCaptureKeyboard) {
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
      if (pressed(GLFW_KEY_H))
        rs.compose.mode = rs.compose.mode == ComposeMode::Colour ? ComposeMode::HitHeatMap : ComposeMode::Colour;
      if (pressed(GLFW_KEY_1)) rs.water = WaterMode::Kept;
      if (pressed(GLFW_KEY_2)) rs.water = WaterMode::Removed;
      if (pressed(GLFW_KEY_3)) rs.water = WaterMode::Swapped;
      if (pressed(GLFW_KEY_C) && scene && !scene->cameras.empty())
        state.snappedCamera = (state.snappedCamera + 1) % int(scene->cameras.size());
    }
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

    // ---- UI
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (scene) {
      drawPanel(ctx->caps.name, *scene, state, camera, stats);
    } else {  // nothing loaded: the built-in surface by itself
      ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
      ImGui::Begin("Refrax");
      ImGui::Text("%s", ctx->caps.name.c_str());
      ImGui::Text("%.1f FPS (%.1f ms)  render %ux%u", stats.fps, stats.frameMs, stats.width, stats.height);
      const char* kinds[] = {"flat", "sine", "triangle"};
      int kind = fallbackSurface.kind == "flat" ? 0 : fallbackSurface.kind == "sine" ? 1 : 2;
      if (ImGui::Combo("surface", &kind, kinds, 3)) fallbackSurface.kind = kinds[kind];
      ImGui::SliderFloat("amplitude", &fallbackSurface.amplitude, 0.0f, 0.2f);
      ImGui::SliderFloat("wavelength", &fallbackSurface.wavelength, 0.05f, 2.0f);
      int show = int(state.show) - 1;
      const char* modes[] = {"normals", "wireframe"};
      if (ImGui::Combo("show", &show, modes, 2)) state.show = ShowMode(show + 1);
      if (ImGui::Button("reset view (R)")) state.resetView = true;
      ImGui::End();
    }
    ImGui::Render();

    if (state.resetView) {
      camera = home;
      state.snappedCamera = -1;
      state.resetView = false;
    }
    if (scene && state.followCheckpoints) pollRunCheckpoint(*scene);
    if (scene) setTracerK(*scene, uint32_t(state.K));
    if (state.autoResolution) state.resolutionScale = nextResolutionScale(state.resolutionScale, stats.frameMs, state.targetFrameMs);

    // ---- the render's size and camera (a dataset camera keeps its aspect)
    uint32_t rw = std::max(1u, uint32_t(float(sc.extent.width) * state.resolutionScale));
    uint32_t rh = std::max(1u, uint32_t(float(sc.extent.height) * state.resolutionScale));
    Camera view;
    if (scene && state.snappedCamera >= 0) {
      const Camera& c = scene->cameras[size_t(state.snappedCamera)].second;
      double s = std::min(double(rw) / c.width, double(rh) / c.height);
      rw = std::max(1u, uint32_t(c.width * s + 0.5));
      rh = std::max(1u, uint32_t(c.height * s + 0.5));
      view = resizedCamera(c, int(rw), int(rh));
    } else {
      view = cameraFromFly(camera, int(rw), int(rh));
    }
    ensureTarget(*ctx, target, rw, rh);
    stats.width = rw;
    stats.height = rh;
    const bool gaussians = scene && state.show == ShowMode::Gaussians;
    const SurfacePreview* preview = nullptr;
    if (gaussians) {
      prepareFrame(renderer, *scene, view, rs);
    } else {
      preview = &surfaceViewFor(*ctx, surfaceView, scene.get(), rs, fallbackSurface);
      if (surfacePixels.size < VkDeviceSize(rw) * rh * 4) {
        vkDeviceWaitIdle(ctx->device);
        surfacePixels = createBuffer(*ctx, VkDeviceSize(rw) * rh * 4);
      }
    }
    const Buffer& pixels = gaussians ? renderer.pixels : surfacePixels;

    // ---- frame
    REFRAX_VK(vkWaitForFences(ctx->device, 1, &frame.fence, VK_TRUE, UINT64_MAX));
    uint32_t imageIndex = 0;
    VkResult acq = vkAcquireNextImageKHR(ctx->device, sc.swapchain, UINT64_MAX, frame.imageReady, VK_NULL_HANDLE, &imageIndex);
    if (acq == VK_ERROR_OUT_OF_DATE_KHR) {
      createSwapchain(*ctx, window, sc);
      continue;
    }
    if (acq != VK_SUCCESS && acq != VK_SUBOPTIMAL_KHR) REFRAX_VK(acq);
    REFRAX_VK(vkResetFences(ctx->device, 1, &frame.fence));

    VkCommandBuffer cb = frame.cmd;
    REFRAX_VK(vkResetCommandBuffer(cb, 0));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    REFRAX_VK(vkBeginCommandBuffer(cb, &bi));
    cmdTimerStart(cb, timer);
    if (gaussians) {
      cmdRenderFrame(cb, renderer, *scene, view, rs, timer);
    } else {
      FlyCamera look = state.snappedCamera >= 0 && scene ? flyFromCamera(view, camera) : camera;
      PreviewMode mode = state.show == ShowMode::SurfaceWireframe ? PreviewMode::Wireframe : PreviewMode::Normals;
      cmdRenderSurfacePreview(cb, *preview, look, rw, rh, mode, background, surfacePixels);
      cmdTimerStamp(cb, timer, "surface");
    }
    cmdPresentPixels(cb, pixels, target, sc.images[imageIndex], sc.extent, background);
    cmdTimerStamp(cb, timer, "blit");
    VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rp.renderPass = sc.overlayPass;
    rp.framebuffer = sc.framebuffers[imageIndex];
    rp.renderArea.extent = sc.extent;
    vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cb);
    vkCmdEndRenderPass(cb);
    cmdTimerStamp(cb, timer, "ui");
    REFRAX_VK(vkEndCommandBuffer(cb));

    VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &frame.imageReady;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &frame.renderDone;
    REFRAX_VK(vkQueueSubmit(ctx->queue, 1, &si, frame.fence));
    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &frame.renderDone;
    pi.swapchainCount = 1;
    pi.pSwapchains = &sc.swapchain;
    pi.pImageIndices = &imageIndex;
    VkResult pr = vkQueuePresentKHR(ctx->queue, &pi);
    if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR) createSwapchain(*ctx, window, sc);
    else if (pr != VK_SUCCESS) REFRAX_VK(pr);

    REFRAX_VK(vkWaitForFences(ctx->device, 1, &frame.fence, VK_TRUE, UINT64_MAX));
    stats.stageMs = gaussians ? renderer.surfaceMs : std::vector<std::pair<std::string, double>>{};
    for (auto& s : readTimer(timer)) stats.stageMs.push_back(s);
    frameIndex++;
    if (frameIndex > bench.warmup) {
      addStages(bench, stats.stageMs);
      bench.frames++;
    }
    if (state.screenshot) {
      char name[64];
      std::snprintf(name, sizeof name, "refrax-view-%05ld.png", frameIndex);
      saveScreenshot(*ctx, pixels, rw, rh, name);
      state.screenshot = false;
    }
    if (frameIndex == 1) firstFrameShown = std::chrono::steady_clock::now();
    const double secondsSinceFirst = std::chrono::duration<double>(std::chrono::steady_clock::now() - firstFrameShown).count();
    if (frames > 0 && frameIndex >= frames && secondsSinceFirst >= minSeconds) {
      if (!screenshot.empty()) saveScreenshot(*ctx, pixels, rw, rh, screenshot);
      std::printf("rendered %ld frames at %ux%u, last %.1f ms\n", frameIndex, rw, rh, stats.frameMs);
      break;
    }
  }
  // The wall time of the last frame is only known at the next loop start: add it here.
  if (benchmark && bench.frames > 0) {
    bench.wallMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - last).count();
    std::printf("benchmark: %s | %s | %ux%u | %u Gaussians | water %s | %ld frames: %.2f FPS (%.1f ms/frame)\n", ctx->caps.name.c_str(),
                scene ? scene->source.c_str() : "surface", stats.width, stats.height, scene ? sceneGaussianCount(*scene) : 0,
                !scene || state.show != ShowMode::Gaussians ? "-" : effectiveWater(*scene, rs) == WaterMode::Kept ? "kept" : effectiveWater(*scene, rs) == WaterMode::Removed ? "removed" : "swapped",
                bench.frames, 1e3 * bench.frames / bench.wallMs, bench.wallMs / bench.frames);
    std::printf("benchmark GPU ms per frame:");
    for (const auto& name : bench.order) std::printf(" %s %.2f", name.c_str(), bench.stageMs[name] / bench.frames);
    std::printf("\n");
    if (scene && state.show == ShowMode::Gaussians) {  // what the trace cost depends on
      auto results = downloadVector<GpuTraceResult>(*ctx, renderer.results, size_t(stats.width) * stats.height);
      double hits = 0, rounds = 0;
      for (const auto& r : results) {
        hits += r.hits;
        rounds += r.rounds;
      }
      std::printf("benchmark trace: %s, K %u, min transmittance %g, %.1f hits and %.2f k-buffer rounds per ray\n",
                  rs.tiledTrace ? "tiles" : "bvh", scene->tracer.K, rs.minTransmittance, hits / double(results.size()),
                  rounds / double(results.size()));
      if (rs.tiledTrace && renderer.tiles) {
        TileStats t = readTileStats(*ctx, *renderer.tiles);
        std::printf("benchmark tiles: %u tiles of %ux%u rays, %.1f Gaussians listed per tile (max %u), %u over the list's %u; "
                    "%u blocks of %ux%u, %.1f listed per block, %u over %u\n",
                    t.tiles, kTileSide, kTileSide, t.meanListed, t.maxListed, t.overflowed, renderer.tiles->capacity, t.blocks, kBlockSide,
                    kBlockSide, t.meanBlockListed, t.blocksOverflowed, renderer.tiles->blockCapacity);
      }
    }
  }

  vkDeviceWaitIdle(ctx->device);
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  vkDestroyDescriptorPool(ctx->device, imguiPool, nullptr);
  destroyFrameSync(*ctx, frame);
  destroySwapchain(*ctx, sc, true);
  glfwDestroyWindow(window);
  int messages = ctx->validationMessageCount.load();
  if (ctx->validation) std::printf("validation messages: %d\n", messages);
  return messages == 0 ? 0 : 1;
}

cli::Command viewerCommand() {
  auto options = cli::deviceOptions();
  options.push_back({"ply", "FILE", "view a 3DGS PLY instead of a run folder", ""});
  options.push_back({"water", "MODE", "keep, remove, flat[:height], sine|triangle[:height:amplitude:wavelength:direction] or a .gltf/.glb mesh",
                     "keep (run), remove (PLY)"});
  options.push_back({"exact-water", "", "trace the water's subdivided proxy surface as training and refrax render do (slower)", ""});
  options.push_back({"bake-cells", "N", "cells per side of the baked water mesh (learned or built-in surface)",
                     "a run's grid cells << subdivision levels (its finest lattice), else 256"});
  options.push_back({"domain", "x0,y0,x1,y1", "with --ply: the water's extent", "the Gaussians' xy bounds + 10%"});
  options.push_back({"water-height", "Z", "with --ply: the water level of swapped-in surfaces", "0"});
  options.push_back({"ior", "N", "index of refraction of the water", "the run's (1.33)"});
  options.push_back({"levels", "K", "with --exact-water: subdivision levels of the water surface", "the run's"});
  options.push_back({"gaussian-trace", "KIND",
                     "tiles: each 8x8 pixel tile lists the Gaussians its rays can reach and its rays test only those (the same "
                     "image, faster on CPU devices); bvh: a ray-query traversal per ray, as training and refrax render",
                     "tiles"});
  options.push_back({"water-trace", "KIND",
                     "grid: the baked water (a height grid) is walked cell by cell; bvh: a ray query per ray through its BVH (the "
                     "same triangles; a glTF mesh always takes the BVH)",
                     "grid"});
  options.push_back({"k", "N", "k-buffer size of the Gaussian tracer", "the run's (16)"});
  options.push_back({"sh", "DEGREE", "spherical-harmonics degree (0-3)", "the checkpoint's"});
  options.push_back({"min-transmittance", "T", "stop blending a ray once its transmittance is below T (faster, less exact)", "0.001"});
  options.push_back({"heatmap", "", "show the hit-count heat map instead of colour", ""});
  options.push_back({"heat-scale", "HITS", "hits per pixel shown at the heat map's top colour", "64"});
  options.push_back({"view", "SPLIT:INDEX", "start at a dataset camera (e.g. test:0)", ""});
  options.push_back({"mode", "MODE", "gaussians, normals or wireframe (the last two: the surface alone)", "gaussians (normals without a scene)"});
  options.push_back({"surface", "KIND", "without a scene: built-in surface flat, sine or triangle", "sine"});
  options.push_back({"camera", "x,y,z,tx,ty,tz", "start camera position and target", "0,-2.2,1.6,0,0,0"});
  options.push_back({"fov", "DEG", "vertical field of view", "43.6"});
  options.push_back({"width", "PIXELS", "window width", "800"});
  options.push_back({"height", "PIXELS", "window height", "600"});
  options.push_back({"size", "PIXELS", "square window of this side (overrides --width/--height)", ""});
  options.push_back({"frames", "N", "render N frames, then exit", ""});
  options.push_back({"screenshot", "FILE", "with --frames: save the last render as PNG", ""});
  options.push_back({"benchmark", "", "with --frames: print FPS and GPU ms per stage (after a warm-up)", ""});
  options.push_back({"min-seconds", "S", "with --frames: keep rendering until S seconds after the first frame (e.g. to see a training run's next checkpoint)", "0"});
  return {"refrax-view", "interactive viewer: fly camera, water on/removed/swapped, per-stage timings",
          "refrax-view [RUN | --ply FILE] [options]", options, runViewer};
}

}  // namespace

int main(int argc, char** argv) {
  cli::Command command = viewerCommand();
  try {
    cli::Args args = cli::parseArgs(command, argc, argv, 1);
    if (args.has("help")) {
      cli::printHelp(command);
      return 0;
    }
    return runViewer(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "refrax-view: error: %s\n", e.what());
    return 1;
  }
}
