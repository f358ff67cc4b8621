#pragma once
// 2D images (the viewer's render target; storage images later), device-local.
#include <volk.h>

#include <utility>

namespace refrax {

struct Context;

struct Image2D {
  Context* ctx = nullptr;
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  uint32_t width = 0, height = 0;

  Image2D() = default;
  Image2D(const Image2D&) = delete;
  Image2D& operator=(const Image2D&) = delete;
  Image2D(Image2D&& o) noexcept { *this = std::move(o); }
  Image2D& operator=(Image2D&& o) noexcept;
  ~Image2D() { release(); }
  void release();
};

Image2D createImage2D(Context& ctx, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage);

// Layout transition of the whole colour image with a full-pipeline barrier (coarse on purpose).
void cmdImageLayout(VkCommandBuffer cb, VkImage image, VkImageLayout from, VkImageLayout to);

}  // namespace refrax
