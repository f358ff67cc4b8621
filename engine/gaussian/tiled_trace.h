#pragma once
// The Gaussian forward over an image's rays in tiles: the viewer's fast path on devices where
// BVH traversal is slow (lavapipe). Two passes:
//   1. tile_cull.comp: per 8x8 tile of rays, the cone holding all its rays
//      (shaders/include/ray_bundle.glsl) and the list of Gaussians whose bounding sphere the
//      cone may reach, sorted by depth; in two levels, so that a tile tests only the list of
//      its 32x32 block (the blocks test every Gaussian);
//   2. gaussian_forward_tiled.comp: each ray tests its tile's list instead of traversing the
//      BVH, with the forward's k-buffer blend (include/gaussian_forward_body.glsl).
// The result equals cmdTraceForward's on the same rays: the same hits, tested the same way,
// blended in the same order (tests/test_tiled_trace.cpp). A tile whose list overflows its
// capacity traverses the BVH. The rays must be an image, row by row (camera rays, or those
// rays refracted at the water in the same order); neighbouring pixels' rays make thin cones.
#include <cstdint>
#include <vector>

#include "engine/gaussian/gaussian_trace.h"

namespace refrax {

constexpr uint32_t kTileSide = 8;    // the forward's workgroup is one 8x8 tile
constexpr uint32_t kBlockSide = 32;  // the first culling level's blocks: 4x4 tiles
// Candidates a tile's list holds (a block's: kBlockCapacityFactor times that). The tiny
// trained scene lists 83 per tile on average (at most 232) at 256^2; a tile with more than the
// capacity traverses the BVH (correct, slower), a block with more lets its tiles test every
// Gaussian.
constexpr uint32_t kDefaultTileCapacity = 4096;
constexpr uint32_t kBlockCapacityFactor = 4;

struct TileCandidates {
  uint32_t width = 0, height = 0, capacity = 0;
  uint32_t tilesX = 0, tilesY = 0;
  Buffer counts;      // per tile: Gaussians listed (may exceed capacity)
  Buffer candidates;  // capacity trace-record indices per tile
  uint32_t blocksX = 0, blocksY = 0, blockCapacity = 0;
  Buffer blockCounts, blockLists;  // the same per 32x32 block
};
TileCandidates createTileCandidates(Context& ctx, uint32_t width, uint32_t height, uint32_t capacity = kDefaultTileCapacity);
// Points `tiles` at a width x height image when its buffers hold that many tiles and blocks
// (a viewer whose resolution scale changes from frame to frame keeps its buffers); false,
// and nothing changed, when they are too small (create new ones).
bool reshapeTileCandidates(TileCandidates& tiles, uint32_t width, uint32_t height);

// Pass 1 over `rays` (width * height, row-major) and the proxies' bounding spheres.
void cmdCullTiles(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const Buffer& rays, TileCandidates& tiles);
// Pass 2 (after a barrier): writes results as cmdTraceForward does.
void cmdTraceForwardTiled(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const Buffer& rays,
                          const Buffer& results, const TileCandidates& tiles, const TraceOptions& options = {});

// What the lists held (downloads the counts).
struct TileStats {
  uint32_t tiles = 0, overflowed = 0, maxListed = 0;
  double meanListed = 0;
  uint32_t blocks = 0, blocksOverflowed = 0;  // first level: blocks whose tiles tested every Gaussian
  double meanBlockListed = 0;
};
TileStats readTileStats(Context& ctx, const TileCandidates& tiles);

// Both passes from host rays (width * height, row-major); stats, when given, filled.
std::vector<GpuTraceResult> traceGaussiansTiled(Context& ctx, GaussianTracer& tracer, const GaussianProxies& proxies,
                                                const std::vector<GpuRay>& rays, uint32_t width, uint32_t height,
                                                const TraceOptions& options = {}, uint32_t capacity = kDefaultTileCapacity,
                                                TileStats* stats = nullptr);

}  // namespace refrax
