#pragma once
// Buffers: device-local storage (mapped directly where the device shares memory with the
// host, as lavapipe and integrated GPUs do; staged otherwise), with upload/download.
#include <volk.h>

#include <cstddef>
#include <initializer_list>
#include <vector>

namespace refrax {

struct Context;

enum class MemoryUse {
  Device,    // shader storage, AS input/storage: device-local, mapped only if also host-visible
  Readback,  // host-visible, cached where possible: for results read every frame
};

struct Buffer {
  Context* ctx = nullptr;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
  VkDeviceAddress address = 0;
  void* mapped = nullptr;  // non-null when the host can write it directly

  Buffer() = default;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;
  Buffer(Buffer&& o) noexcept { *this = std::move(o); }
  Buffer& operator=(Buffer&& o) noexcept;
  ~Buffer() { release(); }
  void release();
  explicit operator bool() const { return buffer != VK_NULL_HANDLE; }
};

// Usage gets storage, transfer and device-address bits added, so any buffer can be bound,
// copied and referenced by an acceleration-structure build.
Buffer createBuffer(Context& ctx, VkDeviceSize size, VkBufferUsageFlags extraUsage = 0, MemoryUse use = MemoryUse::Device);

// AS build inputs (vertices, indices, boxes, instances) need this usage bit.
constexpr VkBufferUsageFlags kAccelInput = VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR;
// Group counts an indirect dispatch reads (cmdDispatchIndirect).
constexpr VkBufferUsageFlags kIndirectArgs = VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT;

void upload(Context& ctx, Buffer& dst, const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
void download(Context& ctx, const Buffer& src, void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
void fillBuffer(Context& ctx, Buffer& dst, uint32_t word);  // every 32-bit word set to `word`

// Uploads recorded into a command buffer instead of submitted on their own: on a device the host
// cannot map (a discrete GPU), each upload() is a submission of its own; a training step's
// batch (its target pixels, mask and pixel list) goes instead through this host-visible area,
// and its copies run at the head of the step's own command buffer (issue 48). Where the host
// maps the destination (lavapipe, integrated GPUs) the data is written in place.
struct RecordedUploads {
  struct Copy {
    VkBuffer dst;
    VkDeviceSize from, bytes;
  };
  Buffer area;  // host-visible, mapped
  VkDeviceSize used = 0;
  std::vector<Copy> pending;
  // Through the area even where the host could write the destination in place (lavapipe):
  // for uploads recorded while an earlier submission may still read the destination.
  bool alwaysStaged = false;
};
// Writes `bytes` of data for dst: in place, or into the area with its copy pending. The area
// grows only while no copy is pending (a copy reads it when its command buffer runs).
void stageUpload(Context& ctx, RecordedUploads& u, Buffer& dst, const void* data, VkDeviceSize bytes);
// Grows the area (no copy pending) to hold uploads of these sizes, each 16-byte aligned.
void reserveUploads(Context& ctx, RecordedUploads& u, std::initializer_list<VkDeviceSize> sizes);
// Records the pending copies and a barrier after them (nothing when none is pending); the
// area is free again once cb has run.
void cmdFlushUploads(VkCommandBuffer cb, RecordedUploads& u);

template <typename T>
Buffer createBufferFrom(Context& ctx, const std::vector<T>& data, VkBufferUsageFlags extraUsage = 0) {
  Buffer b = createBuffer(ctx, data.empty() ? sizeof(T) : data.size() * sizeof(T), extraUsage);
  if (!data.empty()) upload(ctx, b, data.data(), data.size() * sizeof(T));
  return b;
}
template <typename T>
std::vector<T> downloadVector(Context& ctx, const Buffer& src, size_t count) {
  std::vector<T> out(count);
  if (count) download(ctx, src, out.data(), count * sizeof(T));
  return out;
}

}  // namespace refrax
