#include "engine/vk/vk_commands.h"

#include "engine/base/error.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_profile.h"

namespace refrax {

void submitAndWait(Context& ctx, const std::function<void(VkCommandBuffer)>& record) {
  VkCommandBuffer cb = ctx.commandBuffer;
  REFRAX_VK(vkResetCommandBuffer(cb, 0));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  REFRAX_VK(vkBeginCommandBuffer(cb, &bi));
  profileSubmitBegin(cb, ctx);
  record(cb);
  REFRAX_VK(vkEndCommandBuffer(cb));
  REFRAX_VK(vkResetFences(ctx.device, 1, &ctx.fence));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cb;
  REFRAX_VK(vkQueueSubmit(ctx.queue, 1, &si, ctx.fence));
  REFRAX_VK(vkWaitForFences(ctx.device, 1, &ctx.fence, VK_TRUE, UINT64_MAX));
  profileSubmitEnd(ctx);
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
