#pragma once
// Dear ImGui over the viewer's window: its GLFW and Vulkan backends (entry points loaded
// through volk's instance), drawn into the swapchain's overlay pass on top of the render.
#include <volk.h>

struct GLFWwindow;

namespace refrax {

struct Context;
struct Swapchain;

struct ImguiLayer {
  VkDescriptorPool pool = VK_NULL_HANDLE;  // the font texture's descriptor
};

ImguiLayer createImguiLayer(Context& ctx, GLFWwindow* window, const Swapchain& sc);
void destroyImguiLayer(Context& ctx, ImguiLayer& layer);
// Starts a frame's UI (the panels are drawn after this, then ImGui::Render()).
void beginImguiFrame();
// Records the UI into the overlay pass of swapchain image `imageIndex`.
void cmdDrawImgui(VkCommandBuffer cb, const Swapchain& sc, uint32_t imageIndex);

}  // namespace refrax
