// Masks (engine/dataset/view_image.h, View::mask): a pixel whose mask is 0 must not count. The
// loaders find masks/ (mirroring the image folder) or <image>_mask.png; training's loss
// gradient, the backward and densification's statistics ignore those pixels; the metrics
// measure the others only.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"
#include "engine/loss/metrics.h"
#include "engine/vk/vk_commands.h"
#include "tests/train_test_util.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// 1 in the left half of the image, 0 in the right half.
Image leftHalf(int width, int height) {
  Image m{width, height, 1, std::vector<float>(size_t(width) * height, 0.0f)};
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width / 2; x++) m.at(x, y, 0) = 1.0f;
  return m;
}

struct BatchGradients {
  double loss = 0;
  std::vector<float> grads, stats;
  std::vector<GpuRayGrad> rayGrads;
};

// The first batch's loss, Gaussian gradients, statistics and ray gradients, without a step.
BatchGradients firstBatchGradients(Context& ctx, const TrainConfig& c, const Dataset& d) {
  auto s = createTrainSession(ctx, c, d);
  const StepBatch batch = nextStepBatch(*s);
  const TraceOptions opt = stepTraceOptions(*s, batch, 1);
  fillBuffer(ctx, s->buffers.grads, 0);
  fillBuffer(ctx, s->buffers.stats, 0);
  BatchGradients g;
  g.loss = forwardBatch(*s, batch, opt, [&](VkCommandBuffer cb, const BatchContext& context) { cmdBackwardBatch(cb, *s, context, false); }).imageLoss;
  g.grads = downloadVector<float>(ctx, s->buffers.grads, s->model.gaussians.count() * kGaussianFloats);
  g.stats = downloadVector<float>(ctx, s->buffers.stats, s->model.gaussians.count() * 2);
  g.rayGrads = downloadVector<GpuRayGrad>(ctx, s->buffers.rayGrads, batch.rays());
  return g;
}

double largestDifference(const std::vector<float>& a, const std::vector<float>& b, double& largest) {
  double worst = 0;
  largest = 0;
  for (size_t i = 0; i < a.size(); i++) {
    worst = std::max(worst, std::abs(double(a[i]) - b[i]));
    largest = std::max(largest, std::abs(double(a[i])));
  }
  return worst;
}

}  // namespace

GPU_TEST_CASE("masks: what a masked pixel shows changes neither the loss's gradient nor the statistics") {
  const std::string data = test::tinyDataset("nerfrac-primary-sine");
  Dataset clean;
  TrainConfig c = test::sessionConfig(data, 10, 400, 0, 7, clean);  // whole images: the batch spans both halves
  // The same views with their right halves masked, and again with noise painted there.
  Dataset masked = clean, noisy = clean;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  for (Dataset* d : {&masked, &noisy})
    for (View& v : d->splits["train"]) v.mask = leftHalf(v.image.width, v.image.height);
  for (View& v : noisy.splits["train"])
    for (int y = 0; y < v.image.height; y++)
      for (int x = v.image.width / 2; x < v.image.width; x++)
        for (int ch = 0; ch < 3; ch++) v.image.at(x, y, ch) = U(rng);
  Dataset noisyUnmasked = noisy;
  for (View& v : noisyUnmasked.splits["train"]) v.mask = Image{};

  const BatchGradients a = firstBatchGradients(ctx, c, masked), b = firstBatchGradients(ctx, c, noisy);
  const BatchGradients unmasked = firstBatchGradients(ctx, c, noisyUnmasked);
  CHECK(a.loss == doctest::Approx(b.loss).epsilon(1e-6));
  double largest = 0;
  const double gradDiff = largestDifference(a.grads, b.grads, largest);
  REQUIRE(largest > 0);
  CHECK(gradDiff <= 1e-5 * largest);  // the same up to the order of float atomics
  const double statDiff = largestDifference(a.stats, b.stats, largest);
  CHECK(statDiff <= 1e-5 * largest);
  // the masked half's rays carry no gradient to the water
  size_t zero = 0, counted = 0;
  for (const GpuRayGrad& g : a.rayGrads) {
    bool none = true;
    for (int k = 0; k < 3; k++) none = none && g.dOrigin[k] == 0 && g.dDir[k] == 0;
    zero += none ? 1 : 0;
    counted++;
  }
  CHECK(zero >= counted / 2);
  // Without the mask the noise counts: the same batch's gradient differs.
  double unmaskedLargest = 0;
  CHECK(largestDifference(a.grads, unmasked.grads, unmaskedLargest) > 0.05 * unmaskedLargest);
  CHECK(unmasked.loss > 1.2 * a.loss);
}

TEST_CASE("masks: found in masks/ or beside the image, counted, checked, and the metrics measure the pixels that count" *
          doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::string data = dir / "data";
  fs::copy(test::tinyDataset("nerfrac-primary-sine"), data, fs::copy_options::recursive);
  const Dataset plain = loadDataset(data);
  const View& first = plain.split("train")[0];
  const int w = first.image.width, h = first.image.height;
  // Blender: masks/<file_path>.png for the first training view
  const std::string relative = fs::path(first.name).lexically_normal().generic_string();
  fs::create_directories(fs::path(data) / "masks" / fs::path(relative).parent_path());
  writePng(data + "/masks/" + relative + ".png", leftHalf(w, h));
  Dataset d = loadDataset(data);
  CHECK(d.split("train")[0].mask.pixels == leftHalf(w, h).pixels);
  CHECK(d.split("train")[1].mask.pixels.empty());
  bool noted = false;
  for (const std::string& n : d.notes) noted = noted || n.find("masks: 1 of") == 0;
  CHECK(noted);
  // LLFF: <image>_mask.png beside the image, not taken for an image of its own
  Dataset llff = loadLlffDataset(data);
  const std::string llffImage = data + "/" + llff.split("train")[0].name;
  writePng(llffImage.substr(0, llffImage.size() - 4) + "_mask.png", leftHalf(w, h));
  Dataset llffMasked = loadLlffDataset(data);
  CHECK(llffMasked.split("train")[0].mask.pixels == leftHalf(w, h).pixels);
  CHECK(llffMasked.split("train").size() == llff.split("train").size());
  // a mask of the wrong size, and one that leaves nothing, name the mask
  writePng(data + "/masks/" + relative + ".png", leftHalf(w + 2, h));
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains(("mask " + data + "/masks/" + relative + ".png is").c_str()), Error);
  writePng(data + "/masks/" + relative + ".png", Image{w, h, 1, std::vector<float>(size_t(w) * h, 0.0f)});
  CHECK_THROWS_WITH_AS(loadDataset(data), doctest::Contains("leaves no pixel that counts"), Error);

  // Metrics over the left half only equal the metrics of the left halves, and a difference in
  // the right half is unseen: PSNR and SSIM alike to rounding (SSIM's windows take their
  // statistics over counted pixels only; averaging the whole image's map let the right half
  // into the windows that straddle the edge: 0.81 against 0.76 here).
  Image a = first.image, b = first.image;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> U(-0.1f, 0.1f);
  for (float& v : b.pixels) v = std::clamp(v + U(rng), 0.0f, 1.0f);
  Image c = b;
  for (int y = 0; y < h; y++)
    for (int x = w / 2; x < w; x++)
      for (int ch = 0; ch < 3; ch++) c.at(x, y, ch) = 1.0f - c.at(x, y, ch);
  const Image mask = leftHalf(w, h);
  CHECK(psnr(a, b, mask) == doctest::Approx(psnr(a, c, mask)).epsilon(1e-12));
  CHECK(ssim(a, b, mask) == doctest::Approx(ssim(a, c, mask)).epsilon(1e-12));
  CHECK(ssim(a, c, mask) > ssim(a, c) + 0.05);  // the right half, inverted, counts unmasked
  CHECK(psnr(a, c) < psnr(a, c, mask) - 3);
  auto crop = [&](const Image& im) {
    Image out{w / 2, h, 3, {}};
    for (int y = 0; y < h; y++)
      for (int x = 0; x < w / 2; x++)
        for (int ch = 0; ch < 3; ch++) out.pixels.push_back(im.at(x, y, ch));
    return out;
  };
  CHECK(psnr(a, b, mask) == doctest::Approx(psnr(crop(a), crop(b))).epsilon(1e-12));
  Image ones{w, h, 1, std::vector<float>(size_t(w) * h, 1.0f)};
  CHECK(ssim(a, b, ones) == doctest::Approx(ssim(a, b)).epsilon(1e-12));
  CHECK_THROWS_WITH_AS(psnr(a, b, leftHalf(w, h + 1)), doctest::Contains("PSNR: the mask is"), Error);
}

}  // namespace refrax
