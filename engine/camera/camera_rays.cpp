#include "engine/camera/camera_rays.h"

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {
namespace {

struct RayPush {
  float right[4], up[4], back[4], positionTmin[4], intrinsics[4], lensRadial[4], lensExtra[4];
  uint32_t width, count, flags;  // flags: bit 0 the pixel list, bits 8-15 the lens kind
  float tmax;
};
static_assert(sizeof(RayPush) == 128, "RayPush must match camera_rays.comp (and fit the 128 bytes every device has)");

RayPush makePush(const Camera& c, uint32_t count, bool list, float tmin, float tmax) {
  if (c.width <= 0 || c.height <= 0 || !(c.fx > 0) || !(c.fy > 0)) fail("camera rays: the camera has no valid image size or focal length");
  RayPush push{};
  for (int a = 0; a < 3; a++) {
    push.right[a] = float(c.cameraToWorld[0][a]);
    push.up[a] = float(c.cameraToWorld[1][a]);
    push.back[a] = float(c.cameraToWorld[2][a]);
    push.positionTmin[a] = float(c.cameraToWorld[3][a]);
  }
  push.positionTmin[3] = tmin;
  push.intrinsics[0] = float(c.fx);
  push.intrinsics[1] = float(c.fy);
  push.intrinsics[2] = float(c.cx);
  push.intrinsics[3] = float(c.cy);
  for (int a = 0; a < 4; a++) {
    push.lensRadial[a] = float(c.lens.radial[a]);
    push.lensExtra[a] = float(c.lens.extra[a]);
  }
  push.width = uint32_t(c.width);
  push.count = count;
  push.flags = (list ? 1u : 0u) | (uint32_t(c.lens.kind) << 8);
  push.tmax = tmax;
  return push;
}

}  // namespace

CameraRayPipelines createCameraRayPipelines(Context& ctx) {
  CameraRayPipelines p;
  p.rays = createComputePipeline(ctx, "camera_rays", {kStorageBuffer, kStorageBuffer}, sizeof(RayPush));
  p.noPixelList = createBuffer(ctx, 4);
  return p;
}

void cmdCameraRays(VkCommandBuffer cb, const CameraRayPipelines& p, const Camera& camera, const Buffer& rays, float tmin, float tmax) {
  RayPush push = makePush(camera, uint32_t(camera.width) * uint32_t(camera.height), false, tmin, tmax);
  cmdBarrier(cb);  // the ray buffer may still be read by the previous step's tracer
  cmdDispatch(cb, p.rays, {bind(p.noPixelList), bind(rays)}, &push, groupsFor(push.count, 256));
}

void cmdCameraRaysForPixels(VkCommandBuffer cb, const CameraRayPipelines& p, const Camera& camera, const Buffer& pixels, uint32_t count,
                            const Buffer& rays, float tmin, float tmax) {
  if (count == 0) return;
  RayPush push = makePush(camera, count, true, tmin, tmax);
  cmdBarrier(cb);  // the pixel list may come from the previous dispatch
  cmdDispatch(cb, p.rays, {bind(pixels), bind(rays)}, &push, groupsFor(count, 256));
}

}  // namespace refrax
