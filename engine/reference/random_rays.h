#pragma once
// Random rays for tests and self-checks: origins spread over a box above a target region,
// directions towards random points of that region (so most rays hit it).
#include <cmath>
#include <random>
#include <vector>

#include "engine/trace/rays.h"

namespace refrax::ref {

struct RayBox {
  float originMin[3], originMax[3];  // where origins are drawn
  float targetMin[3], targetMax[3];  // where directions point to
};

inline std::vector<GpuRay> randomRays(std::mt19937& rng, size_t count, const RayBox& box, float tmax = 100.0f) {
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  std::vector<GpuRay> rays(count);
  for (auto& r : rays) {
    float o[3], t[3];
    for (int a = 0; a < 3; a++) {
      o[a] = box.originMin[a] + (box.originMax[a] - box.originMin[a]) * U(rng);
      t[a] = box.targetMin[a] + (box.targetMax[a] - box.targetMin[a]) * U(rng);
    }
    float d[3] = {t[0] - o[0], t[1] - o[1], t[2] - o[2]};
    float len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int a = 0; a < 3; a++) {
      r.origin[a] = o[a];
      r.dir[a] = d[a] / len;
    }
    r.tmin = 0.0f;
    r.tmax = tmax;
  }
  return rays;
}

}  // namespace refrax::ref
