#include "engine/vk/strided_copy.h"

#include <string>

#include "engine/base/error.h"
#include "engine/vk/vk_buffer.h"

namespace refrax {

namespace {
struct StridedPush {  // mirror of the push block in shaders/vk/copy_strided.comp
  uint32_t count, channels, srcStride, srcOffset, dstStride, dstOffset, weighted;
};

void requireFloats(const Buffer& b, StridedLayout l, uint32_t count, const char* what) {
  uint64_t floats = count ? uint64_t(l.offset) + uint64_t(count - 1) * l.stride + l.stride : 0;
  if (!b || b.size < floats * 4)
    fail(std::string("strided copy: the ") + what + " buffer holds " + std::to_string(b ? b.size : 0) + " bytes, " +
         std::to_string(floats * 4) + " needed");
}
}  // namespace

ComputePipeline createStridedCopyPipeline(Context& ctx) {
  return createComputePipeline(ctx, "copy_strided", {kStorageBuffer, kStorageBuffer, kStorageBuffer}, sizeof(StridedPush));
}

void cmdCopyStrided(VkCommandBuffer cb, const ComputePipeline& p, const Buffer& src, StridedLayout from, const Buffer& dst, StridedLayout to,
                    uint32_t channels, uint32_t count, const Buffer* weights) {
  if (channels > from.stride || channels > to.stride) fail("strided copy: more channels than a stride holds");
  requireFloats(src, from, count, "source");
  requireFloats(dst, to, count, "destination");
  if (weights) requireFloats(*weights, {1, 0}, count, "weight");
  if (count == 0) return;
  StridedPush push{count, channels, from.stride, from.offset, to.stride, to.offset, weights ? 1u : 0u};
  // unweighted, the source stands in for the weight binding (never read)
  cmdDispatch(cb, p, {bind(src), bind(dst), bind(weights ? *weights : src)}, &push, groupsFor(count, 64));
}

}  // namespace refrax
