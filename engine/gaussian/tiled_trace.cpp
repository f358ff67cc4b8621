#include "engine/gaussian/tiled_trace.h"

#include <algorithm>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_trace_internal.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

struct CullPush {
  uint32_t width, height, records, capacity;
  uint32_t side, level, parentCapacity, parentSide;
};

const ComputePipeline& cullPipeline(GaussianTracer& t) {
  if (!t.tileCull.pipeline)
    t.tileCull = createComputePipeline(*t.ctx, "tile_cull",
                                       {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                                       sizeof(CullPush));
  return t.tileCull;
}

const ComputePipeline& tiledPipeline(GaussianTracer& t, ProxyKind kind) {
  ComputePipeline& p = t.forwardTiled[uint32_t(kind)];
  if (!p.pipeline)
    p = createComputePipeline(*t.ctx, traceShaderName(*t.ctx, "gaussian_forward_tiled").c_str(),
                              {sceneBindingType(*t.ctx), kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer,
                               kStorageBuffer, kStorageBuffer},
                              sizeof(TracePush), traceSpec(t.K, kind));
  return p;
}

}  // namespace

namespace {

// Tiles and blocks of a width x height image.
struct TileGrid {
  uint32_t tilesX, tilesY, blocksX, blocksY;
  VkDeviceSize tiles() const { return VkDeviceSize(tilesX) * tilesY; }
  VkDeviceSize blocks() const { return VkDeviceSize(blocksX) * blocksY; }
};
TileGrid tileGridOf(uint32_t width, uint32_t height) {
  if (width == 0 || height == 0) fail("tiled trace: the image has no pixels");
  return {groupsFor(width, kTileSide), groupsFor(height, kTileSide), groupsFor(width, kBlockSide), groupsFor(height, kBlockSide)};
}

}  // namespace

TileCandidates createTileCandidates(Context& ctx, uint32_t width, uint32_t height, uint32_t capacity) {
  TileGrid g = tileGridOf(width, height);
  if (capacity == 0) fail("tiled trace: a tile's list needs room for at least one candidate");
  TileCandidates t;
  t.capacity = capacity;
  t.blockCapacity = capacity * kBlockCapacityFactor;
  if (g.tiles() * capacity > (VkDeviceSize(1) << 32) || g.blocks() * t.blockCapacity > (VkDeviceSize(1) << 32))
    fail("tiled trace: the candidate lists would exceed 2^32 entries (lower the capacity)");
  t.counts = createBuffer(ctx, g.tiles() * 4);
  t.candidates = createBuffer(ctx, g.tiles() * capacity * 4);
  t.blockCounts = createBuffer(ctx, g.blocks() * 4);
  t.blockLists = createBuffer(ctx, g.blocks() * t.blockCapacity * 4);
  reshapeTileCandidates(t, width, height);  // the buffers fit: sets the shape
  return t;
}

bool reshapeTileCandidates(TileCandidates& t, uint32_t width, uint32_t height) {
  TileGrid g = tileGridOf(width, height);
  if (t.counts.size < g.tiles() * 4 || t.candidates.size < g.tiles() * t.capacity * 4 || t.blockCounts.size < g.blocks() * 4 ||
      t.blockLists.size < g.blocks() * t.blockCapacity * 4)
    return false;
  t.width = width;
  t.height = height;
  t.tilesX = g.tilesX;
  t.tilesY = g.tilesY;
  t.blocksX = g.blocksX;
  t.blocksY = g.blocksY;
  return true;
}

void cmdCullTiles(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const Buffer& rays, TileCandidates& tiles) {
  CullPush blocks{tiles.width, tiles.height, proxies.count, tiles.blockCapacity, kBlockSide, 0, 0, 0};
  cmdDispatch(cb, cullPipeline(tracer),
              {bind(rays), bind(proxies.spheres), bind(tiles.counts), bind(tiles.candidates), bind(tiles.blockCounts), bind(tiles.blockLists)},
              &blocks, tiles.blocksX, tiles.blocksY);
  cmdBarrier(cb);
  CullPush push{tiles.width, tiles.height, proxies.count, tiles.capacity, kTileSide, 1, tiles.blockCapacity, kBlockSide};
  cmdDispatch(cb, cullPipeline(tracer),
              {bind(rays), bind(proxies.spheres), bind(tiles.blockCounts), bind(tiles.blockLists), bind(tiles.counts), bind(tiles.candidates)},
              &push, tiles.tilesX, tiles.tilesY);
}

void cmdTraceForwardTiled(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const Buffer& rays,
                          const Buffer& results, const TileCandidates& tiles, const TraceOptions& options) {
  TracePush push = tracePush(tiles.width * tiles.height, options);
  push.imageWidth = tiles.width;
  push.tileCapacity = tiles.capacity;
  const Buffer& records = options.hitRecords ? options.hitRecords->buffer : tracer.noHitRecords;
  cmdDispatch(cb, tiledPipeline(tracer, proxies.kind),
              {sceneBinding(proxies), bind(proxies.trace), bind(proxies.sh), bind(rays), bind(results), bind(records), bind(tiles.counts),
               bind(tiles.candidates), bind(proxies.spheres)},
              &push, tiles.tilesX, tiles.tilesY);
}

TileStats readTileStats(Context& ctx, const TileCandidates& tiles) {
  TileStats s;
  s.tiles = tiles.tilesX * tiles.tilesY;
  std::vector<uint32_t> counts = downloadVector<uint32_t>(ctx, tiles.counts, s.tiles);
  double sum = 0;
  for (uint32_t c : counts) {
    sum += c;
    s.maxListed = std::max(s.maxListed, c);
    s.overflowed += c > tiles.capacity;
  }
  s.meanListed = s.tiles ? sum / s.tiles : 0;
  s.blocks = tiles.blocksX * tiles.blocksY;
  std::vector<uint32_t> blockCounts = downloadVector<uint32_t>(ctx, tiles.blockCounts, s.blocks);
  double blockSum = 0;
  for (uint32_t c : blockCounts) {
    blockSum += c;
    s.blocksOverflowed += c > tiles.blockCapacity;
  }
  s.meanBlockListed = s.blocks ? blockSum / s.blocks : 0;
  return s;
}

std::vector<GpuTraceResult> traceGaussiansTiled(Context& ctx, GaussianTracer& tracer, const GaussianProxies& proxies,
                                                const std::vector<GpuRay>& rays, uint32_t width, uint32_t height,
                                                const TraceOptions& options, uint32_t capacity, TileStats* stats) {
  if (size_t(width) * height != rays.size()) fail("tiled trace: " + std::to_string(rays.size()) + " rays are not a " +
                                                  std::to_string(width) + "x" + std::to_string(height) + " image");
  validateRays(rays);
  TileCandidates tiles = createTileCandidates(ctx, width, height, capacity);
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer resultBuf = createBuffer(ctx, rays.size() * sizeof(GpuTraceResult));
  fillBuffer(ctx, resultBuf, 0x7FC00000u);  // NaN: a result the shader did not write shows
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdCullTiles(cb, tracer, proxies, rayBuf, tiles);
    cmdBarrier(cb);
    cmdTraceForwardTiled(cb, tracer, proxies, rayBuf, resultBuf, tiles, options);
  });
  if (stats) *stats = readTileStats(ctx, tiles);
  return downloadVector<GpuTraceResult>(ctx, resultBuf, rays.size());
}

}  // namespace refrax
