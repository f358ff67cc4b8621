// refrax bench meshswap: the surface swap (cmdRefractThroughMesh on a baked triangle mesh)
// against the learned-surface stage (traceSurface: global trace, K subdivision levels,
// refraction) on the same camera rays and the same closed-form surface, in one run. The mesh
// is the surface baked with bakeHeightMesh at the coarse grid and at the subdivided
// lattice's finest spacing; wall times (submit and wait included) are medians.
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "engine/height/analytic_height.h"
#include "engine/base/error.h"
#include "engine/surface/mesh_surface.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/surface/water_surface.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

// A pinhole camera 2.5 above the centre of [-1, 1]^2 looking straight down, covering the domain.
std::vector<GpuRay> downwardCameraRays(uint32_t size) {
  std::vector<GpuRay> rays(size_t(size) * size);
  const float h = 2.5f, tanHalf = 1.02f / h;
  for (uint32_t y = 0; y < size; y++)
    for (uint32_t x = 0; x < size; x++) {
      float u = ((x + 0.5f) / size * 2 - 1) * tanHalf, v = ((y + 0.5f) / size * 2 - 1) * tanHalf;
      float len = std::sqrt(u * u + v * v + 1);
      rays[size_t(y) * size + x] = {{0, 0, h}, 0, {u / len, v / len, -1 / len}, 100};
    }
  return rays;
}

int runBenchMeshSwap(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  const uint32_t size = uint32_t(args.getInt("rays", 392));
  const uint32_t cells = uint32_t(args.getInt("grid", 200));
  const uint32_t levels = uint32_t(args.getInt("levels", 2));
  const int runs = int(args.getInt("runs", 5));
  if (size == 0 || cells == 0 || runs <= 0 || levels > 6) fail("bench meshswap: --rays, --grid and --runs must be positive, --levels at most 6");
  const uint32_t n = size * size;
  std::mt19937 rng(7);
  AnalyticHeightField field = createAnalyticHeightField(*ctx, randomWaves(rng, 0.05f, 6.0f));
  HeightSource source = heightSource(field);
  std::vector<GpuRay> rays = downwardCameraRays(size);
  Buffer rayBuf = createBufferFrom(*ctx, rays);
  Buffer refracted = createBuffer(*ctx, VkDeviceSize(n) * sizeof(GpuRay));
  Buffer records = createBuffer(*ctx, VkDeviceSize(n) * sizeof(SurfaceRecord));
  std::printf("device: %s; %u x %u camera rays looking down on a closed-form surface\n", ctx->caps.name.c_str(), size, size);

  WaterSurfaceConfig config;
  config.gridCells = cells;
  config.subdivisionLevels = levels;
  config.maxRays = n;
  WaterSurface surface = createWaterSurface(*ctx, config);
  submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdUpdateSurface(cb, surface, source); });
  double traceMs = bench::medianMs(1, runs, [&] { traceSurface(*ctx, surface, source, rayBuf, n, refracted, records); });
  std::printf("traceSurface (grid %u, K %u): %.2f ms\n", cells, levels, traceMs);

  for (uint32_t meshCells : {cells, cells << levels}) {
    SurfaceMesh mesh = bakeHeightMesh(*ctx, source, config.domain, meshCells, meshCells);
    MeshSurface m = createMeshSurface(*ctx, mesh);
    double meshMs = bench::medianMs(1, runs, [&] {
      submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdRefractThroughMesh(cb, m, rayBuf, n, config.ior, refracted, records); });
    });
    std::printf("cmdRefractThroughMesh (baked %u x %u cells, %u triangles): %.2f ms = %.3f x traceSurface\n", meshCells, meshCells,
                m.triangleCount, meshMs, meshMs / traceMs);
  }
  return 0;
}

REFRAX_BENCH_SUITE({"meshswap",
                    "surface swap (ray query on a baked mesh) against the learned-surface stage, same rays",
                    {{"rays", "N", "camera image side (N x N rays)", "392"},
                     {"grid", "N", "coarse grid cells per side of the learned-surface stage", "200"},
                     {"levels", "K", "its subdivision levels (the fine mesh is baked at grid << K cells)", "2"},
                     {"runs", "N", "timed runs after one warm-up (median)", "5"}},
                    runBenchMeshSwap});

}  // namespace
}  // namespace refrax
