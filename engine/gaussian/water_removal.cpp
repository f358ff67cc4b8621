#include "engine/gaussian/water_removal.h"

#include "engine/base/error.h"
#include "engine/vk/vk_commands.h"

namespace refrax {

std::vector<GpuTraceResult> renderWithoutWater(Context& ctx, GaussianTracer& tracer, const CameraRayPipelines& cameraRays,
                                               const GaussianProxies& proxies, const DeviceGaussians& gaussians, const Camera& camera,
                                               const TraceOptions& options, std::vector<GpuRay>* rays) {
  const uint32_t count = uint32_t(camera.width) * uint32_t(camera.height);
  if (count == 0) fail("render without water: the camera has no pixels");
  Buffer rayBuf = createBuffer(ctx, VkDeviceSize(count) * sizeof(GpuRay));
  Buffer results = createBuffer(ctx, VkDeviceSize(count) * sizeof(GpuTraceResult));
  fillBuffer(ctx, results, 0x7FC00000u);  // NaN: a pixel the tracer did not write shows
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdCameraRays(cb, cameraRays, camera, rayBuf, 0.0f, 1e6f);
    cmdBarrier(cb);
    cmdTraceForward(cb, tracer, proxies, gaussians, rayBuf, results, count, options);
  });
  if (rays) *rays = downloadVector<GpuRay>(ctx, rayBuf, count);
  return downloadVector<GpuTraceResult>(ctx, results, count);
}

}  // namespace refrax
