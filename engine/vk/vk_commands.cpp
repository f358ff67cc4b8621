#include "engine/vk/vk_commands.h"

#include "engine/base/error.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"

namespace refrax {

namespace {
// Records into cb (reset) and submits it on the compute queue with `fence` (reset), no wait.
void recordAndSubmit(Context& ctx, VkCommandBuffer cb, VkFence fence, const std::function<void(VkCommandBuffer)>& record) {
  REFRAX_VK(vkResetCommandBuffer(cb, 0));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  REFRAX_VK(vkBeginCommandBuffer(cb, &bi));
  record(cb);
  REFRAX_VK(vkEndCommandBuffer(cb));
  REFRAX_VK(vkResetFences(ctx.device, 1, &fence));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  REFRAX_VK(vkQueueSubmit(ctx.queue, 1, &si, fence));
}
}  // namespace

void submitAndWait(Context& ctx, const std::function<void(VkCommandBuffer)>& record) {
  waitInFlight(ctx);
  recordAndSubmit(ctx, ctx.commandBuffer, ctx.fence, [&](VkCommandBuffer cb) {
    profileSubmitBegin(cb, ctx);
    record(cb);
  });
  REFRAX_VK(vkWaitForFences(ctx.device, 1, &ctx.fence, VK_TRUE, UINT64_MAX));
  profileSubmitEnd(ctx);
}

SubmitSlot createSubmitSlot(Context& ctx) {
  SubmitSlot slot;
  slot.cb = allocateCommandBuffer(ctx);
  slot.fence = createFence(ctx);
  return slot;
}

void destroySubmitSlot(Context& ctx, SubmitSlot& slot) {
  if (slot.inFlight) waitInFlight(ctx);
  if (slot.fence) vkDestroyFence(ctx.device, slot.fence, nullptr);
  if (slot.cb) vkFreeCommandBuffers(ctx.device, ctx.commandPool, 1, &slot.cb);
  slot = SubmitSlot{};
}

void submitWithoutWait(Context& ctx, SubmitSlot& slot, const std::function<void(VkCommandBuffer)>& record, std::function<void()> done) {
  while (slot.inFlight) waitInFlight(ctx, ctx.inFlight.size() - 1);  // its last submission is the oldest left
  recordAndSubmit(ctx, slot.cb, slot.fence, [&](VkCommandBuffer cb) {
    cmdBarrier(cb);  // after everything submitted before, this one's earlier submissions included
    record(cb);
  });
  slot.inFlight = true;
  bool* flag = &slot.inFlight;
  ctx.inFlight.push_back({slot.fence, [flag, done = std::move(done)] {
                            *flag = false;
                            if (done) done();
                          }});
}

void waitInFlight(Context& ctx, size_t keep) {
  while (ctx.inFlight.size() > keep) {
    Context::InFlight oldest = std::move(ctx.inFlight.front());
    ctx.inFlight.pop_front();
    REFRAX_VK(vkWaitForFences(ctx.device, 1, &oldest.fence, VK_TRUE, UINT64_MAX));
    if (oldest.done) oldest.done();
  }
}

void cmdBarrier(VkCommandBuffer cb) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                     VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
  VkPipelineStageFlags stages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                                VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
  // an indirect dispatch reads its group counts at the draw-indirect stage
  vkCmdPipelineBarrier(cb, stages, stages | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

void cmdBarrierToHost(VkCommandBuffer cb) {
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

void cmdCopyToHost(VkCommandBuffer cb, const Buffer& src, VkDeviceSize srcOffset, const Buffer& dst, VkDeviceSize dstOffset,
                   VkDeviceSize bytes) {
  if (!dst.mapped) fail("cmdCopyToHost into a buffer the host cannot read (create it with MemoryUse::Readback)");
  if (srcOffset + bytes > src.size || dstOffset + bytes > dst.size) fail("cmdCopyToHost past the end of a buffer");
  VkBufferCopy c{srcOffset, dstOffset, bytes};
  vkCmdCopyBuffer(cb, src.buffer, dst.buffer, 1, &c);
  cmdBarrierToHost(cb);
}

}  // namespace refrax
