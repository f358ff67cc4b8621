#pragma once
// The MLP height field (engine/height/height_field.h) as a HeightSource for the water surface, and
// the water-surface calls in terms of a HeightField (what the trainer and viewer use).
#include "engine/height/height_field.h"
#include "engine/height/height_source.h"
#include "engine/surface/water_surface.h"

namespace refrax {

// Evaluation only (accumulateGradients is empty).
HeightSource heightSource(const HeightField& hf);
// Gradients accumulate into dLossdWeights (parameterCount floats; never overwritten).
HeightSource heightSource(const HeightField& hf, const Buffer& dLossdWeights);

inline void cmdUpdateSurface(VkCommandBuffer cb, WaterSurface& ws, const HeightField& hf) { cmdUpdateSurface(cb, ws, heightSource(hf)); }
inline void traceSurface(Context& ctx, WaterSurface& ws, const HeightField& hf, const Buffer& rays, uint32_t count,
                         Buffer& refractedRays, Buffer& records, SurfaceTimings* timings = nullptr) {
  traceSurface(ctx, ws, heightSource(hf), rays, count, refractedRays, records, timings);
}
inline void cmdBackwardSurface(VkCommandBuffer cb, WaterSurface& ws, const HeightField& hf, const Buffer& rays, const Buffer& records,
                               const Buffer& rayGrads, uint32_t count, const Buffer& dLossdWeights) {
  cmdBackwardSurface(cb, ws, heightSource(hf, dLossdWeights), rays, records, rayGrads, count);
}

}  // namespace refrax
