// Image loss (L1 + SSIM) and density regulariser on the device against the double
// reference, and the reference's gradients against central finite differences.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "engine/loss/image_loss.h"
#include "engine/reference/image_loss_ref.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

constexpr uint32_t kNaN = 0x7FC00000u;

struct ImagePair {
  int width, height, channels;
  std::vector<float> rendered, target;
};

// Target uniform in [0,1]; rendered a noisy, partly blurred copy, with some elements equal
// to the target (where the L1 slope is 0).
ImagePair randomPair(std::mt19937& rng, int width, int height, int channels, double minGap) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  ImagePair p{width, height, channels, {}, {}};
  size_t n = size_t(width) * height * channels;
  p.rendered.resize(n);
  p.target.resize(n);
  for (size_t i = 0; i < n; i++) {
    p.target[i] = float(U(rng));
    double noise = (U(rng) - 0.5) * 0.4;
    if (std::abs(noise) < minGap) noise = noise < 0 ? -minGap : minGap;
    p.rendered[i] = float(p.target[i] + noise);
  }
  return p;
}

std::vector<double> toDouble(const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); }

}  // namespace

TEST_CASE("reference SSIM: separable window equals the direct 11x11 window, identical images score 1") {
  std::mt19937 rng(7);
  ImagePair p = randomPair(rng, 14, 9, 2, 0.0);
  auto x = toDouble(p.rendered), y = toDouble(p.target);
  // direct 2D window, zero padded, as 3DGS's conv2d
  double g[11], gs = 0;
  for (int i = 0; i < 11; i++) gs += g[i] = std::exp(-double((i - 5) * (i - 5)) / 4.5);
  for (double& v : g) v /= gs;
  double C1 = 0.01 * 0.01, C2 = 0.03 * 0.03, total = 0;
  for (int py = 0; py < p.height; py++)
    for (int px = 0; px < p.width; px++)
      for (int c = 0; c < p.channels; c++) {
        double m1 = 0, m2 = 0, e11 = 0, e22 = 0, e12 = 0;
        for (int dy = -5; dy <= 5; dy++)
          for (int dx = -5; dx <= 5; dx++) {
            int qx = px + dx, qy = py + dy;
            if (qx < 0 || qy < 0 || qx >= p.width || qy >= p.height) continue;
            size_t q = (size_t(qy) * p.width + qx) * p.channels + c;
            double w = g[dx + 5] * g[dy + 5];
            m1 += w * x[q];
            m2 += w * y[q];
            e11 += w * x[q] * x[q];
            e22 += w * y[q] * y[q];
            e12 += w * x[q] * y[q];
          }
        double s1 = e11 - m1 * m1, s2 = e22 - m2 * m2, s12 = e12 - m1 * m2;
        total += (2 * m1 * m2 + C1) * (2 * s12 + C2) / ((m1 * m1 + m2 * m2 + C1) * (s1 + s2 + C2));
      }
  double direct = total / double(x.size());
  CHECK(ref::ssim(x, y, p.width, p.height, p.channels) == doctest::Approx(direct).epsilon(1e-12));
  CHECK(ref::ssim(x, x, p.width, p.height, p.channels) == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(ref::imageLoss(x, x, p.width, p.height, p.channels, false).loss == doctest::Approx(0.0).epsilon(1e-12));
  CHECK(direct < 0.99);  // the pair really differs
}

TEST_CASE("reference image-loss gradient matches central finite differences") {
  std::mt19937 rng(test::freshSeed());
  ImagePair p = randomPair(rng, 13, 11, 3, 1e-3);  // |x - y| >= 1e-3: away from the L1 kink
  auto x = toDouble(p.rendered), y = toDouble(p.target);
  auto r = ref::imageLoss(x, y, p.width, p.height, p.channels, true);
  const double h = 1e-6;
  double worst = 0, scale = 0;
  for (size_t i = 0; i < x.size(); i++) {
    auto xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    double fd = (ref::imageLoss(xp, y, p.width, p.height, p.channels, false).loss -
                 ref::imageLoss(xm, y, p.width, p.height, p.channels, false).loss) / (2 * h);
    worst = std::max(worst, std::abs(fd - r.grad[i]));
    scale = std::max(scale, std::abs(fd));
  }
  INFO("worst |fd - analytic| " << worst << " of max |fd| " << scale);
  CHECK(scale > 0);
  CHECK(worst < 1e-6 * scale);
}

GPU_TEST_CASE("image loss on the device matches the double reference (loss and dL/drendered)") {
  LossPipelines pipes = createLossPipelines(ctx);
  ImageLossScratch scratch;
  // odd sizes (not multiples of the group or of the 8-output blocks), sizes smaller than the
  // window, one channel, rows longer than one workgroup of pixel blocks
  struct Size {
    int w, h, c;
  };
  for (Size s : {Size{37, 29, 3}, Size{5, 4, 3}, Size{64, 16, 1}, Size{530, 9, 2}}) {  // 530: two groups of pixel blocks
    ImagePair p = randomPair(rng, s.w, s.h, s.c, 0.0);
    for (size_t i = 0; i < p.rendered.size(); i += 7) p.rendered[i] = p.target[i];  // L1 slope 0 here
    auto r = ref::imageLoss(toDouble(p.rendered), toDouble(p.target), s.w, s.h, s.c, true);
    prepareImageLossScratch(ctx, scratch, s.w, s.h, s.c);
    Buffer xb = createBufferFrom(ctx, p.rendered), yb = createBufferFrom(ctx, p.target);
    Buffer gb = createBuffer(ctx, p.rendered.size() * 4), rb = createBuffer(ctx, 16);
    fillBuffer(ctx, gb, kNaN);
    fillBuffer(ctx, rb, kNaN);
    fillBuffer(ctx, scratch.moments, kNaN);
    fillBuffer(ctx, scratch.slopes, kNaN);
    fillBuffer(ctx, scratch.cross, kNaN);
    fillBuffer(ctx, scratch.terms, kNaN);
    fillBuffer(ctx, scratch.partials, kNaN);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdImageLoss(cb, pipes, scratch, xb, yb, gb, rb); });
    auto result = downloadVector<float>(ctx, rb, 4);
    auto grad = downloadVector<float>(ctx, gb, p.rendered.size());
    double n = double(p.rendered.size());
    INFO("size " << s.w << "x" << s.h << "x" << s.c);
    CHECK(result[0] == doctest::Approx(r.loss).epsilon(2e-5));
    CHECK(result[1] == doctest::Approx(r.l1 * n).epsilon(2e-5));
    CHECK(result[2] == doctest::Approx(r.ssim * n).epsilon(2e-5));
    double maxRef = 0, worst = 0;
    size_t bad = 0;
    for (size_t i = 0; i < grad.size(); i++) maxRef = std::max(maxRef, std::abs(r.grad[i]));
    for (size_t i = 0; i < grad.size(); i++) {
      double err = std::abs(double(grad[i]) - r.grad[i]);
      if (!(err <= 1e-4 * maxRef)) bad++;  // NaN counts as bad
      if (std::isfinite(err)) worst = std::max(worst, err);
    }
    INFO("worst gradient error " << worst << " of max " << maxRef);
    CHECK(bad == 0);
  }
  // buffers smaller than the prepared image size are refused before recording
  Buffer tiny = createBuffer(ctx, 16), rb = createBuffer(ctx, 16);
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdImageLoss(cb, pipes, scratch, tiny, tiny, tiny, rb); }), Error);
  ImageLossScratch unprepared;
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdImageLoss(cb, pipes, unprepared, tiny, tiny, tiny, rb); }), Error);
  CHECK_THROWS_AS(prepareImageLossScratch(ctx, unprepared, 0, 4, 3), Error);
}

GPU_TEST_CASE("density regulariser on the device adds the reference gradient and gives the reference value") {
  LossPipelines pipes = createLossPipelines(ctx);
  std::normal_distribution<float> N(0.0f, 3.0f);
  for (uint32_t count : {1u, 300u, 70001u}) {
    std::vector<float> logits(count), prior(count);
    for (auto& v : logits) v = N(rng);
    for (auto& v : prior) v = N(rng);
    logits[0] = -90.0f;  // saturated sigmoid stays finite
    std::vector<double> refGrad;
    double value = ref::densityRegularizer(toDouble(logits), kDensityRegularizerWeight, &refGrad);
    Buffer lb = createBufferFrom(ctx, logits), gb = createBufferFrom(ctx, prior);
    Buffer pb = createBuffer(ctx, densityPartialCount(count) * 8), rb = createBuffer(ctx, 16);
    fillBuffer(ctx, pb, kNaN);
    fillBuffer(ctx, rb, kNaN);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdDensityRegularizer(cb, pipes, lb, count, gb, pb, rb); });
    auto result = downloadVector<float>(ctx, rb, 4);
    auto grad = downloadVector<float>(ctx, gb, count);
    CHECK(result[0] == doctest::Approx(value).epsilon(1e-5));
    size_t bad = 0;
    for (size_t i = 0; i < count; i++) {
      double expect = double(prior[i]) + refGrad[i];
      if (!(std::abs(grad[i] - expect) <= 1e-6 * std::abs(expect) + 1e-7 * std::abs(refGrad[i]) + 1e-12)) bad++;
    }
    CHECK(bad == 0);
  }
  {  // In place in a strided table, as training runs it on the Gaussian table and its gradient:
     // logit i at i * stride + offset; every other value stays as it was.
  const uint32_t count = 1000, stride = 5, offset = 3;
  std::vector<float> table(count * stride), gradTable(count * stride);
  for (auto& v : table) v = N(rng);
  for (auto& v : gradTable) v = N(rng);
  std::vector<double> logits(count), refGrad;
  for (uint32_t i = 0; i < count; i++) logits[i] = table[i * stride + offset];
  const double value = ref::densityRegularizer(logits, 0.05, &refGrad);
  Buffer lb = createBufferFrom(ctx, table), gb = createBufferFrom(ctx, gradTable);
  Buffer pb = createBuffer(ctx, densityPartialCount(count) * 8), rb = createBuffer(ctx, 16);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdDensityRegularizer(cb, pipes, lb, count, gb, pb, rb, 0.05f, stride, offset); });
  CHECK(downloadVector<float>(ctx, rb, 4)[0] == doctest::Approx(value).epsilon(1e-5));
  const std::vector<float> grad = downloadVector<float>(ctx, gb, count * stride);
  size_t bad = 0;
  for (uint32_t k = 0; k < count * stride; k++) {
    const bool slot = k % stride == offset;
    const double expect = double(gradTable[k]) + (slot ? refGrad[k / stride] : 0.0);
    if (!(std::abs(grad[k] - expect) <= (slot ? 1e-6 * std::abs(expect) + 1e-7 * std::abs(refGrad[k / stride]) + 1e-12 : 0.0))) bad++;
  }
  CHECK(bad == 0);
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdDensityRegularizer(cb, pipes, lb, count + 1, gb, pb, rb, 0.05f, stride, offset); }),
                  Error);
  }
  // reference gradient vs finite differences
  std::vector<double> logits(50), g;
  for (auto& v : logits) v = N(rng);
  ref::densityRegularizer(logits, 0.007, &g);
  for (size_t i = 0; i < logits.size(); i++) {
    auto p = logits, m = logits;
    p[i] += 1e-5;
    m[i] -= 1e-5;
    double fd = (ref::densityRegularizer(p, 0.007, nullptr) - ref::densityRegularizer(m, 0.007, nullptr)) / 2e-5;
    CHECK(std::abs(fd - g[i]) <= 1e-6 * std::abs(g[i]) + 1e-12);
    CHECK(std::abs(g[i]) > 0);
  }
}
