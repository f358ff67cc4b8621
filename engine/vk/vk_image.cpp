#include "engine/vk/vk_image.h"

#include <utility>

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"

namespace refrax {

Image2D& Image2D::operator=(Image2D&& o) noexcept {
  if (this != &o) {
    release();
    ctx = o.ctx;
    image = o.image;
    memory = o.memory;
    view = o.view;
    format = o.format;
    width = o.width;
    height = o.height;
    o.ctx = nullptr;
    o.image = VK_NULL_HANDLE;
    o.memory = VK_NULL_HANDLE;
    o.view = VK_NULL_HANDLE;
  }
  return *this;
}

void Image2D::release() {
  if (ctx && ctx->device) {
    if (view) vkDestroyImageView(ctx->device, view, nullptr);
    if (image) vkDestroyImage(ctx->device, image, nullptr);
    if (memory) vkFreeMemory(ctx->device, memory, nullptr);
  }
  ctx = nullptr;
  image = VK_NULL_HANDLE;
  memory = VK_NULL_HANDLE;
  view = VK_NULL_HANDLE;
}

Image2D createImage2D(Context& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage) {
  if (width == 0 || height == 0) fail("createImage2D: zero-sized image");
  Image2D img;
  img.ctx = &ctx;
  img.format = format;
  img.width = width;
  img.height = height;
  VkImageCreateInfo ci{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ci.imageType = VK_IMAGE_TYPE_2D;
  ci.format = format;
  ci.extent = {width, height, 1};
  ci.mipLevels = 1;
  ci.arrayLayers = 1;
  ci.samples = VK_SAMPLE_COUNT_1_BIT;
  ci.tiling = VK_IMAGE_TILING_OPTIMAL;
  ci.usage = usage;
  ci.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  REFRAX_VK(vkCreateImage(ctx.device, &ci, nullptr, &img.image));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(ctx.device, img.image, &req);
  int type = -1;
  for (uint32_t i = 0; i < ctx.memory.memoryTypeCount && type < 0; i++)
    if ((req.memoryTypeBits & (1u << i)) && (ctx.memory.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT))
      type = int(i);
  if (type < 0) fail("no device-local memory for an image");
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = uint32_t(type);
  REFRAX_VK(vkAllocateMemory(ctx.device, &ai, nullptr, &img.memory));
  REFRAX_VK(vkBindImageMemory(ctx.device, img.image, img.memory, 0));
  if (usage & (VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT)) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = img.image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    REFRAX_VK(vkCreateImageView(ctx.device, &vi, nullptr, &img.view));
  }
  return img;
}

void cmdImageLayout(VkCommandBuffer cb, VkImage image, VkImageLayout from, VkImageLayout to) {
  VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
  b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
  b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0, nullptr, 1, &b);
}

}  // namespace refrax
