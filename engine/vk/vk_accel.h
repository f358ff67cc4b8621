#pragma once
// Acceleration structures: triangle BLAS, AABB BLAS, TLAS; full build and in-place refit.
// Topology is fixed at creation (primitive counts, buffers); a refit (update mode) only
// moves vertices/boxes/instances. Never compacted or copied: lavapipe aborts on those.
// Lavapipe's builder keeps primitives in the order given (engine/trace/presort.h sorts them).
#include <volk.h>

#include <cstdint>
#include <vector>

#include "engine/vk/vk_buffer.h"

namespace refrax {

struct Context;

struct AccelOptions {
  bool allowUpdate = false;  // needed for cmdRefit
  bool preferFastBuild = false;
};

struct AccelStruct {
  Context* ctx = nullptr;
  VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
  VkAccelerationStructureTypeKHR type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
  Buffer storage;
  Buffer scratch;
  VkDeviceAddress scratchAddress = 0;  // aligned
  VkDeviceAddress address = 0;
  VkAccelerationStructureGeometryKHR geometry{};
  VkBuildAccelerationStructureFlagsKHR flags = 0;
  uint32_t primitiveCount = 0;
  bool built = false;

  AccelStruct() = default;
  AccelStruct(const AccelStruct&) = delete;
  AccelStruct& operator=(const AccelStruct&) = delete;
  AccelStruct(AccelStruct&& o) noexcept { *this = std::move(o); }
  AccelStruct& operator=(AccelStruct&& o) noexcept;
  ~AccelStruct() { release(); }
  void release();
};

// Vertices: float3 at `vertexStride` bytes; indices: uint32 triples.
AccelStruct createTriangleBlas(Context& ctx, const Buffer& vertices, uint32_t vertexCount, uint32_t vertexStride,
                               const Buffer& indices, uint32_t triangleCount, AccelOptions options = {});
// Boxes: VkAabbPositionsKHR (6 floats) each; intersections are reported as candidates.
AccelStruct createAabbBlas(Context& ctx, const Buffer& boxes, uint32_t boxCount, AccelOptions options = {});
// Instances: VkAccelerationStructureInstanceKHR each.
AccelStruct createTlas(Context& ctx, const Buffer& instances, uint32_t instanceCount, AccelOptions options = {});

void cmdBuild(VkCommandBuffer cb, AccelStruct& as);
void cmdRefit(VkCommandBuffer cb, AccelStruct& as);  // requires allowUpdate and a prior build

// An instance of `blas` with a 3x4 row-major transform (identity when null).
VkAccelerationStructureInstanceKHR makeInstance(const AccelStruct& blas, uint32_t customIndex, const float* transform3x4 = nullptr,
                                                VkGeometryInstanceFlagsKHR flags = 0, uint8_t mask = 0xFF);

}  // namespace refrax

namespace refrax {

// A TLAS together with the instance buffer it reads (kept alive for refits).
struct TopLevel {
  Buffer instances;
  AccelStruct tlas;
};
TopLevel createTopLevel(Context& ctx, const std::vector<VkAccelerationStructureInstanceKHR>& instances, AccelOptions options = {});

}  // namespace refrax
