#include "engine/reference/image_loss_ref.h"

#include <cmath>

#include "engine/base/error.h"
#include "engine/base/shared_math.h"

namespace refrax::f64 {
#include "image_loss.glsl"
}

namespace refrax::ref {
namespace {

// Zero-padded separable window sum of a channel-interleaved plane.
std::vector<double> windowSum(const std::vector<double>& in, int width, int height, int channels) {
  std::vector<double> horizontal(in.size(), 0.0), out(in.size(), 0.0);
  const int r = f64::kSsimRadius;
  double weight[2 * f64::kSsimRadius + 1];
  for (int k = -r; k <= r; k++) weight[k + r] = f64::ssimWindowWeight(k);
  for (int py = 0; py < height; py++)
    for (int px = 0; px < width; px++)
      for (int c = 0; c < channels; c++) {
        double s = 0;
        for (int k = -r; k <= r; k++)
          if (px + k >= 0 && px + k < width) s += weight[k + r] * in[(size_t(py) * width + px + k) * channels + c];
        horizontal[(size_t(py) * width + px) * channels + c] = s;
      }
  for (int py = 0; py < height; py++)
    for (int px = 0; px < width; px++)
      for (int c = 0; c < channels; c++) {
        double s = 0;
        for (int k = -r; k <= r; k++)
          if (py + k >= 0 && py + k < height) s += weight[k + r] * horizontal[(size_t(py + k) * width + px) * channels + c];
        out[(size_t(py) * width + px) * channels + c] = s;
      }
  return out;
}

void checkSizes(const std::vector<double>& x, const std::vector<double>& y, int width, int height, int channels) {
  size_t n = size_t(width) * height * channels;
  if (width <= 0 || height <= 0 || channels <= 0 || x.size() != n || y.size() != n)
    fail("image loss: images of " + std::to_string(x.size()) + " and " + std::to_string(y.size()) + " values do not match " +
         std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels));
}

}  // namespace

ImageLossResult imageLoss(const std::vector<double>& x, const std::vector<double>& y, int width, int height, int channels, bool withGradient) {
  checkSizes(x, y, width, height, channels);
  const size_t n = x.size();
  std::vector<double> xx(n), yy(n), xy(n);
  for (size_t i = 0; i < n; i++) {
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  auto mu1 = windowSum(x, width, height, channels), mu2 = windowSum(y, width, height, channels);
  auto exx = windowSum(xx, width, height, channels), eyy = windowSum(yy, width, height, channels);
  auto exy = windowSum(xy, width, height, channels);
  std::vector<double> dMu1(n), dExx(n), dExy(n);
  ImageLossResult r;
  r.ssimMap.resize(n);
  for (size_t i = 0; i < n; i++) {
    double value;
    f64::ssimTerms(mu1[i], mu2[i], exx[i], eyy[i], exy[i], value, dMu1[i], dExx[i], dExy[i]);
    r.ssimMap[i] = value;
    r.ssim += value;
    r.l1 += std::abs(x[i] - y[i]);
  }
  r.ssim /= double(n);
  r.l1 /= double(n);
  r.loss = f64::kLossL1Weight * r.l1 + f64::kLossSsimWeight * (1.0 - r.ssim);
  if (withGradient) {
    auto A = windowSum(dMu1, width, height, channels), B = windowSum(dExx, width, height, channels);
    auto C = windowSum(dExy, width, height, channels);
    r.grad.resize(n);
    for (size_t i = 0; i < n; i++) {
      double dSsim = A[i] + 2.0 * x[i] * B[i] + y[i] * C[i];
      r.grad[i] = (f64::kLossL1Weight * f64::l1Slope(x[i], y[i]) - f64::kLossSsimWeight * dSsim) / double(n);
    }
  }
  return r;
}

double ssim(const std::vector<double>& x, const std::vector<double>& y, int width, int height, int channels) {
  return imageLoss(x, y, width, height, channels, false).ssim;
}

std::vector<double> maskedSsimMap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& mask, int width,
                                  int height, int channels) {
  checkSizes(x, y, width, height, channels);
  if (mask.size() != size_t(width) * height) fail("masked SSIM: the mask has " + std::to_string(mask.size()) + " values for " +
                                                  std::to_string(width) + "x" + std::to_string(height) + " pixels");
  const size_t n = x.size();
  std::vector<double> m(n), ones(n, 1.0), mx(n), my(n), mxx(n), myy(n), mxy(n);
  for (size_t i = 0; i < n; i++) {
    m[i] = mask[i / size_t(channels)];
    mx[i] = m[i] * x[i];
    my[i] = m[i] * y[i];
    mxx[i] = mx[i] * x[i];
    myy[i] = my[i] * y[i];
    mxy[i] = mx[i] * y[i];
  }
  // The window's weight: its counted pixels' plus the padding's (zeros that count, as unmasked).
  const std::vector<double> inside = windowSum(ones, width, height, channels), counted = windowSum(m, width, height, channels);
  const auto sx = windowSum(mx, width, height, channels), sy = windowSum(my, width, height, channels);
  const auto sxx = windowSum(mxx, width, height, channels), syy = windowSum(myy, width, height, channels);
  const auto sxy = windowSum(mxy, width, height, channels);
  std::vector<double> map(n, 0.0);
  for (size_t i = 0; i < n; i++) {
    if (!(m[i] > 0)) continue;
    const double w = counted[i] + (1.0 - inside[i]);
    double value, d1, d2, d3;
    f64::ssimTerms(sx[i] / w, sy[i] / w, sxx[i] / w, syy[i] / w, sxy[i] / w, value, d1, d2, d3);
    map[i] = value;
  }
  return map;
}

double densityRegularizer(const std::vector<double>& logits, double weight, std::vector<double>* grad) {
  if (logits.empty()) return 0.0;
  double sum = 0;
  const double scale = weight / double(logits.size());
  if (grad) grad->resize(logits.size());
  for (size_t i = 0; i < logits.size(); i++) {
    double s = f64::sigmoidOf(logits[i]);
    sum += s * s;
    if (grad) (*grad)[i] = scale * f64::densitySquareSlope(logits[i]);
  }
  return scale * sum;
}

}  // namespace refrax::ref
