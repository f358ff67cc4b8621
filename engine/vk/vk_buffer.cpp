#include "engine/vk/vk_buffer.h"

#include <cstring>
#include <utility>

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

int findMemoryType(const Context& ctx, uint32_t bits, VkMemoryPropertyFlags want) {
  for (uint32_t i = 0; i < ctx.memory.memoryTypeCount; i++)
    if ((bits & (1u << i)) && (ctx.memory.memoryTypes[i].propertyFlags & want) == want) return int(i);
  return -1;
}

}  // namespace

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  if (this != &o) {
    release();
    ctx = o.ctx;
    buffer = o.buffer;
    memory = o.memory;
    size = o.size;
    address = o.address;
    mapped = o.mapped;
    o.ctx = nullptr;
    o.buffer = VK_NULL_HANDLE;
    o.memory = VK_NULL_HANDLE;
    o.mapped = nullptr;
    o.size = 0;
    o.address = 0;
  }
  return *this;
}

void Buffer::release() {
  if (ctx && ctx->device) {
    if (mapped) vkUnmapMemory(ctx->device, memory);
    if (buffer) vkDestroyBuffer(ctx->device, buffer, nullptr);
    if (memory) vkFreeMemory(ctx->device, memory, nullptr);
  }
  ctx = nullptr;
  buffer = VK_NULL_HANDLE;
  memory = VK_NULL_HANDLE;
  mapped = nullptr;
}

Buffer createBuffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags extraUsage, MemoryUse use) {
  if (size == 0) fail("createBuffer: zero-sized buffer");
  Buffer b;
  b.ctx = &ctx;
  b.size = size;
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size;
  // Without the acceleration-structure extension (the compute trace backend) its usage bit is not valid.
  if (ctx.trace != TraceBackend::RayQuery) extraUsage &= ~kAccelInput;
  bi.usage = extraUsage | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
             VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
  bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  REFRAX_VK(vkCreateBuffer(ctx.device, &bi, nullptr, &b.buffer));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(ctx.device, b.buffer, &req);

  int type = -1;
  if (use == MemoryUse::Readback) {
    // Coherent only: nothing flushes or invalidates a mapping, and the context's staging buffer
    // is reused, so a non-coherent cached type could hand a download stale cache lines.
    type = findMemoryType(ctx, req.memoryTypeBits,
                          VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    if (type < 0) type = findMemoryType(ctx, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  } else {
    // Shared memory (lavapipe, integrated GPUs): device-local and host-visible at once, so no staging.
    type = findMemoryType(ctx, req.memoryTypeBits,
                          VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    if (type < 0 || ctx.caps.separateDeviceMemory) type = findMemoryType(ctx, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  }
  if (type < 0) fail("no suitable Vulkan memory type for a buffer of " + std::to_string(size) + " bytes");

  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &flags};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = uint32_t(type);
  VkResult r = vkAllocateMemory(ctx.device, &ai, nullptr, &b.memory);
  if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
    fail("out of memory allocating a buffer of " + std::to_string(size >> 20) + " MiB");
  REFRAX_VK(r);
  REFRAX_VK(vkBindBufferMemory(ctx.device, b.buffer, b.memory, 0));
  bool staged = use == MemoryUse::Device && ctx.forceStaging;
  if (!staged && (ctx.memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT))
    REFRAX_VK(vkMapMemory(ctx.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
  VkBufferDeviceAddressInfo dai{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  dai.buffer = b.buffer;
  b.address = vkGetBufferDeviceAddress(ctx.device, &dai);
  return b;
}

namespace {

// The context's staging buffer, grown to a power of two of at least `bytes`. A training step
// moves about ten buffers each way; on a discrete GPU each used to allocate its own.
Buffer& stagingFor(Context& ctx, VkDeviceSize bytes) {
  if (!ctx.staging || ctx.staging->size < bytes) {
    ctx.staging.reset();
    VkDeviceSize size = VkDeviceSize(1) << 16;
    while (size < bytes) size *= 2;
    ctx.staging = std::make_unique<Buffer>(createBuffer(ctx, size, 0, MemoryUse::Readback));
  }
  return *ctx.staging;
}

}  // namespace

void upload(Context& ctx, Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (offset + bytes > dst.size) fail("upload past the end of a buffer");
  if (bytes == 0) return;
  waitInFlight(ctx);  // the device may still read dst
  if (dst.mapped) {
    std::memcpy(static_cast<char*>(dst.mapped) + offset, data, bytes);
    return;
  }
  Buffer& staging = stagingFor(ctx, bytes);
  std::memcpy(staging.mapped, data, bytes);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cb, staging.buffer, dst.buffer, 1, &region);
  });
}

void download(Context& ctx, const Buffer& src, void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (offset + bytes > src.size) fail("download past the end of a buffer");
  if (bytes == 0) return;
  waitInFlight(ctx);  // the device may still write src
  if (src.mapped) {
    std::memcpy(data, static_cast<const char*>(src.mapped) + offset, bytes);
    return;
  }
  Buffer& staging = stagingFor(ctx, bytes);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    VkBufferCopy region{offset, 0, bytes};
    vkCmdCopyBuffer(cb, src.buffer, staging.buffer, 1, &region);
    cmdBarrierToHost(cb);
  });
  std::memcpy(data, staging.mapped, bytes);
}

void fillBuffer(Context& ctx, Buffer& dst, uint32_t word) {
  submitAndWait(ctx, [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, dst.buffer, 0, VK_WHOLE_SIZE, word); });
}

void stageUpload(Context& ctx, RecordedUploads& u, Buffer& dst, const void* data, VkDeviceSize bytes) {
  if (bytes > dst.size) fail("upload past the end of a buffer");
  if (bytes == 0) return;
  if (dst.mapped && !u.alwaysStaged) {
    waitInFlight(ctx);  // the device may still read dst
    std::memcpy(dst.mapped, data, bytes);
    return;
  }
  const VkDeviceSize from = (u.used + 15) & ~VkDeviceSize(15);
  if (from + bytes > u.area.size) {
    if (!u.pending.empty()) fail("stageUpload: the upload area must grow while copies from it are pending (reserveUploads first)");
    reserveUploads(ctx, u, {bytes});
    return stageUpload(ctx, u, dst, data, bytes);
  }
  std::memcpy(static_cast<char*>(u.area.mapped) + from, data, bytes);
  u.pending.push_back({dst.buffer, from, bytes});
  u.used = from + bytes;
}

void reserveUploads(Context& ctx, RecordedUploads& u, std::initializer_list<VkDeviceSize> sizes) {
  VkDeviceSize need = 0;
  for (VkDeviceSize b : sizes) need += (b + 15) & ~VkDeviceSize(15);
  if (need <= u.area.size) return;
  if (!u.pending.empty()) fail("reserveUploads: the upload area cannot grow while copies from it are pending");
  VkDeviceSize size = VkDeviceSize(1) << 16;
  while (size < need) size *= 2;
  u.area = createBuffer(ctx, size, 0, MemoryUse::Readback);  // host-visible and coherent
  u.used = 0;
}

void cmdFlushUploads(VkCommandBuffer cb, RecordedUploads& u) {
  if (u.pending.empty()) return;
  for (const RecordedUploads::Copy& c : u.pending) {
    VkBufferCopy region{c.from, 0, c.bytes};
    vkCmdCopyBuffer(cb, u.area.buffer, c.dst, 1, &region);
  }
  cmdBarrier(cb);
  u.pending.clear();
  u.used = 0;
}

}  // namespace refrax
