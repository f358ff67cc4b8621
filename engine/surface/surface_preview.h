#pragma once
// A triangle surface (built-in, learned or loaded) rendered by itself from a camera, shaded
// by normal or with its wireframe: the viewer's surface view and `refrax preview`.
#include <cstdint>

#include "engine/trace/box_bvh.h"
#include "engine/view/fly_camera.h"
#include "engine/surface/grid_mesh.h"
#include "engine/io/image_io.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct SurfacePreview {
  uint32_t triangleCount = 0;
  Buffer vertices, indices;
  AccelStruct blas;
  TopLevel top;
  BoxBvh bvh;  // the compute trace backend's triangle BVH, instead of blas/top
  ComputePipeline pipeline;
};

enum class PreviewMode : uint32_t { Normals = 0, Wireframe = 1 };

SurfacePreview createSurfacePreview(Context& ctx, const std::vector<float>& vertices, const std::vector<uint32_t>& indices);
// Writes width*height packed RGBA8 pixels (row-major, top row first) into `pixels`.
void cmdRenderSurfacePreview(VkCommandBuffer cb, const SurfacePreview& preview, const FlyCamera& camera, uint32_t width,
                             uint32_t height, PreviewMode mode, const float background[3], const Buffer& pixels);
// Packed RGBA8 pixels as an RGB image.
Image rgba8ToImage(const std::vector<uint32_t>& pixels, uint32_t width, uint32_t height);

}  // namespace refrax
