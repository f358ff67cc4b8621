#pragma once
// Camera rays on the device: a GpuRay (engine/trace/rays.h) from the camera's position through the
// centre of each pixel, unit direction, t in [tmin, tmax]. Like every cmd* stage of the
// trainer's pieces (losses, Adam), recording starts with a barrier, so inputs may come from
// the dispatch before and outputs be read by a later stage that does the same.
#include <cstdint>

#include "engine/camera/camera.h"
#include "engine/trace/rays.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

struct Context;

struct CameraRayPipelines {
  ComputePipeline rays;
  Buffer noPixelList;  // bound in the whole-image mode, never read
};
CameraRayPipelines createCameraRayPipelines(Context& ctx);

// Every pixel: rays[y * width + x] (width * height GpuRay).
void cmdCameraRays(VkCommandBuffer cb, const CameraRayPipelines& p, const Camera& camera, const Buffer& rays, float tmin, float tmax);
// The listed pixels (uint32 y * width + x each): rays[i] for pixels[i], i < count.
void cmdCameraRaysForPixels(VkCommandBuffer cb, const CameraRayPipelines& p, const Camera& camera, const Buffer& pixels,
                            uint32_t count, const Buffer& rays, float tmin, float tmax);

}  // namespace refrax
