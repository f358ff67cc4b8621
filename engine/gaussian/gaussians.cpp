#include "engine/gaussian/gaussians.h"

#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"

namespace refrax {

static_assert(kGaussianFloats == f32::kGaussFloats, "host and shader Gaussian layouts differ");

DeviceGaussians uploadGaussians(Context& ctx, const GaussianSet& set) {
  if (set.count() == 0) fail("no Gaussians to upload");
  validateGaussians(set, "Gaussians to upload");
  DeviceGaussians dev;
  dev.count = uint32_t(set.count());
  dev.params = createBufferFrom(ctx, set.params);
  return dev;
}

void updateGaussians(Context& ctx, DeviceGaussians& dev, const GaussianSet& set) {
  if (set.count() != dev.count) fail("updateGaussians: the Gaussian count changed (rebuild instead)");
  validateGaussians(set, "Gaussians to upload");
  upload(ctx, dev.params, set.params.data(), set.params.size() * sizeof(float));
}

GaussianSet downloadGaussians(Context& ctx, const DeviceGaussians& dev) {
  GaussianSet set;
  set.params = downloadVector<float>(ctx, dev.params, size_t(dev.count) * kGaussianFloats);
  return set;
}

}  // namespace refrax
