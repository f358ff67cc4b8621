#pragma once
// The window's swapchain, and the render pass Dear ImGui draws into (on top of the blitted
// render: load, not clear). Recreated when the window changes size.
#include <volk.h>

#include <vector>

struct GLFWwindow;

namespace refrax {

struct Context;

struct Swapchain {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  VkSwapchainKHR swapchain = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{};
  std::vector<VkImage> images;
  std::vector<VkImageView> views;
  std::vector<VkFramebuffer> framebuffers;
  VkRenderPass overlayPass = VK_NULL_HANDLE;
  uint32_t minImageCount = 2;
};

void createSurface(Context& ctx, GLFWwindow* window, Swapchain& sc);
// (Re)creates the swapchain for the window's current size.
void createSwapchain(Context& ctx, GLFWwindow* window, Swapchain& sc);
void destroySwapchain(Context& ctx, Swapchain& sc, bool andSurface);

}  // namespace refrax
