#include "engine/vk/vk_accel.h"

#include <algorithm>
#include <cstring>

#include "engine/base/error.h"
#include "engine/vk/vk_context.h"

namespace refrax {

AccelStruct& AccelStruct::operator=(AccelStruct&& o) noexcept {
  if (this != &o) {
    release();
    ctx = o.ctx;
    handle = o.handle;
    type = o.type;
    storage = std::move(o.storage);
    scratch = std::move(o.scratch);
    scratchAddress = o.scratchAddress;
    address = o.address;
    geometry = o.geometry;
    flags = o.flags;
    primitiveCount = o.primitiveCount;
    built = o.built;
    o.ctx = nullptr;
    o.handle = VK_NULL_HANDLE;
  }
  return *this;
}

void AccelStruct::release() {
  if (ctx && ctx->device && handle) vkDestroyAccelerationStructureKHR(ctx->device, handle, nullptr);
  handle = VK_NULL_HANDLE;
  ctx = nullptr;
  storage.release();
  scratch.release();
}

namespace {

VkAccelerationStructureBuildGeometryInfoKHR buildInfo(const AccelStruct& as, VkBuildAccelerationStructureModeKHR mode) {
  VkAccelerationStructureBuildGeometryInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  info.type = as.type;
  info.flags = as.flags;
  info.mode = mode;
  info.geometryCount = 1;
  info.pGeometries = &as.geometry;
  info.srcAccelerationStructure = mode == VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR ? as.handle : VK_NULL_HANDLE;
  info.dstAccelerationStructure = as.handle;
  info.scratchData.deviceAddress = as.scratchAddress;
  return info;
}

AccelStruct createAccel(Context& ctx, VkAccelerationStructureTypeKHR type, const VkAccelerationStructureGeometryKHR& geometry,
                        uint32_t count, AccelOptions options) {
  if (count == 0) fail("cannot build an acceleration structure over zero primitives");
  AccelStruct as;
  as.ctx = &ctx;
  as.type = type;
  as.geometry = geometry;
  as.primitiveCount = count;
  as.flags = options.preferFastBuild ? VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_BUILD_BIT_KHR
                                     : VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  if (options.allowUpdate) as.flags |= VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR;

  VkAccelerationStructureBuildGeometryInfoKHR info = buildInfo(as, VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR);
  VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  vkGetAccelerationStructureBuildSizesKHR(ctx.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &count, &sizes);

  as.storage = createBuffer(ctx, sizes.accelerationStructureSize, VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR);
  VkDeviceSize align = std::max<VkDeviceSize>(ctx.accelProperties.minAccelerationStructureScratchOffsetAlignment, 1);
  VkDeviceSize scratchBytes = std::max(sizes.buildScratchSize, options.allowUpdate ? sizes.updateScratchSize : 0);
  as.scratch = createBuffer(ctx, std::max<VkDeviceSize>(scratchBytes, 16) + align);
  as.scratchAddress = (as.scratch.address + align - 1) / align * align;

  VkAccelerationStructureCreateInfoKHR ci{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  ci.buffer = as.storage.buffer;
  ci.size = sizes.accelerationStructureSize;
  ci.type = type;
  REFRAX_VK(vkCreateAccelerationStructureKHR(ctx.device, &ci, nullptr, &as.handle));
  VkAccelerationStructureDeviceAddressInfoKHR ai{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  ai.accelerationStructure = as.handle;
  as.address = vkGetAccelerationStructureDeviceAddressKHR(ctx.device, &ai);
  return as;
}

}  // namespace

AccelStruct createTriangleBlas(Context& ctx, const Buffer& vertices, uint32_t vertexCount, uint32_t vertexStride,
                               const Buffer& indices, uint32_t triangleCount, AccelOptions options) {
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
  g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
  auto& t = g.geometry.triangles;
  t.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
  t.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
  t.vertexData.deviceAddress = vertices.address;
  t.vertexStride = vertexStride;
  t.maxVertex = vertexCount - 1;
  t.indexType = VK_INDEX_TYPE_UINT32;
  t.indexData.deviceAddress = indices.address;
  return createAccel(ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, g, triangleCount, options);
}

AccelStruct createAabbBlas(Context& ctx, const Buffer& boxes, uint32_t boxCount, AccelOptions options) {
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_AABBS_KHR;
  g.flags = VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR;  // non-opaque: every box is a candidate
  g.geometry.aabbs.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_AABBS_DATA_KHR;
  g.geometry.aabbs.data.deviceAddress = boxes.address;
  g.geometry.aabbs.stride = sizeof(VkAabbPositionsKHR);
  return createAccel(ctx, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, g, boxCount, options);
}

AccelStruct createTlas(Context& ctx, const Buffer& instances, uint32_t instanceCount, AccelOptions options) {
  VkAccelerationStructureGeometryKHR g{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  g.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  g.geometry.instances.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  g.geometry.instances.arrayOfPointers = VK_FALSE;
  g.geometry.instances.data.deviceAddress = instances.address;
  return createAccel(ctx, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, g, instanceCount, options);
}

void cmdBuild(VkCommandBuffer cb, AccelStruct& as) {
  VkAccelerationStructureBuildGeometryInfoKHR info = buildInfo(as, VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR);
  VkAccelerationStructureBuildRangeInfoKHR range{as.primitiveCount, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
  vkCmdBuildAccelerationStructuresKHR(cb, 1, &info, &ranges);
  as.built = true;
}

void cmdRefit(VkCommandBuffer cb, AccelStruct& as) {
  if (!(as.flags & VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_UPDATE_BIT_KHR))
    fail("refit of an acceleration structure created without allowUpdate");
  if (!as.built) fail("refit of an acceleration structure that was never built");
  VkAccelerationStructureBuildGeometryInfoKHR info = buildInfo(as, VK_BUILD_ACCELERATION_STRUCTURE_MODE_UPDATE_KHR);
  VkAccelerationStructureBuildRangeInfoKHR range{as.primitiveCount, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* ranges = &range;
  vkCmdBuildAccelerationStructuresKHR(cb, 1, &info, &ranges);
}

VkAccelerationStructureInstanceKHR makeInstance(const AccelStruct& blas, uint32_t customIndex, const float* transform3x4,
                                                VkGeometryInstanceFlagsKHR flags, uint8_t mask) {
  VkAccelerationStructureInstanceKHR inst{};
  if (transform3x4) {
    std::memcpy(inst.transform.matrix, transform3x4, sizeof(inst.transform.matrix));
  } else {
    inst.transform.matrix[0][0] = inst.transform.matrix[1][1] = inst.transform.matrix[2][2] = 1.0f;
  }
  inst.instanceCustomIndex = customIndex & 0xFFFFFF;
  inst.mask = mask;
  inst.flags = flags;
  inst.accelerationStructureReference = blas.address;
  return inst;
}

}  // namespace refrax

namespace refrax {

TopLevel createTopLevel(Context& ctx, const std::vector<VkAccelerationStructureInstanceKHR>& instances, AccelOptions options) {
  TopLevel top;
  top.instances = createBuffer(ctx, instances.size() * sizeof(VkAccelerationStructureInstanceKHR),
                               VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR);
  upload(ctx, top.instances, instances.data(), instances.size() * sizeof(VkAccelerationStructureInstanceKHR));
  top.tlas = createTlas(ctx, top.instances, uint32_t(instances.size()), options);
  return top;
}

}  // namespace refrax
