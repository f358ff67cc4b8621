// Adam on the device against the double reference over several steps, the learning-rate
// schedules, and the row remapping densification needs.
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/optim/adam.h"
#include "engine/reference/adam_ref.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

TEST_CASE("learning-rate schedules are log-linear from the initial to the final rate, then hold") {
  LearningRateSchedule s{1.6e-4 * 3.0, 1.6e-6 * 3.0, 30000};
  CHECK(s.at(0) == doctest::Approx(4.8e-4).epsilon(1e-12));
  CHECK(s.at(30000) == doctest::Approx(4.8e-6).epsilon(1e-12));
  CHECK(s.at(90000) == doctest::Approx(4.8e-6).epsilon(1e-12));
  CHECK(s.at(15000) == doctest::Approx(std::sqrt(4.8e-4 * 4.8e-6)).epsilon(1e-12));
  CHECK(s.at(7500) == doctest::Approx(4.8e-4 * std::pow(1e-2, 0.25)).epsilon(1e-12));
  CHECK(s.at(100) < s.at(99));
  LearningRateSchedule constant{0.05, 0.05, 1};
  CHECK(constant.at(0) == 0.05);
  CHECK(constant.at(12345) == 0.05);

  auto rates = referenceLearningRates(2.0);
  CHECK(rates.size() == 7);
  CHECK(referenceLearningRate("position", 2.0).initial == doctest::Approx(3.2e-4));
  CHECK(referenceLearningRate("position", 2.0).final == doctest::Approx(3.2e-6));
  CHECK(referenceLearningRate("height_mlp", 2.0).at(30000) == doctest::Approx(5e-6));
  CHECK(referenceLearningRate("sh_rest", 2.0).at(20000) == doctest::Approx(1.25e-4));
  CHECK(referenceLearningRate("scale", 1.0).at(0) == doctest::Approx(5e-3));
  CHECK_THROWS_AS(referenceLearningRate("opacity_typo", 1.0), Error);
}

GPU_TEST_CASE("Adam on the device matches the double reference over several steps with a decaying rate") {
  AdamPipelines pipes = createAdamPipelines(ctx);
  const uint32_t rows = 1001, width = 3, offset = 17, total = offset + rows * width + 5;
  std::normal_distribution<float> N(0.0f, 1.0f);
  std::vector<float> params(total), grads(total);
  for (auto& p : params) p = N(rng);
  LearningRateSchedule lr{1e-2, 1e-4, 4};  // short, so every step has its own rate
  AdamGroup group = createAdamGroup(ctx, "position", lr, width, rows);
  Buffer pb = createBufferFrom(ctx, params);
  Buffer gb = createBuffer(ctx, total * 4);
  std::vector<double> p(params.begin() + offset, params.begin() + offset + rows * width), m(p.size(), 0.0), v(p.size(), 0.0);
  for (int step = 1; step <= 6; step++) {
    for (auto& g : grads) g = N(rng) * (step % 2 ? 1e-3f : 10.0f);  // gradients of very different size
    for (uint32_t i = 0; i < 50; i++) grads[offset + i] = 0.0f;       // untouched rows stay put at first
    upload(ctx, gb, grads.data(), total * 4);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdAdamStep(cb, pipes, group, pb, gb, offset, step % 2 == 0); });
    std::vector<double> g(grads.begin() + offset, grads.begin() + offset + rows * width);
    ref::adamStep(p, m, v, g, lr.at(step), step);
    CHECK(group.step == step);
    auto back = downloadVector<float>(ctx, pb, total);
    auto gradBack = downloadVector<float>(ctx, gb, total);
    auto mBack = downloadVector<float>(ctx, group.m, p.size());
    size_t bad = 0, badMoments = 0;
    double mScale = 0;  // m is a sum of terms of either sign: its float error scales with the largest
    for (double x : m) mScale = std::max(mScale, std::abs(x));
    for (size_t i = 0; i < p.size(); i++) {
      if (!(std::abs(back[offset + i] - p[i]) <= 1e-6 * std::abs(p[i]) + 1e-4 * 1e-2 * step)) bad++;
      if (!(std::abs(mBack[i] - m[i]) <= 1e-5 * std::abs(m[i]) + 1e-6 * mScale)) badMoments++;
    }
    CHECK(bad == 0);
    CHECK(badMoments == 0);
    // floats outside the group are untouched; gradients cleared only when asked
    for (uint32_t i = 0; i < offset; i++) CHECK(back[i] == params[i]);
    for (uint32_t i = offset + rows * width; i < total; i++) CHECK(back[i] == params[i]);
    CHECK(gradBack[offset + 60] == (step % 2 == 0 ? 0.0f : grads[offset + 60]));
    CHECK(gradBack[0] == grads[0]);
    if (step == 1) CHECK(back[offset + 10] == params[offset + 10]);  // zero gradient, zero moments: no move
    // an actual move of about lr per step
    CHECK(std::abs(back[offset + 100] - params[offset + 100]) > 1e-4);
  }
  // a parameter buffer too small for the group at this offset is refused, the step not taken
  Buffer small = createBuffer(ctx, (offset + rows * width - 1) * 4);
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdAdamStep(cb, pipes, group, small, gb, offset); }), Error);
  CHECK(group.step == 6);
}

GPU_TEST_CASE("remapping Adam rows carries moments along, zeroes new rows, refuses bad rows") {
  AdamPipelines pipes = createAdamPipelines(ctx);
  const uint32_t rows = 300, width = 4;
  std::normal_distribution<float> N(0.0f, 1.0f);
  AdamGroup group = createAdamGroup(ctx, "rotation", {1e-3, 1e-3, 1}, width, rows);
  std::vector<float> m(rows * width), v(rows * width);
  for (auto& x : m) x = N(rng);
  for (auto& x : v) x = std::abs(N(rng));
  upload(ctx, group.m, m.data(), m.size() * 4);
  upload(ctx, group.v, v.data(), v.size() * 4);
  group.step = 7;
  // prune every third row, clone some, split one into two new rows
  std::vector<uint32_t> source;
  for (uint32_t r = 0; r < rows; r++)
    if (r % 3) source.push_back(r);
  source.push_back(5);
  source.push_back(kNewRow);
  source.push_back(kNewRow);
  std::shuffle(source.begin(), source.end(), rng);
  remapAdamRows(ctx, pipes, group, source);
  CHECK(group.rows == source.size());
  CHECK(group.step == 7);  // torch keeps a tensor's step count across 3DGS's replacements
  auto mBack = downloadVector<float>(ctx, group.m, source.size() * width);
  auto vBack = downloadVector<float>(ctx, group.v, source.size() * width);
  size_t bad = 0;
  for (size_t i = 0; i < source.size(); i++)
    for (uint32_t k = 0; k < width; k++) {
      float em = source[i] == kNewRow ? 0.0f : m[source[i] * width + k];
      float ev = source[i] == kNewRow ? 0.0f : v[source[i] * width + k];
      if (mBack[i * width + k] != em || vBack[i * width + k] != ev) bad++;
    }
  CHECK(bad == 0);
  // the gather itself, into a NaN-poisoned table (a skipped row would stay NaN)
  Buffer src = createBufferFrom(ctx, m), dst = createBuffer(ctx, source.size() * width * 4), rowsBuf = createBufferFrom(ctx, source);
  fillBuffer(ctx, dst, 0x7FC00000u);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdGatherRows(cb, pipes, src, dst, rowsBuf, uint32_t(source.size()), width); });
  auto gathered = downloadVector<float>(ctx, dst, source.size() * width);
  size_t badGather = 0;
  for (size_t i = 0; i < source.size(); i++)
    for (uint32_t k = 0; k < width; k++)
      if (!(gathered[i * width + k] == (source[i] == kNewRow ? 0.0f : m[source[i] * width + k]))) badGather++;
  CHECK(badGather == 0);
  CHECK_THROWS_AS(remapAdamRows(ctx, pipes, group, {0, uint32_t(source.size())}), Error);
  CHECK(group.rows == source.size());  // unchanged after the refusal
  remapAdamRows(ctx, pipes, group, {});
  CHECK(group.rows == 0);
}
