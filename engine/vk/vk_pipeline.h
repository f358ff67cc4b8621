#pragma once
// Compute pipelines from embedded SPIR-V, and the one way Refrax binds resources:
// every shader declares its resources in set 0 at bindings 0, 1, 2, ... in the order the
// pipeline lists them, and they are pushed per dispatch (VK_KHR_push_descriptor), with
// scalars in one push-constant block. No descriptor pools, no set bookkeeping.
#include <volk.h>

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace refrax {

struct Context;
struct Buffer;
struct AccelStruct;

struct ComputePipeline {
  Context* ctx = nullptr;
  std::string name;
  VkShaderModule module = VK_NULL_HANDLE;
  VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  std::vector<VkDescriptorType> bindings;
  uint32_t pushBytes = 0;
  double createMs = 0;  // pipeline creation time (LLVM JIT on lavapipe)

  ComputePipeline() = default;
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  ComputePipeline(ComputePipeline&& o) noexcept { *this = std::move(o); }
  ComputePipeline& operator=(ComputePipeline&& o) noexcept;
  ~ComputePipeline() { release(); }
  void release();
};

// Specialization constant: constant_id = id, 32-bit value (int, uint or float bits).
struct SpecConstant {
  uint32_t id;
  uint32_t value;
};
SpecConstant specFloat(uint32_t id, float v);

constexpr VkDescriptorType kStorageBuffer = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kAccelStruct = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
constexpr VkDescriptorType kStorageImage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;

ComputePipeline createComputePipeline(Context& ctx, const char* shaderName, std::vector<VkDescriptorType> bindings,
                                      uint32_t pushBytes, const std::vector<SpecConstant>& spec = {});
// The bindings of a shader whose resources are all storage buffers.
inline std::vector<VkDescriptorType> storageBuffers(uint32_t count) { return std::vector<VkDescriptorType>(count, kStorageBuffer); }

// One resource bound at one binding of a dispatch.
struct Binding {
  VkDescriptorType type;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkAccelerationStructureKHR accel = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
};
Binding bind(const Buffer& b);
Binding bind(const AccelStruct& a);
Binding bindImage(VkImageView view);

// Pushes the bindings (checked against the pipeline's list) and the push constants, then
// dispatches groups (gx, gy, gz).
void cmdDispatch(VkCommandBuffer cb, const ComputePipeline& p, std::initializer_list<Binding> bindings, const void* push,
                 uint32_t gx, uint32_t gy = 1, uint32_t gz = 1);

// The same, with the group counts (a VkDispatchIndirectCommand) read from `args` at `offset`
// when the dispatch runs: a count the device computed earlier in the same submission. `args`
// needs kIndirectArgs usage.
void cmdDispatchIndirect(VkCommandBuffer cb, const ComputePipeline& p, std::initializer_list<Binding> bindings, const void* push,
                         const Buffer& args, VkDeviceSize offset);

inline uint32_t groupsFor(uint32_t items, uint32_t groupSize) { return (items + groupSize - 1) / groupSize; }

}  // namespace refrax
