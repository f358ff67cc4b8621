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

// The SSIM map where only the pixels with mask > 0 count (mask: width * height, one weight a
// pixel): each window's means, variances and covariance are taken over its counted pixels,
// the window weights times the mask, normalised; pixels past the image edge keep the zero
// padding above. An all-ones mask gives imageLoss's map; a masked-out pixel's value reaches
// no window (the map at masked-out centres is left 0).
std::vector<double> maskedSsimMap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& mask, int width,
                                  int height, int channels);

// weight * mean(sigmoid(logit)^2); gradient wrt each logit when `grad` is given.
double densityRegularizer(const std::vector<double>& logits, double weight, std::vector<double>* grad);

}  // namespace refrax::ref
