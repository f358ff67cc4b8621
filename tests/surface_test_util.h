#pragma once
// Helpers shared by the water-surface tests: run a trace with poisoned outputs and read
// everything back.
#include <cstring>
#include <vector>

#include <glm/glm.hpp>

#include "engine/height/analytic_height.h"
#include "engine/height/height_field.h"
#include "engine/reference/random_rays.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/surface/water_surface.h"

namespace refrax::test {

constexpr uint32_t kPoison = 0x7FC00000u;  // quiet NaN

// An MLP the generated (fused) kernels run, its last layer drawn for ripples of a few
// hundredths: a water-like slope range.
inline HeightFieldConfig rippleField() {
  HeightFieldConfig hc;
  hc.width = 32;
  hc.hiddenLayers = 3;
  hc.octaves = 2;
  hc.lastLayerInitRange = 0.05f;
  return hc;
}

struct SurfaceRun {
  Buffer rays, refracted, records;
  std::vector<GpuRay> refractedRays;
  std::vector<SurfaceRecord> recordList;
  std::vector<float> hitNormals;  // 16 floats per ray when keepHitNormals
  SurfaceCounters counters;
};

inline SurfaceRun runSurface(Context& ctx, WaterSurface& ws, const HeightSource& hs, const std::vector<GpuRay>& rays) {
  SurfaceRun run;
  uint32_t n = uint32_t(rays.size());
  run.rays = createBufferFrom(ctx, rays);
  run.refracted = createBuffer(ctx, std::max<size_t>(rays.size(), 1) * sizeof(GpuRay));
  run.records = createBuffer(ctx, std::max<size_t>(rays.size(), 1) * sizeof(SurfaceRecord));
  fillBuffer(ctx, run.refracted, kPoison);
  fillBuffer(ctx, run.records, kPoison);
  fillBuffer(ctx, ws.hitNormals, kPoison);
  traceSurface(ctx, ws, hs, run.rays, n, run.refracted, run.records);
  run.refractedRays = downloadVector<GpuRay>(ctx, run.refracted, n);
  run.recordList = downloadVector<SurfaceRecord>(ctx, run.records, n);
  if (ws.config.keepHitNormals) run.hitNormals = downloadVector<float>(ctx, ws.hitNormals, size_t(n) * 16);
  run.counters = ws.lastCounters;
  return run;
}

inline void updateSurface(Context& ctx, WaterSurface& ws, const HeightSource& hs) {
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, ws, hs); });
}

// Rays from above towards the domain [-1, 1]^2 (most hit it).
// Origins over [-originSpread, originSpread]^2 at z 1..2, aimed at [-spread, spread]^2 near z 0.
inline std::vector<GpuRay> raysFromAbove(std::mt19937& rng, size_t count, float spread = 1.0f, float originSpread = 1.5f) {
  float o = originSpread;
  return ref::randomRays(rng, count, {{-o, -o, 1.0f}, {o, o, 2.0f}, {-spread, -spread, -0.1f}, {spread, spread, 0.1f}});
}

inline glm::dvec3 vec3Of(const float* v) { return {v[0], v[1], v[2]}; }

}  // namespace refrax::test
