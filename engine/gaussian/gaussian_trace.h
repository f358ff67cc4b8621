#pragma once
// The refraction-aware Gaussian ray tracer (3DGRT k-buffer on ray queries, docs/method.md §1.4-1.5):
// proxies in an acceleration structure, a forward pass over any list of rays (camera rays
// or rays refracted at the water surface) and its backward to per-Gaussian gradients and
// per-ray dL/d(origin, direction).
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "engine/base/gpu_layout.h"
#include "engine/gaussian/gaussians.h"
#include "engine/trace/box_bvh.h"
#include "engine/trace/device_order.h"
#include "engine/trace/rays.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_pipeline.h"

namespace refrax {

// Which proxies stand for the Gaussians in the BVH.
enum class ProxyKind : uint32_t {
  AabbBlas = 0,          // one AABB per Gaussian in a single BLAS (presorted, median split)
  InstancedUnitBox = 1,  // a unit-box BLAS instanced per Gaussian (transform = scaled rotation)
};
const char* proxyKindName(ProxyKind kind);
struct DeviceCaps;
// "aabb", "instanced" or "auto". Auto picks the variant `refrax bench tracer` measured
// faster on this kind of device: the AABB BLAS on CPU devices (lavapipe); on GPUs, not
// measured here, the reference implementation's default, the instanced unit box.
ProxyKind proxyKindFor(const std::string& choice, const DeviceCaps& caps);

// GpuTraceResult {rgb[3], opacity, depth, transmittance, hits, rounds}, declared once in
// shaders/include/trace_result.glsl.
#include "trace_result.glsl"
constexpr uint32_t kTraceResultFloats = sizeof(GpuTraceResult) / 4;  // rgb first

// Hit records: a training forward writes, per ray, the hits it blended in order (Gaussian
// id and unclamped alpha, 8 bytes each; HitRecord in gaussian_trace_types.glsl), and the
// backward reads them instead of traversing the BVH a second time. Rays that blended more
// than `perRay` hits are re-traced by the backward. Valid until the Gaussians change.
struct HitRecords {
  Buffer buffer;  // perRay records for each of `rays` rays
  uint32_t rays = 0, perRay = 0;
};
HitRecords createHitRecords(Context& ctx, uint32_t rays, uint32_t perRay);
// Records per ray that training keeps by default (512 bytes per ray). A ray with more hits is
// re-traced, not wrong, but on a SIMD device its whole group waits for it: on the 100k probe
// scene (7.4 hits per ray on average) 32 records left 3.5% of rays over and the backward at
// 1.44-1.50x the forward; 64 cover every ray there and gave 1.23-1.31x (`refrax bench
// tracer --hit-records`, lavapipe). Trained scenes blend 10-26 hits per ray on average.
constexpr uint32_t kDefaultHitRecordsPerRay = 64;

struct TraceOptions {
  float background[3] = {0, 0, 0};
  uint32_t shDegree = 3;
  uint32_t maxRounds = 1u << 20;  // a safety net only: every round makes progress
  // The forward stops blending once the transmittance drops below this (kMinTransmittance
  // of gaussian_math.glsl by default; the viewer raises it to trade accuracy for speed).
  // The backward takes the default only (it must stop where training's forward stopped).
  float minTransmittance = 1e-3f;
  // Forward: what GpuTraceResult::depth holds. 0: the expected depth, sum of T alpha t (not
  // normalised). In (0, 1): the t of the blended hit at which the opacity 1 - T first reaches
  // this level, and 0 on a ray whose opacity never does (its opacity says so): a surface's
  // depth as a surveyor reads it (0.5 for the bed under the water, refrax export --bottom),
  // which no faint Gaussian in front of it or behind it moves. The backward ignores it.
  float depthAtOpacity = 0.0f;
  // Backward: the densification statistic weighs |dL/dmean| by the distance from the camera
  // (3DGS's thresholds are for that). Refracted rays start at the water, so a trainer gives
  // the camera position here and distances run from it to the ray's origin, then along the
  // ray. Unset: from the ray's origin.
  std::optional<glm::vec3> statisticsViewpoint;
  // Forward: write them; backward: read them (the same records, from the forward that
  // produced the `results` it is given). Unset: the backward re-traces every ray.
  const HitRecords* hitRecords = nullptr;
};

// The default k-buffer size. The output does not depend on K (hits are blended in the same
// order); the speed does: on lavapipe every k-buffer round re-traverses the BVH and the 8
// rays of a SIMD group wait for the one with the most rounds, so one round for nearly every
// ray pays. `refrax bench tracer-scene` measured K = 48 1.6-2x faster than K = 16 on trained
// scenes (2k-112k Gaussians, 10-23 hits per ray) and 1.6x on the 100k probe scene; K = 64
// was within the noise of 48 (5-10% either way).
constexpr uint32_t kDefaultKBuffer = 48;

// Pipelines, compiled on first use (lavapipe JIT-compiles each one).
struct GaussianTracer {
  Context* ctx = nullptr;
  uint32_t K = kDefaultKBuffer;
  bool casAtomics = false;  // compare-and-swap instead of float atomicAdd (forced where the device lacks it)
  ComputePipeline prepare;
  ComputePipeline forward[2];
  ComputePipeline backward[2];
  ComputePipeline tileCull;          // engine/gaussian/tiled_trace.h
  ComputePipeline forwardTiled[2];
  ComputePipeline bvhRefit;          // the compute trace backend's proxy BVH (engine/trace/box_bvh.h)
  // Where the proxies' median-split order is made: on the device (engine/trace/device_order.h)
  // on a GPU, where it saves reading the Gaussians back; on the host from their means on a CPU
  // device (lavapipe), where the device's passes cost several times the host's sort (bench
  // proxy-order). The two orders are the same (tests/test_device_order.cpp). Training
  // densifies on the same side (engine/gaussian/densify_device.h).
  bool orderOnDevice = true;
  std::optional<DeviceOrderPipelines> order;
  Buffer noHitRecords;  // bound where no hit records are written or read
};
// K: k-buffer size (specialization constant). casAtomics: force the fallback even where
// float atomics exist (tests use it to cover both paths).
GaussianTracer createGaussianTracer(Context& ctx, uint32_t K = kDefaultKBuffer, bool casAtomics = false);

struct GaussianProxies {
  ProxyKind kind = ProxyKind::AabbBlas;
  uint32_t count = 0;
  uint32_t clamped = 0;         // Gaussians whose box was clamped to kMaxProxyHalfExtent (when built)
  Buffer orderBuffer;           // order[slot] = Gaussian id (slot = BLAS primitive / TLAS instance)
  std::optional<MedianSplitScratch> orderScratch;  // kept once reordered (reorderGaussianProxies)
  Buffer trace;      // TraceGaussian per slot (AABB variant) or per id (instanced variant)
  Buffer sh;         // SH coefficients per Gaussian id as 12 vec4s (the tracer loads these, not the 48 raw floats)
  Buffer spheres;    // bounding sphere of each cut-off ellipsoid (centre, radius), in `trace`'s order (the tiled forward's culling)
  Buffer boxes;      // AABB per slot (AABB variant; written in both)
  Buffer instances;  // VkAccelerationStructureInstanceKHR per slot (TLAS of either variant)
  Buffer unitBox;    // the one box [-1,1]^3 (instanced variant)
  AccelStruct blas;
  AccelStruct tlas;
  BoxBvh bvh;        // the compute trace backend: the boxes' BVH instead of blas/tlas (AABB variant)
  bool allowUpdate = false;
};
// Binding 0 of the tracer's shaders: the TLAS, or the box BVH's nodes (compute backend).
Binding sceneBinding(const GaussianProxies& proxies);
// The tracer shader `name` for the context's trace backend ("_compute" variants), and binding
// 0's type.
std::string traceShaderName(const Context& ctx, const std::string& name);
VkDescriptorType sceneBindingType(const Context& ctx);

// The median-split order of the Gaussians' means on the host (presort.h medianSplitOrder).
std::vector<uint32_t> gaussianMeansOrder(const GaussianSet& set);

// The proxy box of one Gaussian (raw parameters) as gaussian_prepare.comp writes it, on the
// host in double precision (used to choose the BVH order, and by benchmarks), as
// VkAabbPositionsKHR: min x y z, max x y z.
void gaussianProxyBox(const float* g, float box[6]);

// Orders the proxies (the median split of the Gaussians' means, where tracer.orderOnDevice
// says), writes them from the device parameters and builds the acceleration structures. `host`
// is the same Gaussians (the count of clamped boxes, and a host-made order, are taken from it).
GaussianProxies buildGaussianProxies(Context& ctx, GaussianTracer& tracer, const DeviceGaussians& gaussians, const GaussianSet& host,
                                     ProxyKind kind, bool allowUpdate = true);
// The same with no host copy (training's Gaussians densified on the device): the order is made
// on the device (tracer.orderOnDevice must hold) and no clamped boxes are counted.
GaussianProxies buildGaussianProxies(Context& ctx, GaussianTracer& tracer, const DeviceGaussians& gaussians, ProxyKind kind,
                                     bool allowUpdate = true);
// The proxies in the median-split order of the Gaussians' means now (same count), the
// structures rebuilt, after the Gaussians moved. The order is the one buildGaussianProxies gives
// the same Gaussians, so a run resumed from a checkpoint traces the tree the uninterrupted run
// traced. Recorded (cmd...) only where tracer.orderOnDevice: nothing is read back; otherwise the
// means are read back and ordered on the host.
void cmdReorderGaussianProxies(VkCommandBuffer cb, GaussianTracer& tracer, GaussianProxies& proxies, const DeviceGaussians& gaussians);
void reorderGaussianProxies(Context& ctx, GaussianTracer& tracer, GaussianProxies& proxies, const DeviceGaussians& gaussians);
// The proxies' order (order[slot] = Gaussian id), read back.
std::vector<uint32_t> downloadProxyOrder(Context& ctx, const GaussianProxies& proxies);
// After the Gaussians moved (same count): rewrite the proxies and refit (keeps the order
// and the tree topology) or rebuild the tree in the same order.
void cmdUpdateGaussianProxies(VkCommandBuffer cb, GaussianTracer& tracer, GaussianProxies& proxies, const DeviceGaussians& gaussians,
                              bool refit);
void updateGaussianProxies(Context& ctx, GaussianTracer& tracer, GaussianProxies& proxies, const DeviceGaussians& gaussians, bool refit);

// Recorded passes over device buffers (for pipelines of several stages and benchmarks).
// rays: GpuRay[count]; results: GpuTraceResult[count]; dLoss: float4 (dL/dRGB, dL/dopacity)
// per ray; grads: kGaussianFloats floats per Gaussian and stats: 2 floats per Gaussian
// (position-gradient norm sum, hit count), both accumulated into (zero them first);
// rayGrads: GpuRayGrad[count].
void cmdTraceForward(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const DeviceGaussians& gaussians,
                     const Buffer& rays, const Buffer& results, uint32_t count, const TraceOptions& options = {});
void cmdTraceBackward(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const DeviceGaussians& gaussians,
                      const Buffer& rays, const Buffer& results, const Buffer& dLoss, const Buffer& grads, const Buffer& stats,
                      const Buffer& rayGrads, uint32_t count, const TraceOptions& options = {});

// Whole passes from host vectors.
std::vector<GpuTraceResult> traceGaussians(Context& ctx, GaussianTracer& tracer, const GaussianProxies& proxies,
                                           const DeviceGaussians& gaussians, const std::vector<GpuRay>& rays,
                                           const TraceOptions& options = {});
struct GaussianGradients {
  std::vector<float> params;     // kGaussianFloats per Gaussian
  std::vector<float> stats;      // 2 per Gaussian: sum of |dL/dmean| * distance / 2, rays that blended it
  std::vector<GpuRayGrad> rays;  // per ray
};
// dLoss: 4 floats per ray (dL/dR, dL/dG, dL/dB, dL/dopacity); `forward` from traceGaussians.
// hitRecordsPerRay > 0: a recording forward runs first, as in training, and the backward
// reads its hit records (options.hitRecords must be unset).
GaussianGradients traceGaussiansBackward(Context& ctx, GaussianTracer& tracer, const GaussianProxies& proxies,
                                         const DeviceGaussians& gaussians, const std::vector<GpuRay>& rays,
                                         const std::vector<GpuTraceResult>& forward, const std::vector<float>& dLoss,
                                         const TraceOptions& options = {}, uint32_t hitRecordsPerRay = 0);

}  // namespace refrax
