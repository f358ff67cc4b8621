// The device's orders (engine/trace/device_order.h) against the host's: the exclusive scan
// against std::exclusive_scan, the radix sort against std::stable_sort, the median split
// against presort.h medianSplitOrder over boxes of no size at the same points.
#include <algorithm>
#include <numeric>

#include "engine/trace/device_order.h"
#include "engine/trace/presort.h"
#include "engine/vk/vk_commands.h"
#include "tests/gpu_test.h"

using namespace refrax;

namespace {

std::vector<uint32_t> scanOnDevice(Context& ctx, const DeviceOrderPipelines& p, const std::vector<uint32_t>& values) {
  Buffer b = createBufferFrom(ctx, values);
  Buffer sums = createScanBlockSums(ctx, uint32_t(values.size()));
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdExclusiveScan(cb, p, b, uint32_t(values.size()), sums); });
  return downloadVector<uint32_t>(ctx, b, values.size());
}

// Points on a coarse lattice (many equal coordinates, -0 among them) or spread.
std::vector<float> randomPoints(std::mt19937& rng, size_t n, bool lattice) {
  std::uniform_real_distribution<float> U(-2.0f, 2.0f);
  std::uniform_int_distribution<int> cell(-3, 3);
  std::vector<float> xyz(3 * n);
  for (size_t i = 0; i < xyz.size(); i++) {
    xyz[i] = lattice ? float(cell(rng)) * 0.25f : U(rng);
    if (xyz[i] == 0 && (i / 3) % 2 == 1) xyz[i] = -0.0f;  // -0 and +0 alike: equal to the host's comparison
  }
  return xyz;
}

std::vector<uint32_t> hostOrder(const std::vector<float>& xyz) {
  std::vector<Box> boxes(xyz.size() / 3);
  for (size_t i = 0; i < boxes.size(); i++)
    boxes[i] = Box{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  return medianSplitOrder(boxes);
}

}  // namespace

GPU_TEST_CASE("device order: the exclusive scan matches the host's across block edges") {
  DeviceOrderPipelines p = createDeviceOrderPipelines(ctx);
  std::uniform_int_distribution<uint32_t> U(0, 1000);
  for (size_t n : {size_t(1), size_t(511), size_t(512), size_t(513), size_t(3 * 70001)}) {
    std::vector<uint32_t> values(n);
    for (uint32_t& v : values) v = U(rng);
    std::vector<uint32_t> want(n);
    std::exclusive_scan(values.begin(), values.end(), want.begin(), 0u);
    INFO(n << " values");
    CHECK(scanOnDevice(ctx, p, values) == want);
  }
}

GPU_TEST_CASE("device order: the radix sort is std::stable_sort by key, within its range only") {
  DeviceOrderPipelines p = createDeviceOrderPipelines(ctx);
  for (size_t n : {size_t(2), size_t(255), size_t(256), size_t(257), size_t(5000), size_t(200000)})
    for (bool fewKeys : {true, false}) {
      // A segment [base, base + n) of a longer buffer, as the median split sorts one axis's list.
      const size_t base = 37, total = base + n + 11;
      std::uniform_int_distribution<uint32_t> key(0, fewKeys ? 20u : 0xFFFFFFFFu);
      std::vector<uint32_t> keys(total), values(total);
      for (size_t i = 0; i < total; i++) keys[i] = key(rng), values[i] = uint32_t(i);
      std::vector<std::pair<uint32_t, uint32_t>> want;
      for (size_t i = base; i < base + n; i++) want.push_back({keys[i], values[i]});
      std::stable_sort(want.begin(), want.end(), [](auto& a, auto& b) { return a.first < b.first; });
      Buffer k = createBufferFrom(ctx, keys), v = createBufferFrom(ctx, values);
      Buffer tk = createBuffer(ctx, total * 4), tv = createBuffer(ctx, total * 4);
      RadixSortScratch scratch = createRadixSortScratch(ctx, uint32_t(n));
      submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdRadixSort(cb, p, k, v, tk, tv, uint32_t(base), uint32_t(n), scratch); });
      std::vector<uint32_t> gotKeys = downloadVector<uint32_t>(ctx, k, total), gotValues = downloadVector<uint32_t>(ctx, v, total);
      size_t wrong = 0, touched = 0;
      for (size_t i = 0; i < n; i++) wrong += gotKeys[base + i] != want[i].first || gotValues[base + i] != want[i].second;
      for (size_t i = 0; i < total; i++)
        if (i < base || i >= base + n) touched += gotKeys[i] != keys[i] || gotValues[i] != values[i];
      INFO(n << " keys, " << (fewKeys ? "21 distinct" : "spread"));
      CHECK(wrong == 0);
      CHECK(touched == 0);
    }
}

GPU_TEST_CASE("device order: the median split is the host's medianSplitOrder, ties by index") {
  DeviceOrderPipelines p = createDeviceOrderPipelines(ctx);
  CHECK(medianSplitLevels(1) == 0);
  CHECK(medianSplitLevels(2) == 1);
  CHECK(medianSplitLevels(5) == 3);
  CHECK(medianSplitLevels(1024) == 10);
  CHECK(medianSplitLevels(1025) == 11);
  for (size_t n : {size_t(1), size_t(2), size_t(3), size_t(5), size_t(17), size_t(1000), size_t(65537)})
    for (bool lattice : {true, false}) {
      std::vector<float> xyz = randomPoints(rng, n, lattice);
      // Points inside a longer record, as the Gaussians' means lie in their parameters.
      const PointLayout layout{5, 1};
      std::vector<float> records(5 * n, 7.0f);
      for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) records[5 * i + 1 + a] = xyz[3 * i + a];
      Buffer points = createBufferFrom(ctx, records), order = createBuffer(ctx, n * 4);
      MedianSplitScratch scratch = createMedianSplitScratch(ctx, uint32_t(n));
      submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdMedianSplitOrder(cb, p, scratch, points, layout, uint32_t(n), order); });
      std::vector<uint32_t> got = downloadVector<uint32_t>(ctx, order, n), want = hostOrder(xyz);
      size_t differ = 0;
      for (size_t k = 0; k < n; k++) differ += got[k] != want[k];
      INFO(n << " points, " << (lattice ? "on a lattice (ties)" : "spread") << ": " << differ << " slots differ");
      CHECK(differ == 0);
      if (n >= 17) {  // not a trivial order
        std::vector<uint32_t> identity(n);
        std::iota(identity.begin(), identity.end(), 0u);
        CHECK(want != identity);
      }
    }
}

GPU_TEST_CASE("device order: bad sizes are refused with a message") {
  DeviceOrderPipelines p = createDeviceOrderPipelines(ctx);
  MedianSplitScratch scratch = createMedianSplitScratch(ctx, 4);
  Buffer points = createBuffer(ctx, 64 * 4), order = createBuffer(ctx, 64 * 4);
  CHECK_THROWS_WITH(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdMedianSplitOrder(cb, p, scratch, points, {3, 0}, 5, order); }),
                    doctest::Contains("fewer points"));
  CHECK_THROWS_WITH(submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdMedianSplitOrder(cb, p, scratch, points, {3, 1}, 4, order); }),
                    doctest::Contains("outside its stride"));
}
