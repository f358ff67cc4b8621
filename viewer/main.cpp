// refrax-view: an interactive window over Refrax renders. Fly camera (WASD/QE, right-drag
// to look, wheel for speed, O orbit, R reset, P screenshot), Dear ImGui panels with the
// controls and per-stage GPU timings. `--screenshot FILE --frames N` renders N frames in the
// window, saves the last render as PNG and exits (for tests and scripts).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include <chrono>
#include <cstdio>
#include <cstring>

#include "engine/builtin_surfaces.h"
#include "engine/error.h"
#include "engine/fly_camera.h"
#include "engine/grid_mesh.h"
#include "engine/io/image_io.h"
#include "engine/surface_preview.h"
#include "engine/vk_buffer.h"
#include "engine/vk_commands.h"
#include "engine/vk_context.h"
#include "engine/vk_image.h"
#include "engine/vk_timer.h"
#include "trainer/cli.h"
#include "viewer/swapchain.h"

using namespace refrax;

namespace {

struct ViewSettings {
  BuiltinSurface surface{"sine", 0.0f, 0.03f, 0.6f, 30.0f};
  int previewMode = 0;  // PreviewMode
  float resolutionScale = 1.0f;
  bool autoResolution = false;
  float targetFrameMs = 100.0f;
  float background[3] = {0.05f, 0.05f, 0.08f};
};

struct FrameSync {
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  VkSemaphore imageReady = VK_NULL_HANDLE, renderDone = VK_NULL_HANDLE;
};

FrameSync createFrameSync(Context& ctx) {
  FrameSync f;
  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = ctx.commandPool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  REFRAX_VK(vkAllocateCommandBuffers(ctx.device, &cai, &f.cmd));
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  fci.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  REFRAX_VK(vkCreateFence(ctx.device, &fci, nullptr, &f.fence));
  VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  REFRAX_VK(vkCreateSemaphore(ctx.device, &sci, nullptr, &f.imageReady));
  REFRAX_VK(vkCreateSemaphore(ctx.device, &sci, nullptr, &f.renderDone));
  return f;
}

void destroyFrameSync(Context& ctx, FrameSync& f) {
  vkDestroySemaphore(ctx.device, f.imageReady, nullptr);
  vkDestroySemaphore(ctx.device, f.renderDone, nullptr);
  vkDestroyFence(ctx.device, f.fence, nullptr);
  vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &f.cmd);
}

SurfacePreview buildSurface(Context& ctx, const BuiltinSurface& s) {
  GridMesh mesh = makeGridMesh(128, 128, -1, -1, 1, 1, surfaceHeightFunction(s));
  return createSurfacePreview(ctx, mesh.vertices, mesh.indices);
}

// The render target: packed RGBA8 pixels written by compute, copied into an image that is
// blitted (scaled) onto the swapchain image.
struct RenderTarget {
  uint32_t width = 0, height = 0;
  Buffer pixels;
  Image2D image;
};

void ensureTarget(Context& ctx, RenderTarget& t, uint32_t w, uint32_t h) {
  if (t.width == w && t.height == h) return;
  vkDeviceWaitIdle(ctx.device);
  t.width = w;
  t.height = h;
  t.pixels = createBuffer(ctx, size_t(w) * h * 4);
  t.image = createImage2D(ctx, w, h, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
}

void saveScreenshot(Context& ctx, const RenderTarget& t, const std::string& path) {
  auto pixels = downloadVector<uint32_t>(ctx, t.pixels, size_t(t.width) * t.height);
  writePng(path, rgba8ToImage(pixels, t.width, t.height));
  std::printf("screenshot %s (%ux%u)\n", path.c_str(), t.width, t.height);
}

struct Input {
  bool looking = false;
  double lastX = 0, lastY = 0;
  float wheel = 0;
};

void onScroll(GLFWwindow* w, double, double dy) {
  static_cast<Input*>(glfwGetWindowUserPointer(w))->wheel += float(dy);
  ImGui_ImplGlfw_ScrollCallback(w, 0, dy);
}

int runViewer(const cli::Args& args) {
  if (!glfwInit())
    fail("no display to open a window on (set DISPLAY, or run under xvfb-run); for images without a window use `refrax render`");
  struct GlfwGuard {
    ~GlfwGuard() { glfwTerminate(); }
  } glfwGuard;
  if (!glfwVulkanSupported()) fail("GLFW found no Vulkan loader for windows");
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  int winW = int(args.getInt("width", 800)), winH = int(args.getInt("height", 600));
  GLFWwindow* window = glfwCreateWindow(winW, winH, "refrax-view", nullptr, nullptr);
  if (!window) fail("could not open a window");

  ContextOptions co;
  co.device = args.get("device");
  co.validation = args.has("validation");
  co.verbose = true;
  uint32_t nExt = 0;
  const char** ext = glfwGetRequiredInstanceExtensions(&nExt);
  co.extraInstanceExtensions.assign(ext, ext + nExt);
  co.extraDeviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  auto ctx = createContext(co);

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

  ViewSettings view;
  if (args.has("surface")) view.surface.kind = args.get("surface");
  view.previewMode = args.get("mode", "normals") == "wireframe" ? 1 : 0;
  BuiltinSurface built = view.surface;
  SurfacePreview preview = buildSurface(*ctx, built);
  FlyCamera home = parseLookAt(args.get("camera", "0,-2.2,1.6,0,0,0")), camera = home;

  FrameSync frame = createFrameSync(*ctx);
  GpuTimer timer;
  createTimer(*ctx, timer, 8);
  RenderTarget target;
  std::vector<std::pair<std::string, double>> stageMs;
  const long frames = args.getInt("frames", 0);
  const std::string screenshot = args.get("screenshot");
  if (frames < 0) fail("--frames must be positive");
  if (!screenshot.empty() && frames == 0) fail("--screenshot needs --frames N");
  long frameIndex = 0;
  double fps = 0, frameMs = 0;
  bool wantScreenshot = false;
  auto last = std::chrono::steady_clock::now();

  while (!glfwWindowShouldClose(window)) {
    glfwPollEvents();
    auto now = std::chrono::steady_clock::now();
    float dt = std::chrono::duration<float>(now - last).count();
    last = now;
    frameMs = dt * 1e3;
    fps = fps == 0 ? 1.0 / std::max(dt, 1e-4f) : 0.9 * fps + 0.1 / std::max(dt, 1e-4f);

    // ---- input (ignored while ImGui has the mouse/keyboard)
    ImGuiIO& io = ImGui::GetIO();
    if (!io.WantCaptureKeyboard) {
      auto key = [&](int k) { return glfwGetKey(window, k) == GLFW_PRESS ? 1.0f : 0.0f; };
      flyMove(camera, key(GLFW_KEY_W) - key(GLFW_KEY_S), key(GLFW_KEY_D) - key(GLFW_KEY_A), key(GLFW_KEY_E) - key(GLFW_KEY_Q), dt);
      if (glfwGetKey(window, GLFW_KEY_R) == GLFW_PRESS) camera = home;
      static bool pWas = false, oWas = false;
      bool p = glfwGetKey(window, GLFW_KEY_P) == GLFW_PRESS, o = glfwGetKey(window, GLFW_KEY_O) == GLFW_PRESS;
      if (p && !pWas) wantScreenshot = true;
      if (o && !oWas) camera.orbit = !camera.orbit;
      pWas = p;
      oWas = o;
    }
    double mx, my;
    glfwGetCursorPos(window, &mx, &my);
    bool rightDown = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS && !io.WantCaptureMouse;
    if (rightDown && input.looking) flyLook(camera, -float(mx - input.lastX) * 0.005f, -float(my - input.lastY) * 0.005f);
    input.looking = rightDown;
    input.lastX = mx;
    input.lastY = my;
    if (input.wheel != 0 && !io.WantCaptureMouse) camera.speed *= std::pow(1.2f, input.wheel);
    input.wheel = 0;

    // ---- UI
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::Begin("Refrax");
    ImGui::Text("%s", ctx->caps.name.c_str());
    ImGui::Text("%.1f FPS (%.1f ms)  render %ux%u", fps, frameMs, target.width, target.height);
    for (auto& s : stageMs) ImGui::Text("  %-8s %7.2f ms", s.first.c_str(), s.second);
    ImGui::Separator();
    const char* kinds[] = {"flat", "sine", "triangle"};
    int kind = view.surface.kind == "flat" ? 0 : view.surface.kind == "sine" ? 1 : 2;
    if (ImGui::Combo("surface", &kind, kinds, 3)) view.surface.kind = kinds[kind];
    ImGui::SliderFloat("amplitude", &view.surface.amplitude, 0.0f, 0.2f);
    ImGui::SliderFloat("wavelength", &view.surface.wavelength, 0.05f, 2.0f);
    ImGui::SliderFloat("direction", &view.surface.directionDeg, 0.0f, 180.0f);
    const char* modes[] = {"normals", "wireframe"};
    ImGui::Combo("show", &view.previewMode, modes, 2);
    ImGui::Checkbox("auto resolution", &view.autoResolution);
    if (view.autoResolution) ImGui::SliderFloat("target ms", &view.targetFrameMs, 16.0f, 500.0f);
    else ImGui::SliderFloat("resolution", &view.resolutionScale, 0.1f, 1.0f);
    ImGui::SliderFloat("speed", &camera.speed, 0.01f, 10.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    ImGui::Checkbox("orbit (O)", &camera.orbit);
    if (ImGui::Button("reset view (R)")) camera = home;
    ImGui::SameLine();
    if (ImGui::Button("screenshot (P)")) wantScreenshot = true;
    ImGui::End();
    ImGui::Render();

    if (built.kind != view.surface.kind || built.amplitude != view.surface.amplitude ||
        built.wavelength != view.surface.wavelength || built.directionDeg != view.surface.directionDeg) {
      vkDeviceWaitIdle(ctx->device);
      built = view.surface;
      preview = buildSurface(*ctx, built);
    }
    if (view.autoResolution && frameMs > 0) {  // hold the target frame time by rendering fewer pixels
      float ratio = view.targetFrameMs / float(frameMs);
      view.resolutionScale = std::clamp(view.resolutionScale * std::clamp(std::sqrt(ratio), 0.8f, 1.2f), 0.1f, 1.0f);
    }

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
    uint32_t rw = std::max(1u, uint32_t(float(sc.extent.width) * view.resolutionScale));
    uint32_t rh = std::max(1u, uint32_t(float(sc.extent.height) * view.resolutionScale));
    ensureTarget(*ctx, target, rw, rh);

    VkCommandBuffer cb = frame.cmd;
    REFRAX_VK(vkResetCommandBuffer(cb, 0));
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    REFRAX_VK(vkBeginCommandBuffer(cb, &bi));
    cmdTimerStart(cb, timer);
    cmdRenderSurfacePreview(cb, preview, camera, rw, rh, PreviewMode(view.previewMode), view.background, target.pixels);
    cmdTimerStamp(cb, timer, "surface");
    cmdBarrier(cb);
    cmdImageLayout(cb, target.image.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {rw, rh, 1};
    vkCmdCopyBufferToImage(cb, target.pixels.buffer, target.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    cmdImageLayout(cb, target.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkImage swapImage = sc.images[imageIndex];
    cmdImageLayout(cb, swapImage, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.srcOffsets[1] = {int32_t(rw), int32_t(rh), 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.dstOffsets[1] = {int32_t(sc.extent.width), int32_t(sc.extent.height), 1};
    vkCmdBlitImage(cb, target.image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &blit, VK_FILTER_LINEAR);
    cmdImageLayout(cb, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
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
    stageMs = readTimer(timer);
    frameIndex++;
    if (wantScreenshot) {
      char name[64];
      std::snprintf(name, sizeof name, "refrax-view-%05ld.png", frameIndex);
      saveScreenshot(*ctx, target, name);
      wantScreenshot = false;
    }
    if (frames > 0 && frameIndex >= frames) {
      if (!screenshot.empty()) saveScreenshot(*ctx, target, screenshot);
      std::printf("rendered %ld frames at %ux%u, last %.1f ms\n", frameIndex, target.width, target.height, frameMs);
      break;
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
  options.push_back({"surface", "KIND", "built-in water surface: flat, sine or triangle", "sine"});
  options.push_back({"mode", "MODE", "normals or wireframe", "normals"});
  options.push_back({"camera", "x,y,z,tx,ty,tz", "start camera position and target", "0,-2.2,1.6,0,0,0"});
  options.push_back({"width", "PIXELS", "window width", "800"});
  options.push_back({"height", "PIXELS", "window height", "600"});
  options.push_back({"frames", "N", "render N frames, then exit", ""});
  options.push_back({"screenshot", "FILE", "with --frames: save the last render as PNG", ""});
  return {"refrax-view", "interactive viewer: fly camera, water on/removed/swapped, per-stage timings",
          "refrax-view [options]", options, runViewer};
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
    if (!args.positional.empty()) fail("unexpected argument '" + args.positional[0] + "'");
    return runViewer(args);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "refrax-view: error: %s\n", e.what());
    return 1;
  }
}
