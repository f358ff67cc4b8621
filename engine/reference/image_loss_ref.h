#pragma once
// CPU double reference of the training losses (engine/loss/image_loss.h), from the same shared
// math (shaders/include/image_loss.glsl) evaluated in double. Images are row-major,
// channel-interleaved. Also the SSIM the evaluation metrics report.
#include <vector>

namespace refrax::ref {

struct ImageLossResult {
  double loss = 0;     // 0.8 * L1 + 0.2 * (1 - SSIM)
  double l1 = 0;       // mean |x - y|
  double ssim = 0;     // mean SSIM map
  std::vector<double> ssimMap;  // per element (the masked metrics average it over the pixels that count)
  std::vector<double> grad;  // dL/dx, filled when asked for
};

// x rendered, y target, both width * height * channels.
ImageLossResult imageLoss(const std::vector<double>& x, const std::vector<double>& y, int width, int height, int channels,
                          bool withGradient);

// Mean SSIM (the 3DGS definition above).
double ssim(const std::vector<double>& x, const std::vector<double>& y, int width, int height, int channels);

// weight * mean(sigmoid(logit)^2); gradient wrt each logit when `grad` is given.
double densityRegularizer(const std::vector<double>& logits, double weight, std::vector<double>* grad);

}  // namespace refrax::ref
