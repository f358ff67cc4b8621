#include "viewer/swapchain.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <algorithm>

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"

namespace refrax {

void createSurface(Context& ctx, GLFWwindow* window, Swapchain& sc) {
  REFRAX_VK(glfwCreateWindowSurface(ctx.instance, window, nullptr, &sc.surface));
  VkBool32 present = VK_FALSE;
  vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical, ctx.queueFamily, sc.surface, &present);
  if (!present) fail("device '" + ctx.caps.name + "' cannot present to this window from its compute queue");
}

void createSwapchain(Context& ctx, GLFWwindow* window, Swapchain& sc) {
  VkSwapchainKHR old = sc.swapchain;
  destroySwapchain(ctx, sc, false);  // views and framebuffers; the old swapchain is retired below
  sc.swapchain = VK_NULL_HANDLE;

  VkSurfaceCapabilitiesKHR caps;
  REFRAX_VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx.physical, sc.surface, &caps));
  uint32_t n = 0;
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical, sc.surface, &n, nullptr);
  std::vector<VkSurfaceFormatKHR> formats(n);
  vkGetPhysicalDeviceSurfaceFormatsKHR(ctx.physical, sc.surface, &n, formats.data());
  if (formats.empty()) fail("the window surface offers no formats");
  VkSurfaceFormatKHR chosen = formats[0];
  for (auto& f : formats)  // UNORM: our pixels are already display values (as in the saved PNGs)
    if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) chosen = f;
  sc.format = chosen.format;

  int w = 0, h = 0;
  glfwGetFramebufferSize(window, &w, &h);
  sc.extent = caps.currentExtent.width != UINT32_MAX ? caps.currentExtent : VkExtent2D{uint32_t(w), uint32_t(h)};
  sc.extent.width = std::clamp(sc.extent.width, caps.minImageExtent.width, caps.maxImageExtent.width);
  sc.extent.height = std::clamp(sc.extent.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  sc.minImageCount = std::max(2u, caps.minImageCount);
  uint32_t count = caps.maxImageCount ? std::min(caps.minImageCount + 1, caps.maxImageCount) : caps.minImageCount + 1;

  VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  ci.surface = sc.surface;
  ci.minImageCount = count;
  ci.imageFormat = chosen.format;
  ci.imageColorSpace = chosen.colorSpace;
  ci.imageExtent = sc.extent;
  ci.imageArrayLayers = 1;
  ci.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT)) fail("the window surface cannot be a copy destination");
  ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ci.preTransform = caps.currentTransform;
  ci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  ci.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always available
  ci.clipped = VK_TRUE;
  ci.oldSwapchain = old;
  REFRAX_VK(vkCreateSwapchainKHR(ctx.device, &ci, nullptr, &sc.swapchain));
  if (old) vkDestroySwapchainKHR(ctx.device, old, nullptr);

  vkGetSwapchainImagesKHR(ctx.device, sc.swapchain, &n, nullptr);
  sc.images.resize(n);
  vkGetSwapchainImagesKHR(ctx.device, sc.swapchain, &n, sc.images.data());

  if (!sc.overlayPass) {
    VkAttachmentDescription att{};
    att.format = sc.format;
    att.samples = VK_SAMPLE_COUNT_1_BIT;
    att.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    att.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    att.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkSubpassDependency dep{};
    dep.srcSubpass = VK_SUBPASS_EXTERNAL;
    dep.dstSubpass = 0;
    dep.srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dep.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    dep.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    rp.attachmentCount = 1;
    rp.pAttachments = &att;
    rp.subpassCount = 1;
    rp.pSubpasses = &sub;
    rp.dependencyCount = 1;
    rp.pDependencies = &dep;
    REFRAX_VK(vkCreateRenderPass(ctx.device, &rp, nullptr, &sc.overlayPass));
  }
  for (VkImage img : sc.images) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = img;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = sc.format;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view;
    REFRAX_VK(vkCreateImageView(ctx.device, &vi, nullptr, &view));
    sc.views.push_back(view);
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = sc.overlayPass;
    fi.attachmentCount = 1;
    fi.pAttachments = &view;
    fi.width = sc.extent.width;
    fi.height = sc.extent.height;
    fi.layers = 1;
    VkFramebuffer fb;
    REFRAX_VK(vkCreateFramebuffer(ctx.device, &fi, nullptr, &fb));
    sc.framebuffers.push_back(fb);
  }
}

void destroySwapchain(Context& ctx, Swapchain& sc, bool andSurface) {
  vkDeviceWaitIdle(ctx.device);
  for (auto fb : sc.framebuffers) vkDestroyFramebuffer(ctx.device, fb, nullptr);
  for (auto v : sc.views) vkDestroyImageView(ctx.device, v, nullptr);
  sc.framebuffers.clear();
  sc.views.clear();
  if (andSurface) {
    if (sc.overlayPass) vkDestroyRenderPass(ctx.device, sc.overlayPass, nullptr);
    if (sc.swapchain) vkDestroySwapchainKHR(ctx.device, sc.swapchain, nullptr);
    if (sc.surface) vkDestroySurfaceKHR(ctx.instance, sc.surface, nullptr);
    sc.overlayPass = VK_NULL_HANDLE;
    sc.swapchain = VK_NULL_HANDLE;
    sc.surface = VK_NULL_HANDLE;
  }
}

}  // namespace refrax
