// Buffers and plain compute dispatch against CPU results, with outputs poisoned first.
#include <cmath>
#include <cstring>
#include <vector>

#include "engine/vk_buffer.h"
#include "engine/vk_commands.h"
#include "engine/shader_table.h"
#include "engine/vk_pipeline.h"
#include "tests/gpu_test.h"

using namespace refrax;

GPU_TEST_CASE("buffer upload and download round-trip bytes exactly") {
  std::uniform_int_distribution<uint32_t> U;
  for (size_t words : {1u, 7u, 1000u, 1u << 18}) {
    std::vector<uint32_t> data(words);
    for (auto& w : data) w = U(rng);
    Buffer b = createBuffer(ctx, words * 4);
    fillBuffer(ctx, b, 0xDEADBEEF);
    upload(ctx, b, data.data(), words * 4);
    std::vector<uint32_t> back(words, 0);
    download(ctx, b, back.data(), words * 4);
    CHECK(back == data);
    // partial ranges land at their offsets
    if (words > 4) {
      uint32_t two[2] = {1, 2};
      upload(ctx, b, two, 8, 8);
      auto all = downloadVector<uint32_t>(ctx, b, words);
      CHECK(all[2] == 1);
      CHECK(all[3] == 2);
      CHECK(all[1] == data[1]);
      CHECK(all[4] == data[4]);
    }
  }
}

GPU_TEST_CASE("out-of-range uploads are refused") {
  Buffer b = createBuffer(ctx, 16);
  uint32_t x[8] = {};
  CHECK_THROWS_AS(upload(ctx, b, x, 32), Error);
  CHECK_THROWS_AS(download(ctx, b, x, 8, 12), Error);
}

GPU_TEST_CASE("compute dispatch matches the CPU (y = a x + b)") {
  std::uniform_real_distribution<float> U(-10.0f, 10.0f);
  const uint32_t n = 10007;  // not a multiple of the group size
  std::vector<float> x(n);
  for (auto& v : x) v = U(rng);
  struct {
    float a, b;
    uint32_t count;
  } push{U(rng), U(rng), n};
  Buffer xb = createBufferFrom(ctx, x);
  Buffer yb = createBuffer(ctx, (n + 64) * 4);
  fillBuffer(ctx, yb, 0x7FC00000u);  // NaN: any element the shader skips stays NaN
  ComputePipeline p = createComputePipeline(ctx, "scale_add", {kStorageBuffer, kStorageBuffer}, sizeof(push));
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdDispatch(cb, p, {bind(xb), bind(yb)}, &push, groupsFor(n, 64)); });
  auto y = downloadVector<float>(ctx, yb, n + 64);
  size_t bad = 0;
  for (uint32_t i = 0; i < n; i++) {
    double ref = double(push.a) * x[i] + push.b;
    if (!(std::fabs(y[i] - ref) <= 1e-5 * std::max(1.0, std::fabs(ref)))) bad++;
  }
  CHECK(bad == 0);
  // elements past `count` must be untouched
  for (uint32_t i = n; i < n + 64; i++) CHECK(std::isnan(y[i]));
}

GPU_TEST_CASE("dispatch with mismatched bindings is refused") {
  Buffer a = createBuffer(ctx, 64);
  ComputePipeline p = createComputePipeline(ctx, "scale_add", {kStorageBuffer, kStorageBuffer}, 12);
  uint32_t push[3] = {};
  CHECK_THROWS_AS(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdDispatch(cb, p, {bind(a)}, push, 1); }), Error);
}

TEST_CASE("an unknown shader name is a clear error") { CHECK_THROWS_AS(findShader("no_such_shader"), Error); }
