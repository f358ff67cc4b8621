#pragma once
// Command recording and submission: record into the context's command buffer, submit,
// wait. Barriers are coarse on purpose (every stage Refrax uses is compute or AS build).
#include <volk.h>

#include <functional>

namespace refrax {

struct Buffer;
struct Context;

// Records with `record`, submits on the compute queue and waits for completion.
void submitAndWait(Context& ctx, const std::function<void(VkCommandBuffer)>& record);

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
