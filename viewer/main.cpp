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

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "engine/app/cli.h"
#include "engine/base/error.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/model/open_model.h"
#include "engine/surface/builtin_surface_spec.h"
#include "engine/surface/gltf_surface.h"
#include "engine/view/fly_camera.h"
#include "engine/view/frame_clock.h"
#include "engine/view/view_camera.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_timer.h"
#include "viewer/benchmark.h"
#include "engine/frame/frame_renderer.h"
#include "viewer/imgui_layer.h"
#include "viewer/input.h"
#include "viewer/panels.h"
#include "viewer/present.h"
#include "viewer/surface_view.h"
#include "viewer/swapchain.h"
#include "viewer/viewer_options.h"

using namespace refrax;

namespace {

const float kBackground[3] = {0.05f, 0.05f, 0.08f};

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

// The built-in surface shown with nothing loaded (--surface), before the panel changes it.
BuiltinSurface fallbackSurface(const ViewerOptions& o) { return BuiltinSurface{o.surface, 0.0f, 0.03f, 0.6f, 30.0f}; }

// The files the options name, read (or at least checked) before a window opens, so each is
// one clear error with or without a display.
struct ViewerInputs {
  long defaultK = long(kDefaultKBuffer);
  std::optional<GaussianSet> plyGaussians;
};
ViewerInputs readInputs(const ViewerOptions& o) {
  ViewerInputs in;
  // K changes only the speed, not the image: a run trained with a smaller K opens at the default.
  if (!o.runDir.empty()) in.defaultK = std::max(in.defaultK, long(readRunConfig(o.runDir).kBuffer));  // also: a folder that is not a run
  if (!o.ply.empty()) in.plyGaussians = readGaussiansPly(o.ply);
  if (isMeshPath(o.water)) readSurfaceGltf(o.water);
  surfaceHeightFunction(fallbackSurface(o));  // an unknown --surface
  return in;
}

GLFWwindow* openWindow(const ViewerOptions& o) {
  if (!glfwInit())
    fail("no display to open a window on (set DISPLAY, or run under xvfb-run); for images without a window use `refrax render`");
  if (!glfwVulkanSupported()) fail("GLFW found no Vulkan loader for windows");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  GLFWwindow* window = glfwCreateWindow(o.width, o.height, "refrax-view", nullptr, nullptr);
  if (!window) fail("could not open a window");
  return window;
}

std::unique_ptr<Context> openViewerContext(const ViewerOptions& o) {
  ContextOptions co;
  co.device = o.device;
  co.trace = o.trace;
  co.validation = o.validation;
  co.verbose = true;
  uint32_t nExt = 0;
  const char** ext = glfwGetRequiredInstanceExtensions(&nExt);
  co.extraInstanceExtensions.assign(ext, ext + nExt);
  co.extraDeviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  return createContext(co);
}

std::unique_ptr<ViewScene> openScene(Context& ctx, const ViewerOptions& o, ViewerInputs& in, uint32_t K) {
  if (!o.runDir.empty()) {
    auto scene = openRunScene(ctx, o.runDir, K);
    std::printf("refrax-view: loaded step %d (%s)\n", scene->model->step, scene->watch.taken.c_str());
    std::fflush(stdout);
    return scene;
  }
  if (!o.ply.empty()) return openPlyScene(ctx, o.ply, std::move(*in.plyGaussians), K, o.domain, o.waterHeight, o.ior.value_or(kPlyIor));
  return nullptr;
}

// The render settings a scene opens with: the run's (its IOR, lattice, SH degree), then the flags.
void initialRenderSettings(RenderSettings& rs, const ViewerOptions& o, const ViewScene* scene) {
  rs.swap = BuiltinSurface{"flat", 0.0f, 0.02f, 0.5f, 0.0f};
  if (scene) {
    rs = sceneRenderSettings(*scene);  // as `refrax render` opens it
    if (o.ior) rs.ior = *o.ior;
    applyWaterSpec(o.water.empty() ? (scene->model ? "keep" : "remove") : o.water, scene->waterHeight, rs);
  }
  if (o.levels) rs.subdivisionLevels = *o.levels;
  if (o.shDegree) rs.shDegree = *o.shDegree;
  rs.minTransmittance = o.minTransmittance;
  rs.exactWater = o.exactWater;
  rs.tiledTrace = o.tiledTrace;
  rs.walkGrid = o.walkGrid;
  if (o.bakeCells) rs.bakeCells = o.bakeCells;
  if (o.heatmap) rs.compose.mode = ComposeMode::HitHeatMap;
  rs.compose.heatFullScale = o.heatScale;
}

ViewerState initialState(const ViewerOptions& o, const ViewScene* scene, long K) {
  ViewerState state;
  state.K = int(K);
  initialRenderSettings(state.render, o, scene);
  if (scene && !o.view.empty()) state.snappedCamera = findCamera(*scene, o.view);
  // Without a camera given, open where the test views are seen from (a free camera outside
  // a top-down rig sees a trained scene's floaters): the first test camera, else the first.
  else if (scene && !o.cameraGiven && !scene->cameras.empty()) {
    state.snappedCamera = 0;
    for (size_t i = 0; i < scene->cameras.size(); i++)
      if (scene->cameras[i].first == "test 000") state.snappedCamera = int(i);
  }
  std::string show = o.mode.empty() ? (scene ? "gaussians" : "normals") : o.mode;
  state.show = show == "gaussians" ? ShowMode::Gaussians : show == "wireframe" ? ShowMode::SurfaceWireframe : ShowMode::SurfaceNormals;
  return state;
}

// What one frame loop iteration works with, apart from the window and the device.
struct Viewer {
  Context* ctx = nullptr;
  GLFWwindow* window = nullptr;
  Swapchain sc;
  std::unique_ptr<ViewScene> scene;
  ViewerState state;
  FlyCamera home, camera;
  BuiltinSurface fallbackSurface;  // shown with nothing loaded
  Input input;
  FrameSync frame;
  GpuTimer timer;
  RenderTarget target;
  FrameRenderer renderer;
  SurfaceView surfaceView;
  Buffer surfacePixels;
  FrameStats stats;
  Benchmark bench;
  FrameClock frameClock;
  long frameIndex = 0;
  std::chrono::steady_clock::time_point last, firstFrameShown;
};

// The frame's UI, and what it asked for before the render (reset, checkpoints, K, resolution).
void updateUi(Viewer& v) {
  beginImguiFrame();
  if (v.scene) drawPanel(v.ctx->caps.name, *v.scene, v.state, v.camera, v.stats);
  else drawSurfacePanel(v.ctx->caps.name, v.fallbackSurface, v.state, v.stats);
  ImGui::Render();
  if (v.state.resetView) {
    v.camera = v.home;
    v.state.snappedCamera = -1;
    v.state.resetView = false;
  }
  if (v.scene && v.state.followCheckpoints) pollRunCheckpoint(*v.scene);
  if (v.scene) setTracerK(*v.scene, uint32_t(v.state.K));
  if (v.state.autoResolution)
    v.state.resolutionScale = nextResolutionScale(v.state.resolutionScale, v.stats.frameMs, v.state.targetFrameMs);
}

// The render's size and camera: the window scaled by the resolution, a dataset camera keeping its aspect.
Camera frameCamera(Viewer& v) {
  uint32_t rw = std::max(1u, uint32_t(float(v.sc.extent.width) * v.state.resolutionScale));
  uint32_t rh = std::max(1u, uint32_t(float(v.sc.extent.height) * v.state.resolutionScale));
  if (v.scene && v.state.snappedCamera >= 0) {
    const Camera& c = v.scene->cameras[size_t(v.state.snappedCamera)].second;
    double s = std::min(double(rw) / c.width, double(rh) / c.height);
    rw = std::max(1u, uint32_t(c.width * s + 0.5));
    rh = std::max(1u, uint32_t(c.height * s + 0.5));
    return resizedCamera(c, int(rw), int(rh));
  }
  return cameraFromFly(v.camera, int(rw), int(rh));
}

bool showsGaussians(const Viewer& v) { return v.scene && v.state.show == ShowMode::Gaussians; }

// The Gaussians' pre-pass (the exact water's trace) or the surface preview, before recording.
const SurfacePreview* prepareRender(Viewer& v, const Camera& view) {
  ensureTarget(*v.ctx, v.target, uint32_t(view.width), uint32_t(view.height));
  v.stats.width = uint32_t(view.width);
  v.stats.height = uint32_t(view.height);
  if (showsGaussians(v)) {
    prepareFrame(v.renderer, *v.scene, view, v.state.render);
    return nullptr;
  }
  const SurfacePreview* preview = &surfaceViewFor(*v.ctx, v.surfaceView, v.scene.get(), v.state.render, v.fallbackSurface);
  if (v.surfacePixels.size < VkDeviceSize(view.width) * view.height * 4) {
    vkDeviceWaitIdle(v.ctx->device);
    v.surfacePixels = createBuffer(*v.ctx, VkDeviceSize(view.width) * view.height * 4);
  }
  return preview;
}

const Buffer& framePixels(const Viewer& v) { return showsGaussians(v) ? v.renderer.pixels : v.surfacePixels; }

void recordFrame(Viewer& v, VkCommandBuffer cb, const Camera& view, const SurfacePreview* preview, uint32_t imageIndex) {
  REFRAX_VK(vkResetCommandBuffer(cb, 0));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  REFRAX_VK(vkBeginCommandBuffer(cb, &bi));
  cmdTimerStart(cb, v.timer);
  if (showsGaussians(v)) {
    cmdRenderFrame(cb, v.renderer, *v.scene, view, v.state.render, v.timer);
  } else {
    FlyCamera look = v.state.snappedCamera >= 0 && v.scene ? flyFromCamera(view, v.camera) : v.camera;
    PreviewMode mode = v.state.show == ShowMode::SurfaceWireframe ? PreviewMode::Wireframe : PreviewMode::Normals;
    cmdRenderSurfacePreview(cb, *preview, look, uint32_t(view.width), uint32_t(view.height), mode, kBackground, v.surfacePixels);
    cmdTimerStamp(cb, v.timer, "surface");
  }
  cmdPresentPixels(cb, framePixels(v), v.target, v.sc.images[imageIndex], v.sc.extent, kBackground);
  cmdTimerStamp(cb, v.timer, "blit");
  cmdDrawImgui(cb, v.sc, imageIndex);
  cmdTimerStamp(cb, v.timer, "ui");
  REFRAX_VK(vkEndCommandBuffer(cb));
}

// Acquires a swapchain image, records, submits and presents, and waits for the frame.
// False when the swapchain was out of date (recreated; the frame is skipped).
bool renderAndPresent(Viewer& v, const Camera& view, const SurfacePreview* preview) {
  Context& ctx = *v.ctx;
  FrameSync& f = v.frame;
  REFRAX_VK(vkWaitForFences(ctx.device, 1, &f.fence, VK_TRUE, UINT64_MAX));
  uint32_t imageIndex = 0;
  VkResult acq = vkAcquireNextImageKHR(ctx.device, v.sc.swapchain, UINT64_MAX, f.imageReady, VK_NULL_HANDLE, &imageIndex);
  if (acq == VK_ERROR_OUT_OF_DATE_KHR) {
    createSwapchain(ctx, v.window, v.sc);
    return false;
  }
  if (acq != VK_SUCCESS && acq != VK_SUBOPTIMAL_KHR) REFRAX_VK(acq);
  REFRAX_VK(vkResetFences(ctx.device, 1, &f.fence));
  recordFrame(v, f.cmd, view, preview, imageIndex);
  VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.waitSemaphoreCount = 1;
  si.pWaitSemaphores = &f.imageReady;
  si.pWaitDstStageMask = &waitStage;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &f.cmd;
  si.signalSemaphoreCount = 1;
  si.pSignalSemaphores = &f.renderDone;
  REFRAX_VK(vkQueueSubmit(ctx.queue, 1, &si, f.fence));
  VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  pi.waitSemaphoreCount = 1;
  pi.pWaitSemaphores = &f.renderDone;
  pi.swapchainCount = 1;
  pi.pSwapchains = &v.sc.swapchain;
  pi.pImageIndices = &imageIndex;
  VkResult pr = vkQueuePresentKHR(ctx.queue, &pi);
  if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR) createSwapchain(ctx, v.window, v.sc);
  else if (pr != VK_SUCCESS) REFRAX_VK(pr);
  REFRAX_VK(vkWaitForFences(ctx.device, 1, &f.fence, VK_TRUE, UINT64_MAX));
  return true;
}

// After a presented frame: its stage times, the benchmark's sums, a screenshot (P), and
// whether --frames (and --min-seconds) are done.
bool frameDone(Viewer& v, const ViewerOptions& o) {
  v.stats.stageMs = showsGaussians(v) ? v.renderer.surfaceMs : std::vector<std::pair<std::string, double>>{};
  for (auto& s : readTimer(v.timer)) v.stats.stageMs.push_back(s);
  v.frameIndex++;
  if (v.frameIndex > v.bench.warmup) {
    addStages(v.bench, v.stats.stageMs);
    v.bench.frames++;
  }
  const Buffer& pixels = framePixels(v);
  if (v.state.screenshot) {
    char name[64];
    std::snprintf(name, sizeof name, "refrax-view-%05ld.png", v.frameIndex);
    saveScreenshot(*v.ctx, pixels, v.stats.width, v.stats.height, name);
    v.state.screenshot = false;
  }
  // --min-seconds counts from the first frame, after the pipelines compiled.
  if (v.frameIndex == 1) v.firstFrameShown = std::chrono::steady_clock::now();
  const double secondsSinceFirst = std::chrono::duration<double>(std::chrono::steady_clock::now() - v.firstFrameShown).count();
  if (o.frames == 0 || v.frameIndex < o.frames || secondsSinceFirst < o.minSeconds) return false;
  if (!o.screenshot.empty()) saveScreenshot(*v.ctx, pixels, v.stats.width, v.stats.height, o.screenshot);
  std::printf("rendered %ld frames at %ux%u, last %.1f ms\n", v.frameIndex, v.stats.width, v.stats.height, v.stats.frameMs);
  return true;
}

// One iteration of the window's loop; false once the run is done.
bool viewerFrame(Viewer& v, const ViewerOptions& o) {
  glfwPollEvents();
  auto now = std::chrono::steady_clock::now();
  float dt = std::chrono::duration<float>(now - v.last).count();
  v.last = now;
  addFrameInterval(v.frameClock, dt * 1e3);  // engine/view/frame_clock.h: skips the setup's interval
  v.stats.frameMs = v.frameClock.meanMs;
  v.stats.fps = v.frameClock.fps();
  if (v.frameIndex == v.bench.warmup) v.bench.wallMs = 0;
  else if (v.frameIndex > v.bench.warmup) v.bench.wallMs += dt * 1e3;
  handleInput(v.window, v.input, v.state, v.camera, v.scene.get(), dt);
  updateUi(v);
  Camera view = frameCamera(v);
  const SurfacePreview* preview = prepareRender(v, view);
  if (!renderAndPresent(v, view, preview)) return true;
  return !frameDone(v, o);
}

int runViewer(const cli::Args& args) {
  // Everything about the inputs that can be checked without a window, first.
  const ViewerOptions o = parseViewerOptions(args);
  ViewerInputs inputs = readInputs(o);
  const long K = o.k.value_or(inputs.defaultK);
  struct GlfwGuard {
    ~GlfwGuard() { glfwTerminate(); }
  } glfwGuard;
  GLFWwindow* window = openWindow(o);
  auto ctx = openViewerContext(o);  // before the viewer's buffers, which it outlives
  Viewer v;
  v.window = window;
  v.ctx = ctx.get();
  v.scene = openScene(*ctx, o, inputs, uint32_t(K));
  v.state = initialState(o, v.scene.get(), K);
  // Slow devices hold a usable frame rate at a lower resolution; screenshots and benchmarks
  // keep the window's size (viewer_options.h).
  v.state.autoResolution = o.autoResolution.value_or(ctx->caps.type == VK_PHYSICAL_DEVICE_TYPE_CPU && o.frames == 0);
  v.state.targetFrameMs = float(1000.0 / o.targetFps);
  v.fallbackSurface = fallbackSurface(o);
  v.home = v.camera = o.home;
  createSurface(*ctx, v.window, v.sc);
  createSwapchain(*ctx, v.window, v.sc);
  ImguiLayer imgui = createImguiLayer(*ctx, v.window, v.sc);
  attachInput(v.window, v.input);
  v.frame = createFrameSync(*ctx);
  createTimer(*ctx, v.timer, 16);
  v.renderer = createFrameRenderer(*ctx);
  v.bench.warmup = std::min<long>(5, o.frames / 4);
  v.last = v.firstFrameShown = std::chrono::steady_clock::now();

  while (!glfwWindowShouldClose(v.window) && viewerFrame(v, o)) {
  }
  if (o.benchmark && v.bench.frames > 0) {
    // The wall time of the last frame is only known at the next loop start: add it here.
    v.bench.wallMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - v.last).count();
    printBenchmark(*ctx, v.bench, v.scene.get(), v.state, v.stats, v.renderer);
  }

  vkDeviceWaitIdle(ctx->device);
  destroyImguiLayer(*ctx, imgui);
  destroyFrameSync(*ctx, v.frame);
  destroySwapchain(*ctx, v.sc, true);
  glfwDestroyWindow(v.window);
  int messages = ctx->validationMessageCount.load();
  if (ctx->validation) std::printf("validation messages: %d\n", messages);
  return messages == 0 ? 0 : 1;
}

cli::Command viewerCommand() {
  return {"refrax-view", "interactive viewer: fly camera, water on/removed/swapped, per-stage timings",
          "refrax-view [RUN | --ply FILE] [options]", viewerOptionList(), runViewer};
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
