#include "viewer/imgui_layer.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "viewer/swapchain.h"

namespace refrax {

ImguiLayer createImguiLayer(Context& ctx, GLFWwindow* window, const Swapchain& sc) {
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplVulkan_LoadFunctions(
      [](const char* name, void* inst) { return vkGetInstanceProcAddr(*static_cast<VkInstance*>(inst), name); }, &ctx.instance);
  ImGui_ImplGlfw_InitForVulkan(window, true);
  ImguiLayer layer;
  VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 8};
  VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dpi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  dpi.maxSets = 8;
  dpi.poolSizeCount = 1;
  dpi.pPoolSizes = &poolSize;
  REFRAX_VK(vkCreateDescriptorPool(ctx.device, &dpi, nullptr, &layer.pool));
  ImGui_ImplVulkan_InitInfo ii{};
  ii.Instance = ctx.instance;
  ii.PhysicalDevice = ctx.physical;
  ii.Device = ctx.device;
  ii.QueueFamily = ctx.queueFamily;
  ii.Queue = ctx.queue;
  ii.DescriptorPool = layer.pool;
  ii.MinImageCount = sc.minImageCount;
  ii.ImageCount = uint32_t(sc.images.size());
  ii.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  ImGui_ImplVulkan_Init(&ii, sc.overlayPass);
  submitAndWait(ctx, [](VkCommandBuffer cb) { ImGui_ImplVulkan_CreateFontsTexture(cb); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
  return layer;
}

void destroyImguiLayer(Context& ctx, ImguiLayer& layer) {
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  vkDestroyDescriptorPool(ctx.device, layer.pool, nullptr);
  layer.pool = VK_NULL_HANDLE;
}

void beginImguiFrame() {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void cmdDrawImgui(VkCommandBuffer cb, const Swapchain& sc, uint32_t imageIndex) {
  VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rp.renderPass = sc.overlayPass;
  rp.framebuffer = sc.framebuffers[imageIndex];
  rp.renderArea.extent = sc.extent;
  vkCmdBeginRenderPass(cb, &rp, VK_SUBPASS_CONTENTS_INLINE);
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cb);
  vkCmdEndRenderPass(cb);
}

}  // namespace refrax
