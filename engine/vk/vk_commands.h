#pragma once
// Command recording and submission: record into the context's command buffer, submit,
// wait. Barriers are coarse on purpose (every stage Refrax uses is compute or AS build).
#include <volk.h>

#include <functional>

namespace refrax {

struct Buffer;
struct Context;

// Records with `record`, submits on the compute queue and waits for completion (after any
// submission still in flight: waitInFlight).
void submitAndWait(Context& ctx, const std::function<void(VkCommandBuffer)>& record);

// A command buffer and fence of a caller's own, for submissions not waited for (a training
// step's while the host records the next, issue 48). Destroy after waitInFlight.
struct SubmitSlot {
  VkCommandBuffer cb = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  bool inFlight = false;
};
SubmitSlot createSubmitSlot(Context& ctx);
void destroySubmitSlot(Context& ctx, SubmitSlot& slot);
// Records into the slot's command buffer (waiting first for its last submission, if still in
// flight) after a barrier on everything submitted before it, submits it, and returns without
// waiting; `done` runs once its fence has signalled (waitInFlight). Every later submitAndWait,
// upload and download waits for it first, so the host never touches what it still uses:
// only the caller's own host-visible buffers (its uploads' area, its readbacks) need one
// per slot.
void submitWithoutWait(Context& ctx, SubmitSlot& slot, const std::function<void(VkCommandBuffer)>& record, std::function<void()> done = {});
// Waits for the oldest submissions in flight until at most `keep` remain, running each one's
// `done` in submission order.
void waitInFlight(Context& ctx, size_t keep = 0);

// Shader/transfer/AS-build writes made visible to every later compute, transfer, AS and
// indirect-dispatch read.
void cmdBarrier(VkCommandBuffer cb);
// Transfer writes made visible to the host (a copy into a mapped readback buffer, read after
// the submission's wait).
void cmdBarrierToHost(VkCommandBuffer cb);
// Copies `bytes` of src at srcOffset to dst at dstOffset, then cmdBarrierToHost: a value the
// host reads after the wait with no submission of its own.
void cmdCopyToHost(VkCommandBuffer cb, const Buffer& src, VkDeviceSize srcOffset, const Buffer& dst, VkDeviceSize dstOffset,
                   VkDeviceSize bytes);

}  // namespace refrax
