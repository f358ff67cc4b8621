// The Gaussians' optimiser step on the device (engine/gaussian/gaussian_device_step.h) against
// the host's (table_adam.h tableAdamStep, densify.h densityDecay / densityReset and
// resetAdamColumns, the statistic's sums), which test_table_adam.cpp checks against the
// double reference: every group's update, non-finite gradients as zero, the decay and the
// reset at their steps, the group steps, and the statistic scaled by the batch.
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/gaussian/densify.h"
#include "engine/gaussian/gaussian_adam.h"
#include "engine/gaussian/gaussian_device_step.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussians.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

GPU_TEST_CASE("Gaussian device step: Adam, the density schedule and the statistic's sums match the host's step by step") {
  std::mt19937 rng(11);
  std::normal_distribution<float> N(0.0f, 1.0f);
  std::uniform_real_distribution<float> U(0.0f, 1.0f);
  const uint32_t count = 37;  // not a whole workgroup
  GaussianSet host;
  host.params.resize(size_t(count) * kGaussianFloats);
  for (float& p : host.params) p = N(rng);
  for (uint32_t i = 0; i < count; i++) host.at(i)[f32::kGaussLogitDensity] = 12 * (U(rng) - 0.5f);  // densities 0.0025 to 0.9975
  TableAdam hostAdam = createGaussianAdam(2.0, 5, count), deviceAdam = hostAdam;
  std::vector<float> hostSums(count * 2, 0.0f), deviceSums;
  DensifyConfig densify;
  densify.decayFloor = 1e-6f;

  GaussianDeviceOptimiser o = createGaussianDeviceOptimiser(ctx, count, kGaussianFloats);
  uploadGaussianOptimiser(ctx, o, deviceAdam, hostSums);
  Buffer params = createBufferFrom(ctx, host.params), grads = createBuffer(ctx, host.params.size() * 4), stats = createBuffer(ctx, count * 2 * 4);

  // Six steps: a decay at step 2, a reset at step 4, a non-finite gradient now and then.
  for (int step = 1; step <= 6; step++) {
    CAPTURE(step);
    std::vector<float> g(host.params.size()), st(count * 2);
    for (float& x : g) x = 0.1f * N(rng);
    g[size_t(step) * 13] = step % 2 ? NAN : INFINITY;
    for (float& x : st) x = U(rng);
    upload(ctx, grads, g.data(), g.size() * 4);
    upload(ctx, stats, st.data(), st.size() * 4);
    GaussianStepEvents events;
    events.decay = step == 2;
    events.reset = step == 4;
    events.statScale = 4.0f;
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdGaussianStep(cb, o, deviceAdam, params, grads, stats, events, densify); });

    for (size_t i = 0; i < hostSums.size(); i += 2) {
      hostSums[i] += st[i] * events.statScale;
      hostSums[i + 1] += st[i + 1];
    }
    tableAdamStep(hostAdam, host.params, g);
    if (events.decay) densityDecay(host, densify);
    if (events.reset) {
      densityReset(host, densify);
      resetAdamColumns(hostAdam, "density");
    }

    const std::vector<float> device = downloadVector<float>(ctx, params, host.params.size());
    TableAdam moments = deviceAdam;
    downloadGaussianOptimiser(ctx, o, moments, deviceSums);
    double worstParam = 0, worstMoment = 0;
    for (size_t k = 0; k < device.size(); k++) {
      worstParam = std::max(worstParam, double(std::abs(device[k] - host.params[k])) / (1.0 + std::abs(host.params[k])));
      worstMoment = std::max(worstMoment, double(std::abs(moments.m[k] - hostAdam.m[k]) + std::abs(moments.v[k] - hostAdam.v[k])));
    }
    INFO("worst parameter difference " << worstParam << ", moments " << worstMoment);
    CHECK(worstParam < 2e-6);  // the decay's float logarithms against the host's double
    CHECK(worstMoment < 1e-6);
    for (size_t g2 = 0; g2 < hostAdam.groups.size(); g2++) CHECK(deviceAdam.groups[g2].step == hostAdam.groups[g2].step);
    for (size_t i = 0; i < hostSums.size(); i++) CHECK(deviceSums[i] == doctest::Approx(hostSums[i]).epsilon(1e-6));
  }
  // the reset zeroed the density's moments and started its group afresh
  CHECK(deviceAdam.groups[3].name == "density");
  CHECK(deviceAdam.groups[3].step == 2);
}
