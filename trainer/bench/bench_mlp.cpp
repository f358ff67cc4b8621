// refrax bench mlp: height-field MLP throughput (forward and backward GFLOP/s, 2 flops per
// multiply-add) per width, the chosen (generated) forward kernel side by side with the
// loop-based one, and pipeline creation time reported apart from the runs.
#include <chrono>
#include <cstdio>
#include <functional>
#include <random>
#include <sstream>

#include "engine/base/error.h"
#include "engine/height/height_field.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

std::vector<uint32_t> parseList(const std::string& s) {
  std::vector<uint32_t> v;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    try {
      v.push_back(uint32_t(std::stoul(item)));
    } catch (...) {
      fail("bench mlp: bad width list '" + s + "'");
    }
  return v;
}

struct Run {
  double ms = 0;       // median
  double firstMs = 0;  // the first submit: lavapipe JIT-compiles each pipeline at its first dispatch
};

Run timeSubmits(Context& ctx, int runs, const std::function<void(VkCommandBuffer)>& record) {
  Run r;
  auto t0 = std::chrono::steady_clock::now();
  submitAndWait(ctx, record);
  r.firstMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  r.ms = bench::medianMs(1, runs, [&] { submitAndWait(ctx, record); });
  return r;
}

int runMlpBench(const cli::Args& args) {
  auto ctx = openContext(args);
  const uint32_t points = uint32_t(args.getInt("points", 80000));
  const uint32_t backwardPoints = uint32_t(args.getInt("backward-points", 16384));
  const uint32_t genericPoints = uint32_t(args.getInt("generic-points", 8192));
  const int runs = int(args.getInt("runs", 5));
  HeightFieldConfig base;
  base.hiddenLayers = uint32_t(args.getInt("depth", 6));
  base.octaves = uint32_t(args.getInt("octaves", 6));
  std::vector<uint32_t> widths = parseList(args.get("widths", "32,64,128,256"));
  if (points == 0 || backwardPoints == 0 || genericPoints == 0 || runs < 1) fail("bench mlp: point counts and runs must be positive");

  std::printf("device: %s (%s)\n", ctx->caps.name.c_str(), ctx->caps.driver.c_str());
  std::printf("MLP: %u inputs (%u octaves), %u hidden layers, Leaky ReLU, no biases; median of %d runs after 1 warm-up;\n"
              "times are submit-to-completion wall times; \"1st\" is the first submit, which includes lavapipe's JIT\n"
              "compilation of the pipelines (unless Mesa's disk cache has them: MESA_SHADER_CACHE_DISABLE=true measures it cold).\n"
              "backward flops: recomputed forward + deltas + weight gradient = 2 * (3 P - width * inputs) per point\n",
              2 + 4 * base.octaves, base.octaves, base.hiddenLayers, runs);
  std::printf("%6s %9s  %-26s %9s %10s %9s | %-22s %9s %10s | %9s %9s %10s\n", "width", "params", "forward kernel", "1st ms",
              "fwd ms", "GFLOP/s", "generic (points)", "GFLOP/s", "speedup", "bwd 1st", "bwd ms", "GFLOP/s");

  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> U(-1.0f, 1.0f);
  uint32_t maxPoints = std::max({points, backwardPoints, genericPoints});
  std::vector<float> xy(2 * size_t(maxPoints)), g(maxPoints);
  for (auto& v : xy) v = U(rng);
  for (auto& v : g) v = U(rng);
  Buffer pb = createBufferFrom(*ctx, xy), gb = createBufferFrom(*ctx, g);
  Buffer hb = createBuffer(*ctx, size_t(maxPoints) * 4);

  for (uint32_t width : widths) {
    HeightFieldConfig c = base;
    c.width = width;
    HeightField hf = createHeightField(*ctx, c, 7);
    const double P = double(hf.parameterCount);
    const double fwdFlops = 2.0 * P, bwdFlops = 2.0 * (3.0 * P - double(width) * hf.inputCount);

    auto forward = [&](uint32_t n) { return [&, n](VkCommandBuffer cb) { cmdEvaluateHeights(cb, hf, pb, n, hb); }; };
    Run fast = timeSubmits(*ctx, runs, forward(points));
    std::string kernel = hf.forwardKernelName();
    hf.forceGenericForward = true;
    Run generic = timeSubmits(*ctx, runs, forward(genericPoints));
    hf.forceGenericForward = false;
    Buffer grad = createBuffer(*ctx, hf.parameterCount * 4);
    fillBuffer(*ctx, grad, 0);
    hf.forceGenericBackward = args.has("loop-backward");
    Run bwd = timeSubmits(*ctx, runs, [&](VkCommandBuffer cb) { cmdAccumulateHeightGradients(cb, hf, pb, gb, backwardPoints, grad); });
    double fastG = fwdFlops * points / (fast.ms * 1e6), genericG = fwdFlops * genericPoints / (generic.ms * 1e6);
    std::printf("%6u %9.0f  %-26s %9.0f %10.2f %9.2f | %-13s(%6u) %9.2f %9.1fx | %9.0f %9.2f %10.2f\n", width, P, kernel.c_str(),
                fast.firstMs, fast.ms, fastG, "generic", genericPoints, genericG, fastG / genericG, bwd.firstMs, bwd.ms,
                bwdFlops * backwardPoints / (bwd.ms * 1e6));
    std::fflush(stdout);
  }
  std::printf("forward: %u points; backward: %u points\n", points, backwardPoints);
  return 0;
}

REFRAX_BENCH_SUITE({"mlp",
                    "height-field MLP forward/backward GFLOP/s per width (generated vs loop-based kernels)",
                    {{"points", "N", "points per forward evaluation", "80000"},
                     {"backward-points", "N", "points per backward pass", "16384"},
                     {"generic-points", "N", "points per loop-based forward (it is slow on lavapipe)", "8192"},
                     {"widths", "LIST", "comma-separated widths", "32,64,128,256"},
                     {"depth", "N", "hidden layers", "6"},
                     {"octaves", "N", "encoding octaves", "6"},
                     {"runs", "N", "timed runs per figure (median)", "5"},
                     {"loop-backward", "", "backward with the loop-based kernels instead of the generated ones", ""}},
                    runMlpBench});

}  // namespace
}  // namespace refrax
