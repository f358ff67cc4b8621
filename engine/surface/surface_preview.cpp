#include "engine/surface/surface_preview.h"

#include "engine/trace/triangle_bvh.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

SurfacePreview createSurfacePreview(Context& ctx, const std::vector<float>& vertices, const std::vector<uint32_t>& indices) {
  SurfacePreview p;
  p.triangleCount = uint32_t(indices.size() / 3);
  p.vertices = createBufferFrom(ctx, vertices, kAccelInput);
  if (ctx.trace == TraceBackend::Compute) {  // a triangle BVH of its own instead of BLAS/TLAS
    std::vector<uint32_t> ordered = trianglesInSplitOrder(vertices, indices);
    p.indices = createBufferFrom(ctx, ordered);
    p.bvh = createTriangleBvh(ctx, vertices, ordered);
    p.pipeline = createComputePipeline(ctx, "view_surface_compute", {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                       sizeof(GpuPinholeCamera) + 32);
    return p;
  }
  p.indices = createBufferFrom(ctx, indices, kAccelInput);
  p.blas = createTriangleBlas(ctx, p.vertices, uint32_t(vertices.size() / 3), 12, p.indices, p.triangleCount);
  p.top = createTopLevel(ctx, {makeInstance(p.blas, 0, nullptr, VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR)});
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBuild(cb, p.blas);
    cmdBarrier(cb);
    cmdBuild(cb, p.top.tlas);
  });
  p.pipeline = createComputePipeline(ctx, "view_surface", {kAccelStruct, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                     sizeof(GpuPinholeCamera) + 32);
  return p;
}

void cmdRenderSurfacePreview(VkCommandBuffer cb, const SurfacePreview& preview, const FlyCamera& camera, uint32_t width,
                             uint32_t height, PreviewMode mode, const float background[3], const Buffer& pixels) {
  struct {
    GpuPinholeCamera cam;
    uint32_t size[4];
    float background[4];
  } push{toGpuCamera(camera, width, height), {width, height, uint32_t(mode), 0}, {background[0], background[1], background[2], 1}};
  cmdDispatch(cb, preview.pipeline,
              {preview.bvh.leaves ? bind(preview.bvh.nodes) : bind(preview.top.tlas), bind(preview.vertices), bind(preview.indices), bind(pixels)},
              &push,
              groupsFor(width, 8), groupsFor(height, 8));
}

Image rgba8ToImage(const std::vector<uint32_t>& pixels, uint32_t width, uint32_t height) {
  Image img;
  img.width = int(width);
  img.height = int(height);
  img.channels = 3;
  img.pixels.resize(size_t(width) * height * 3);
  for (size_t i = 0; i < size_t(width) * height; i++)
    for (int c = 0; c < 3; c++) img.pixels[i * 3 + c] = float((pixels[i] >> (8 * c)) & 0xFF) / 255.0f;
  return img;
}

}  // namespace refrax
