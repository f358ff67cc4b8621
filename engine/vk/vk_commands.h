#pragma once
// Command recording and submission: record into the context's command buffer, submit,
// wait. Barriers are coarse on purpose (every stage Refrax uses is compute or AS build).
#include <volk.h>

#include <functional>

namespace refrax {

struct Context;

// Records with `record`, submits on the compute queue and waits for completion.
void submitAndWait(Context& ctx, const std::function<void(VkCommandBuffer)>& record);

// Shader/transfer/AS-build writes made visible to every later compute, transfer, AS and
// indirect-dispatch read.
void cmdBarrier(VkCommandBuffer cb);

}  // namespace refrax
