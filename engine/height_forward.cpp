// Height field forward: picks the kernel for the configuration and records it.
#include <algorithm>

#include "engine/error.h"
#include "engine/height_field_kernels.h"
#include "engine/vk_context.h"

namespace refrax {

void cmdHeightForwardGeneric(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count,
                             const Buffer& heights);
const ComputePipeline& heightGenericForwardPipeline(const HeightField& hf);

std::string heightForwardKernelName(const HeightField& hf) {
  (void)hf;
  return "generic";
}

double prepareHeightForward(const HeightField& hf) {
  size_t before = hf.pipelines->byName.size();
  const ComputePipeline& p = heightGenericForwardPipeline(hf);
  return hf.pipelines->byName.size() > before ? p.createMs : 0.0;
}

void cmdHeightForward(VkCommandBuffer cb, const HeightField& hf, HeightPush push, const Buffer& points, uint32_t count,
                      const Buffer& heights) {
  cmdHeightForwardGeneric(cb, hf, push, points, count, heights);
}

}  // namespace refrax
