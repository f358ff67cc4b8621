#include "viewer/benchmark.h"

#include <cstdio>

#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_context.h"

namespace refrax {

void addStages(Benchmark& b, const std::vector<std::pair<std::string, double>>& stages) {
  for (const auto& [name, ms] : stages) {
    if (!b.stageMs.count(name)) b.order.push_back(name);
    b.stageMs[name] += ms;
  }
}

namespace {

const char* waterShown(ViewScene* scene, const ViewerState& state) {
  if (!scene || state.show != ShowMode::Gaussians) return "-";
  WaterMode w = effectiveWater(*scene, state.render);
  return w == WaterMode::Kept ? "kept" : w == WaterMode::Removed ? "removed" : "swapped";
}

// What the trace cost depends on: hits and k-buffer rounds per ray, and the tiles' lists.
void printTraceCost(Context& ctx, ViewScene& scene, const RenderSettings& rs, const FrameStats& stats, const FrameRenderer& renderer) {
  auto results = downloadVector<GpuTraceResult>(ctx, renderer.results, size_t(stats.width) * stats.height);
  double hits = 0, rounds = 0;
  for (const auto& r : results) {
    hits += r.hits;
    rounds += r.rounds;
  }
  std::printf("benchmark trace: %s, K %u, min transmittance %g, %.1f hits and %.2f k-buffer rounds per ray\n",
              rs.tiledTrace ? "tiles" : "bvh", scene.tracer.K, rs.minTransmittance, hits / double(results.size()),
              rounds / double(results.size()));
  if (rs.tiledTrace && renderer.tiles) {
    TileStats t = readTileStats(ctx, *renderer.tiles);
    std::printf("benchmark tiles: %u tiles of %ux%u rays, %.1f Gaussians listed per tile (max %u), %u over the list's %u; "
                "%u blocks of %ux%u, %.1f listed per block, %u over %u\n",
                t.tiles, kTileSide, kTileSide, t.meanListed, t.maxListed, t.overflowed, renderer.tiles->capacity, t.blocks, kBlockSide,
                kBlockSide, t.meanBlockListed, t.blocksOverflowed, renderer.tiles->blockCapacity);
  }
}

}  // namespace

void printBenchmark(Context& ctx, const Benchmark& b, ViewScene* scene, const ViewerState& state, const FrameStats& stats,
                    const FrameRenderer& renderer) {
  std::printf("benchmark: %s | %s | %ux%u | %u Gaussians | water %s | %ld frames: %.2f FPS (%.1f ms/frame)\n", ctx.caps.name.c_str(),
              scene ? scene->source.c_str() : "surface", stats.width, stats.height, scene ? sceneGaussianCount(*scene) : 0,
              waterShown(scene, state), b.frames, 1e3 * b.frames / b.wallMs, b.wallMs / b.frames);
  std::printf("benchmark GPU ms per frame:");
  for (const auto& name : b.order) std::printf(" %s %.2f", name.c_str(), b.stageMs.at(name) / b.frames);
  std::printf("\n");
  if (scene && state.show == ShowMode::Gaussians) printTraceCost(ctx, *scene, state.render, stats, renderer);
}

}  // namespace refrax
