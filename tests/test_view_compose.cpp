// The viewer's compose stage (traced colour or hit heat map to RGBA8) against its double
// reference on random trace results.
#include <doctest/doctest.h>

#include <random>

#include "engine/vk/vk_commands.h"
#include "engine/view/view_compose.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {
int channel(uint32_t p, int c) { return int((p >> (8 * c)) & 0xFFu); }
}  // namespace

GPU_TEST_CASE("view compose matches its double reference for colour and hit heat map") {
  const uint32_t n = 1000;
  std::uniform_real_distribution<float> colour(-0.3f, 1.3f);
  std::uniform_int_distribution<uint32_t> hits(0, 120);
  std::vector<GpuTraceResult> results(n);
  for (auto& r : results) {
    for (float& c : r.rgb) c = colour(rng);
    r.opacity = 0.5f;
    r.depth = 1.0f;
    r.transmittance = 0.5f;
    r.hits = hits(rng);
    r.rounds = 1;
  }
  results[0].hits = 0;  // the heat map's ends: black, and the top colour from the full scale on
  results[1].hits = 1000;
  Buffer rb = createBufferFrom(ctx, results);
  Buffer pixels = createBuffer(ctx, (n + 1) * 4);
  ComputePipeline pipeline = createViewComposePipeline(ctx);
  for (ComposeMode mode : {ComposeMode::Colour, ComposeMode::HitHeatMap}) {
    ComposeOptions o;
    o.mode = mode;
    o.heatFullScale = std::uniform_real_distribution<float>(5.0f, 80.0f)(rng);
    fillBuffer(ctx, pixels, 0x7FC00000u);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdComposeView(cb, pipeline, rb, pixels, n, o); });
    auto got = downloadVector<uint32_t>(ctx, pixels, n + 1);
    int worst = 0, exact = 0;
    for (uint32_t i = 0; i < n; i++) {
      uint32_t want = composePixelReference(results[i], o);
      bool same = true;
      for (int c = 0; c < 4; c++) {
        worst = std::max(worst, std::abs(channel(got[i], c) - channel(want, c)));
        same = same && channel(got[i], c) == channel(want, c);
      }
      exact += same;
    }
    INFO("mode " << uint32_t(mode) << " full scale " << o.heatFullScale);
    CHECK(worst <= 1);          // float32 against double can round a channel the other way at .5
    CHECK(exact >= int(n) - 5);  // which is rare
    CHECK(got[n] == 0x7FC00000u);  // nothing written past count
    if (mode == ComposeMode::HitHeatMap) {
      CHECK(got[0] == 0xFF000000u);
      CHECK(got[1] == (255u | (255u << 8) | (153u << 16) | (255u << 24)));
    } else {
      // colour: clamped to [0, 1], rounded half up like the PNG writer
      for (uint32_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
          float v = std::clamp(results[i].rgb[c], 0.0f, 1.0f) * 255.0f;
          CHECK(std::abs(channel(got[i], c) - int(std::lround(v))) <= 1);
        }
    }
  }
}

GPU_TEST_CASE("view compose rejects a non-positive heat map scale") {
  ComposeOptions o;
  o.heatFullScale = 0;
  GpuTraceResult r{};
  CHECK_THROWS_WITH_AS(composePixelReference(r, o), doctest::Contains("full scale"), refrax::Error);
}
