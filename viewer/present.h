#pragma once
// The window side of a frame: per-frame command buffer, fence and semaphores; the render
// target (packed RGBA8 pixels copied into an image); the copy and the letterboxed blit onto
// the swapchain image; PNG screenshots of the render target.
#include <string>

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_image.h"
#include "viewer/swapchain.h"

namespace refrax {

struct FrameSync {
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  VkSemaphore imageReady = VK_NULL_HANDLE, renderDone = VK_NULL_HANDLE;
};
FrameSync createFrameSync(Context& ctx);
void destroyFrameSync(Context& ctx, FrameSync& f);

struct RenderTarget {
  uint32_t width = 0, height = 0;
  Image2D image;
};
void ensureTarget(Context& ctx, RenderTarget& t, uint32_t width, uint32_t height);

// Copies width*height RGBA8 pixels into the target image and blits it, aspect kept (bars in
// `clear`), onto the swapchain image, left in COLOR_ATTACHMENT_OPTIMAL for the UI pass.
void cmdPresentPixels(VkCommandBuffer cb, const Buffer& pixels, RenderTarget& target, VkImage swapImage, VkExtent2D swapExtent,
                      const float clear[3]);

void saveScreenshot(Context& ctx, const Buffer& pixels, uint32_t width, uint32_t height, const std::string& path);

}  // namespace refrax
