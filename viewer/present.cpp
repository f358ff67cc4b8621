#include "viewer/present.h"

#include <algorithm>
#include <cstdio>

#include "engine/base/error.h"
#include "engine/io/image_io.h"
#include "engine/surface/surface_preview.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

FrameSync createFrameSync(Context& ctx) {
  FrameSync f;
  f.cmd = allocateCommandBuffer(ctx);
  f.fence = createFence(ctx, true);
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

void ensureTarget(Context& ctx, RenderTarget& t, uint32_t w, uint32_t h) {
  if (t.width == w && t.height == h) return;
  vkDeviceWaitIdle(ctx.device);
  t.width = w;
  t.height = h;
  t.image = createImage2D(ctx, w, h, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
}

void cmdPresentPixels(VkCommandBuffer cb, const Buffer& pixels, RenderTarget& t, VkImage swapImage, VkExtent2D extent, const float clear[3]) {
  cmdBarrier(cb);
  cmdImageLayout(cb, t.image.image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {t.width, t.height, 1};
  vkCmdCopyBufferToImage(cb, pixels.buffer, t.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
  cmdImageLayout(cb, t.image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  cmdImageLayout(cb, swapImage, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
  // Letterbox: the largest rectangle of the render's aspect centred in the window.
  double scale = std::min(double(extent.width) / t.width, double(extent.height) / t.height);
  int32_t w = std::max(1, int32_t(t.width * scale + 0.5)), h = std::max(1, int32_t(t.height * scale + 0.5));
  int32_t x0 = (int32_t(extent.width) - w) / 2, y0 = (int32_t(extent.height) - h) / 2;
  if (w != int32_t(extent.width) || h != int32_t(extent.height)) {
    VkClearColorValue colour{{clear[0], clear[1], clear[2], 1.0f}};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cb, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &colour, 1, &range);
    cmdBarrier(cb);
  }
  VkImageBlit blit{};
  blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.srcOffsets[1] = {int32_t(t.width), int32_t(t.height), 1};
  blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  blit.dstOffsets[0] = {x0, y0, 0};
  blit.dstOffsets[1] = {x0 + w, y0 + h, 1};
  vkCmdBlitImage(cb, t.image.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit,
                 VK_FILTER_LINEAR);
  cmdImageLayout(cb, swapImage, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
}

void saveScreenshot(Context& ctx, const Buffer& pixels, uint32_t width, uint32_t height, const std::string& path) {
  auto data = downloadVector<uint32_t>(ctx, pixels, size_t(width) * height);
  writePng(path, rgba8ToImage(data, width, height));
  std::printf("screenshot %s (%ux%u)\n", path.c_str(), width, height);
}

}  // namespace refrax
