#include "engine/train/gradient_check.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"
#include "engine/height/height_field.h"
#include "engine/surface/height_field_source.h"
#include "engine/vk/vk_commands.h"

namespace refrax {
namespace {

// The surface lifted from `weights`; returns the coarse grid's heights.
std::vector<float> liftSurface(TrainSession& s, const std::vector<float>& weights) {
  uploadWeights(*s.model.ctx, *s.model.height, weights);
  submitAndWait(*s.model.ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, *s.model.surface, *s.model.height); });
  return downloadVector<float>(*s.model.ctx, s.model.surface->gridHeights, s.model.surface->gridPointCount);
}

}  // namespace

SurfaceGradientCheck checkSurfaceGradient(TrainSession& s, const StepBatch& batch, std::vector<double> direction,
                                          const std::vector<double>& steps) {
  if (!s.model.height || !s.model.surface) fail("the gradient check needs the learned water (the refraction model)");
  Context& ctx = *s.model.ctx;
  pushWaterGradient(s);  // the pending sum goes to heightGrad, which is kept and put back below
  const TraceOptions opt = stepTraceOptions(s, batch, s.model.step + 1);
  SurfaceGradientCheck r;
  const BatchForward forward = forwardBatch(s, batch, opt);
  r.loss = forward.imageLoss;
  // The gradient summed since the last surface step (--surface-batch), put back at the end.
  const std::vector<float> pendingSum = downloadVector<float>(ctx, s.water.heightGrad, s.model.height->parameterCount);
  fillBuffer(ctx, s.buffers.grads, 0);
  fillBuffer(ctx, s.buffers.stats, 0);
  fillBuffer(ctx, s.water.heightGrad, 0);
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBackwardBatch(cb, s, forward.context, true);
    cmdPushSurfaceGradients(cb, *s.model.surface, heightSource(*s.model.height, s.water.heightGrad));
  });
  std::vector<float> gradient = downloadVector<float>(ctx, s.water.heightGrad, s.model.height->parameterCount);
  const std::vector<GpuRayGrad> rayGrads = downloadVector<GpuRayGrad>(ctx, s.buffers.rayGrads, batch.rays());
  for (float g : gradient) r.gradientNorm += double(g) * g;
  r.gradientNorm = std::sqrt(r.gradientNorm);
  if (direction.empty()) direction.assign(gradient.begin(), gradient.end());
  if (direction.size() != gradient.size())
    fail("the gradient check's direction has " + std::to_string(direction.size()) + " values, the height MLP " +
         std::to_string(gradient.size()) + " weights");
  double norm = 0;
  for (double d : direction) norm += d * d;
  norm = std::sqrt(norm);
  if (!(norm > 0)) fail("the gradient check's direction is zero (the batch gave the surface no gradient)");
  for (size_t i = 0; i < direction.size(); i++) {
    direction[i] /= norm;
    r.slope += direction[i] * gradient[i];
  }

  const std::vector<float> weights = downloadWeights(ctx, *s.model.height);
  const std::vector<float> heights = downloadVector<float>(ctx, s.model.surface->gridHeights, s.model.surface->gridPointCount);
  auto lossAt = [&](double h, double* heightChange, std::vector<GpuRay>* rays) {
    std::vector<float> w(weights);
    for (size_t i = 0; i < w.size(); i++) w[i] = float(double(weights[i]) + h * direction[i]);
    std::vector<float> lifted = liftSurface(s, w);
    if (heightChange) {
      *heightChange = 0;
      for (size_t k = 0; k < lifted.size(); k++)
        if (std::isfinite(lifted[k]) && std::isfinite(heights[k]))
          *heightChange = std::max(*heightChange, std::abs(double(lifted[k]) - heights[k]));
    }
    double loss = forwardBatch(s, batch, opt).imageLoss;
    *rays = downloadVector<GpuRay>(ctx, s.model.refracted, batch.rays());
    return loss;
  };
  for (double h : steps) {
    double change = 0;
    std::vector<GpuRay> up, down;
    double plus = lossAt(h, &change, &up), minus = lossAt(-h, nullptr, &down);
    double predicted = 0;
    for (size_t i = 0; i < rayGrads.size(); i++)
      for (int k = 0; k < 3; k++)
        predicted += double(rayGrads[i].dOrigin[k]) * (double(up[i].origin[k]) - down[i].origin[k]) +
                     double(rayGrads[i].dDir[k]) * (double(up[i].dir[k]) - down[i].dir[k]);
    r.rayPredictions.push_back(predicted / (2 * h));
    r.steps.push_back(h);
    r.centralDifferences.push_back((plus - minus) / (2 * h));
    r.heightChanges.push_back(change);
  }
  liftSurface(s, weights);
  upload(ctx, s.water.heightGrad, pendingSum.data(), pendingSum.size() * 4);
  return r;
}

}  // namespace refrax
