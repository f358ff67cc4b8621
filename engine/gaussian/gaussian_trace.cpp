#include "engine/gaussian/gaussian_trace.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/trace/presort.h"
#include "engine/gaussian/gaussian_trace_internal.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"

namespace refrax {

namespace {

struct PreparePush {
  uint32_t count, instanced;
  uint32_t blasAddress[2];
};

constexpr uint32_t kTraceGaussianBytes = 48;
constexpr uint32_t kShPackedBytes = 12 * 16;  // kShVec4s vec4s (gaussian_trace_types.glsl)
static_assert(kShPackedBytes == f32::kShCoefficients * 3 * sizeof(float), "the packed SH holds every coefficient");
constexpr uint32_t kInstanceBytes = sizeof(VkAccelerationStructureInstanceKHR);
static_assert(kInstanceBytes == 64, "instance layout written by gaussian_prepare.comp");
static_assert(sizeof(Box) == 6 * sizeof(float), "gaussianProxyBox writes a Box as six floats");

const ComputePipeline& forwardPipeline(GaussianTracer& t, ProxyKind kind) {
  ComputePipeline& p = t.forward[uint32_t(kind)];
  if (!p.pipeline)
    p = createComputePipeline(*t.ctx, traceShaderName(*t.ctx, "gaussian_forward").c_str(),
                              {sceneBindingType(*t.ctx), kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                              sizeof(TracePush), traceSpec(t.K, kind));
  return p;
}

const ComputePipeline& backwardPipeline(GaussianTracer& t, ProxyKind kind) {
  ComputePipeline& p = t.backward[uint32_t(kind)];
  if (!p.pipeline)
    p = createComputePipeline(*t.ctx, traceShaderName(*t.ctx, t.casAtomics ? "gaussian_backward_cas" : "gaussian_backward").c_str(),
                              {sceneBindingType(*t.ctx), kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer,
                               kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer},
                              sizeof(TracePush), traceSpec(t.K, kind));
  return p;
}

const DeviceOrderPipelines& orderPipelines(GaussianTracer& t) {
  if (!t.order) t.order = createDeviceOrderPipelines(*t.ctx);
  return *t.order;
}

// The Gaussians' means in their parameters: the points the proxies are ordered by.
constexpr PointLayout kGaussianMeans{kGaussianFloats, f32::kGaussMean};

const ComputePipeline& preparePipeline(GaussianTracer& t) {
  if (!t.prepare.pipeline)
    t.prepare = createComputePipeline(*t.ctx, "gaussian_prepare",
                                      {kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer, kStorageBuffer,
                                       kStorageBuffer},
                                      sizeof(PreparePush));
  return t.prepare;
}

}  // namespace

void gaussianProxyBox(const float* g, float box[6]) {
  using namespace f64;
  real3 mu(g[kGaussMean], g[kGaussMean + 1], g[kGaussMean + 2]);
  real3x3 R = rotationOf(real4(g[kGaussRotation], g[kGaussRotation + 1], g[kGaussRotation + 2], g[kGaussRotation + 3]));
  real3 s = glm::exp(real3(g[kGaussLogScale], g[kGaussLogScale + 1], g[kGaussLogScale + 2]));
  real radius = proxyRadiusOf(sigmoidOf(g[kGaussLogitDensity]));
  real3 e;
  for (int a = 0; a < 3; a++) e[a] = std::min(radius * length(real3(R[0][a] * s.x, R[1][a] * s.y, R[2][a] * s.z)), kMaxProxyHalfExtent);
  for (int a = 0; a < 3; a++) {
    box[a] = float(mu[a] - e[a]);
    box[3 + a] = float(mu[a] + e[a]);
  }
}

void validateRays(const std::vector<GpuRay>& rays) {
  for (size_t i = 0; i < rays.size(); i++) {
    const GpuRay& r = rays[i];
    bool finite = std::isfinite(r.tmin) && std::isfinite(r.tmax);
    for (int a = 0; a < 3; a++) finite = finite && std::isfinite(r.origin[a]) && std::isfinite(r.dir[a]);
    if (!finite) fail("ray " + std::to_string(i) + " has a non-finite origin, direction or range");
    if (r.dir[0] == 0 && r.dir[1] == 0 && r.dir[2] == 0) fail("ray " + std::to_string(i) + " has a zero direction");
    if (r.tmin < 0 || r.tmax < r.tmin) fail("ray " + std::to_string(i) + " has an invalid range [tmin, tmax]");
  }
}

std::vector<SpecConstant> traceSpec(uint32_t K, ProxyKind kind) { return {{0, K}, {1, kind == ProxyKind::InstancedUnitBox ? 1u : 0u}}; }

TracePush tracePush(uint32_t count, const TraceOptions& o) {
  TracePush push{};
  if (o.hitRecords) {
    if (o.hitRecords->perRay == 0 || o.hitRecords->rays < count) fail("hit records hold fewer rays than the trace");
    push.recordsPerRay = o.hitRecords->perRay;
  }
  for (int c = 0; c < 3; c++) push.background[c] = o.background[c];
  push.count = count;
  push.shDegree = o.shDegree;
  push.maxRounds = std::max(o.maxRounds, 1u);
  push.minTransmittance = o.minTransmittance;
  if (!(o.minTransmittance >= 0.0f && o.minTransmittance < 1.0f)) fail("minimum transmittance must be in [0, 1)");
  if (o.statisticsViewpoint) {
    for (int a = 0; a < 3; a++) push.statViewpoint[a] = (*o.statisticsViewpoint)[a];
    push.statViewpoint[3] = 1.0f;
  }
  push.depthAtOpacity = o.depthAtOpacity;
  if (!(o.depthAtOpacity >= 0.0f && o.depthAtOpacity < 1.0f)) fail("the depth's opacity level must be in [0, 1)");
  if (o.shDegree > 3) fail("SH degree " + std::to_string(o.shDegree) + " is above 3");
  return push;
}

const char* proxyKindName(ProxyKind kind) { return kind == ProxyKind::AabbBlas ? "aabb-blas" : "instanced-unit-box"; }

ProxyKind proxyKindFor(const std::string& choice, const DeviceCaps& caps) {
  if (choice == "aabb") return ProxyKind::AabbBlas;
  if (choice == "instanced") return ProxyKind::InstancedUnitBox;
  if (choice != "auto") fail("unknown Gaussian proxy '" + choice + "' (aabb, instanced or auto)");
  return caps.type == VK_PHYSICAL_DEVICE_TYPE_CPU ? ProxyKind::AabbBlas : ProxyKind::InstancedUnitBox;
}

std::string traceShaderName(const Context& ctx, const std::string& name) {
  return ctx.trace == TraceBackend::Compute ? name + "_compute" : name;
}

VkDescriptorType sceneBindingType(const Context& ctx) { return ctx.trace == TraceBackend::Compute ? kStorageBuffer : kAccelStruct; }

Binding sceneBinding(const GaussianProxies& p) { return p.bvh.leaves ? bind(p.bvh.nodes) : bind(p.tlas); }

GaussianTracer createGaussianTracer(Context& ctx, uint32_t K, bool casAtomics) {
  if (K == 0 || K > 64) fail("k-buffer size " + std::to_string(K) + " is outside 1..64");
  GaussianTracer t;
  t.ctx = &ctx;
  t.K = K;
  t.casAtomics = casAtomics || !ctx.caps.floatAtomicAdd;
  t.noHitRecords = createBuffer(ctx, 16);
  t.orderOnDevice = ctx.caps.type != VK_PHYSICAL_DEVICE_TYPE_CPU;
  // REFRAX_PROXY_ORDER=device|host: the other side on any device (the compute-backend test pass
  // orders on the device as a GPU does; tests/CMakeLists.txt).
  if (const char* where = std::getenv("REFRAX_PROXY_ORDER")) {
    const std::string w = where;
    if (w != "device" && w != "host") fail("REFRAX_PROXY_ORDER must be device or host, not '" + w + "'");
    t.orderOnDevice = w == "device";
  }
  return t;
}

HitRecords createHitRecords(Context& ctx, uint32_t rays, uint32_t perRay) {
  if (rays == 0 || perRay == 0) fail("hit records need at least one ray and one record per ray");
  HitRecords r;
  r.rays = rays;
  r.perRay = perRay;
  r.buffer = createBuffer(ctx, VkDeviceSize(rays) * perRay * 8);
  return r;
}

namespace {

// buildGaussianProxies, with the host's copy or without it (then ordered on the device).
GaussianProxies buildProxies(Context& ctx, GaussianTracer& tracer, const DeviceGaussians& gaussians, const GaussianSet* hostCopy,
                             ProxyKind kind, bool allowUpdate) {
  if (hostCopy && hostCopy->count() != gaussians.count) fail("buildGaussianProxies: host and device Gaussian counts differ");
  if (!hostCopy && !tracer.orderOnDevice) fail("buildGaussianProxies: no host copy to order the proxies by on this device");
  if (gaussians.count > 0xFFFFFFu) fail("more than 16M Gaussians (instance custom indices have 24 bits)");
  GaussianProxies p;
  // The compute backend has no acceleration structures: the proxies are boxes in a BVH of its own.
  const bool compute = ctx.trace == TraceBackend::Compute;
  if (compute) kind = ProxyKind::AabbBlas;
  p.kind = kind;
  p.count = gaussians.count;
  p.allowUpdate = allowUpdate;
  for (uint32_t i = 0; hostCopy && i < p.count; i++) {
    float box[6];
    gaussianProxyBox(hostCopy->at(i), box);
    bool clamped = false;
    for (int a = 0; a < 3; a++) clamped = clamped || box[3 + a] - box[a] >= float(2 * f64::kMaxProxyHalfExtent);
    p.clamped += clamped ? 1 : 0;
  }
  p.orderBuffer = createBuffer(ctx, VkDeviceSize(std::max<uint32_t>(p.count, 1)) * sizeof(uint32_t));
  p.trace = createBuffer(ctx, VkDeviceSize(p.count) * kTraceGaussianBytes);
  p.sh = createBuffer(ctx, VkDeviceSize(p.count) * kShPackedBytes);
  p.spheres = createBuffer(ctx, VkDeviceSize(p.count) * 16);
  AccelOptions opts{allowUpdate, false};
  if (compute) {
    // (no Gaussians: one empty box, which no ray meets)
    std::vector<Box> empty(std::max<uint32_t>(p.count, 1), Box{INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY});
    p.boxes = createBufferFrom(ctx, empty);
    p.instances = createBuffer(ctx, kInstanceBytes);  // placeholder binding
    p.bvh = createBoxBvh(ctx, std::max<uint32_t>(p.count, 1));
    if (!tracer.bvhRefit.pipeline) tracer.bvhRefit = createBvhRefitPipeline(ctx);
  } else if (kind == ProxyKind::AabbBlas) {
    p.boxes = createBuffer(ctx, VkDeviceSize(p.count) * sizeof(Box), kAccelInput);
    p.instances = createBuffer(ctx, kInstanceBytes, kAccelInput);
    p.blas = createAabbBlas(ctx, p.boxes, p.count, opts);
    VkAccelerationStructureInstanceKHR inst = makeInstance(p.blas, 0, nullptr, VK_GEOMETRY_INSTANCE_FORCE_NO_OPAQUE_BIT_KHR);
    upload(ctx, p.instances, &inst, sizeof(inst));
    p.tlas = createTlas(ctx, p.instances, 1, opts);
  } else {
    Box unit{-1, -1, -1, 1, 1, 1};
    p.unitBox = createBufferFrom(ctx, std::vector<Box>{unit}, kAccelInput);
    p.blas = createAabbBlas(ctx, p.unitBox, 1);
    p.boxes = createBuffer(ctx, sizeof(Box));  // placeholder binding
    p.instances = createBuffer(ctx, VkDeviceSize(p.count) * kInstanceBytes, kAccelInput);
    p.tlas = createTlas(ctx, p.instances, p.count, opts);
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdBuild(cb, p.blas); });
  }
  if (tracer.orderOnDevice) {
    MedianSplitScratch scratch = createMedianSplitScratch(ctx, p.count);
    submitAndWait(ctx, [&](VkCommandBuffer cb) {
      cmdMedianSplitOrder(cb, orderPipelines(tracer), scratch, gaussians.params, kGaussianMeans, p.count, p.orderBuffer);
      cmdUpdateGaussianProxies(cb, tracer, p, gaussians, false);
    });
    return p;
  }
  if (p.count) {
    std::vector<uint32_t> order = gaussianMeansOrder(*hostCopy);
    upload(ctx, p.orderBuffer, order.data(), order.size() * sizeof(uint32_t));
  }
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateGaussianProxies(cb, tracer, p, gaussians, false); });
  return p;
}

}  // namespace

GaussianProxies buildGaussianProxies(Context& ctx, GaussianTracer& tracer, const DeviceGaussians& gaussians, const GaussianSet& host,
                                     ProxyKind kind, bool allowUpdate) {
  return buildProxies(ctx, tracer, gaussians, &host, kind, allowUpdate);
}

GaussianProxies buildGaussianProxies(Context& ctx, GaussianTracer& tracer, const DeviceGaussians& gaussians, ProxyKind kind, bool allowUpdate) {
  return buildProxies(ctx, tracer, gaussians, nullptr, kind, allowUpdate);
}

void cmdReorderGaussianProxies(VkCommandBuffer cb, GaussianTracer& tracer, GaussianProxies& p, const DeviceGaussians& gaussians) {
  if (gaussians.count != p.count) fail("Gaussian count changed since the proxies were built (rebuild them)");
  if (!tracer.orderOnDevice) fail("cmdReorderGaussianProxies: this tracer orders the proxies on the host (reorderGaussianProxies)");
  if (!p.orderScratch) p.orderScratch = createMedianSplitScratch(*tracer.ctx, p.count);
  cmdMedianSplitOrder(cb, orderPipelines(tracer), *p.orderScratch, gaussians.params, kGaussianMeans, p.count, p.orderBuffer);
  cmdUpdateGaussianProxies(cb, tracer, p, gaussians, false);
}

void reorderGaussianProxies(Context& ctx, GaussianTracer& tracer, GaussianProxies& proxies, const DeviceGaussians& gaussians) {
  if (tracer.orderOnDevice) {
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdReorderGaussianProxies(cb, tracer, proxies, gaussians); });
    return;
  }
  if (gaussians.count != proxies.count) fail("Gaussian count changed since the proxies were built (rebuild them)");
  if (proxies.count) {
    std::vector<uint32_t> order = gaussianMeansOrder(downloadGaussians(ctx, gaussians));
    upload(ctx, proxies.orderBuffer, order.data(), order.size() * sizeof(uint32_t));
  }
  updateGaussianProxies(ctx, tracer, proxies, gaussians, false);
}

std::vector<uint32_t> gaussianMeansOrder(const GaussianSet& set) {
  std::vector<Box> means(set.count());  // boxes of no size: their centroids are the means
  for (size_t i = 0; i < set.count(); i++) {
    const float* mu = set.at(i) + f32::kGaussMean;
    means[i] = Box{mu[0], mu[1], mu[2], mu[0], mu[1], mu[2]};
  }
  return medianSplitOrder(means);
}

std::vector<uint32_t> downloadProxyOrder(Context& ctx, const GaussianProxies& proxies) {
  return downloadVector<uint32_t>(ctx, proxies.orderBuffer, proxies.count);
}

void cmdUpdateGaussianProxies(VkCommandBuffer cb, GaussianTracer& tracer, GaussianProxies& p, const DeviceGaussians& gaussians, bool refit) {
  if (gaussians.count != p.count) fail("Gaussian count changed since the proxies were built (rebuild them)");
  PreparePush push{p.count, p.kind == ProxyKind::InstancedUnitBox ? 1u : 0u, {0, 0}};
  if (p.kind == ProxyKind::InstancedUnitBox) {
    push.blasAddress[0] = uint32_t(p.blas.address & 0xFFFFFFFFu);
    push.blasAddress[1] = uint32_t(p.blas.address >> 32);
  }
  // Each variant binds the buffer it does not use at its small placeholder size; the
  // shader writes boxes only for the AABB variant and instances only for the instanced one.
  cmdDispatch(cb, preparePipeline(tracer),
              {bind(gaussians.params), bind(p.orderBuffer), bind(p.trace), bind(p.boxes), bind(p.instances), bind(p.sh), bind(p.spheres)},
              &push,
              groupsFor(p.count, 64));
  cmdBarrier(cb);
  if (p.bvh.leaves) {  // compute backend: the same tree topology, bounds from the new boxes
    cmdRefitBoxBvh(cb, tracer.bvhRefit, p.bvh, p.boxes);
    return;
  }
  if (p.kind == ProxyKind::AabbBlas) {
    if (refit) cmdRefit(cb, p.blas); else cmdBuild(cb, p.blas);
    cmdBarrier(cb);
  }
  if (refit) cmdRefit(cb, p.tlas); else cmdBuild(cb, p.tlas);
  cmdBarrier(cb);
}

void updateGaussianProxies(Context& ctx, GaussianTracer& tracer, GaussianProxies& proxies, const DeviceGaussians& gaussians, bool refit) {
  if (refit && !proxies.allowUpdate) fail("refit of Gaussian proxies built without allowUpdate");
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdUpdateGaussianProxies(cb, tracer, proxies, gaussians, refit); });
}

void cmdTraceForward(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const DeviceGaussians& gaussians,
                     const Buffer& rays, const Buffer& results, uint32_t count, const TraceOptions& options) {
  TracePush push = tracePush(count, options);
  const Buffer& records = options.hitRecords ? options.hitRecords->buffer : tracer.noHitRecords;
  cmdDispatch(cb, forwardPipeline(tracer, proxies.kind),
              {sceneBinding(proxies), bind(proxies.trace), bind(proxies.sh), bind(rays), bind(results), bind(records)}, &push,
              groupsFor(count, 64));
}

void cmdTraceBackward(VkCommandBuffer cb, GaussianTracer& tracer, const GaussianProxies& proxies, const DeviceGaussians& gaussians,
                      const Buffer& rays, const Buffer& results, const Buffer& dLoss, const Buffer& grads, const Buffer& stats,
                      const Buffer& rayGrads, uint32_t count, const TraceOptions& options) {
  if (options.minTransmittance != TraceOptions{}.minTransmittance)
    fail("the Gaussian backward stops at the default minimum transmittance only");
  TracePush push = tracePush(count, options);
  const Buffer& records = options.hitRecords ? options.hitRecords->buffer : tracer.noHitRecords;
  cmdDispatch(cb, backwardPipeline(tracer, proxies.kind),
              {sceneBinding(proxies), bind(proxies.trace), bind(gaussians.params), bind(rays), bind(results), bind(dLoss), bind(grads),
               bind(stats), bind(rayGrads), bind(records), bind(proxies.sh)},
              &push, groupsFor(count, 64));
}

std::vector<GpuTraceResult> traceGaussians(Context& ctx, GaussianTracer& tracer, const GaussianProxies& proxies,
                                           const DeviceGaussians& gaussians, const std::vector<GpuRay>& rays, const TraceOptions& options) {
  if (rays.empty()) return {};
  validateRays(rays);
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer resultBuf = createBuffer(ctx, rays.size() * sizeof(GpuTraceResult));
  fillBuffer(ctx, resultBuf, 0x7FC00000u);  // NaN: a result the shader did not write shows
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, tracer, proxies, gaussians, rayBuf, resultBuf, uint32_t(rays.size()), options); });
  return downloadVector<GpuTraceResult>(ctx, resultBuf, rays.size());
}

GaussianGradients traceGaussiansBackward(Context& ctx, GaussianTracer& tracer, const GaussianProxies& proxies,
                                         const DeviceGaussians& gaussians, const std::vector<GpuRay>& rays,
                                         const std::vector<GpuTraceResult>& forward, const std::vector<float>& dLoss,
                                         const TraceOptions& options, uint32_t hitRecordsPerRay) {
  if (forward.size() != rays.size() || dLoss.size() != 4 * rays.size()) fail("traceGaussiansBackward: per-ray inputs of different sizes");
  if (hitRecordsPerRay > 0 && options.hitRecords) fail("traceGaussiansBackward: hit records given twice");
  for (float v : dLoss)
    if (!std::isfinite(v)) fail("traceGaussiansBackward: non-finite loss gradient");
  GaussianGradients out;
  if (rays.empty()) return out;
  validateRays(rays);
  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer fwdBuf = createBufferFrom(ctx, forward);
  Buffer lossBuf = createBufferFrom(ctx, dLoss);
  Buffer gradBuf = createBuffer(ctx, VkDeviceSize(gaussians.count) * kGaussianFloats * 4);
  Buffer statBuf = createBuffer(ctx, VkDeviceSize(gaussians.count) * 2 * 4);
  Buffer rayGradBuf = createBuffer(ctx, rays.size() * sizeof(GpuRayGrad));
  fillBuffer(ctx, gradBuf, 0);
  fillBuffer(ctx, statBuf, 0);
  fillBuffer(ctx, rayGradBuf, 0x7FC00000u);
  const uint32_t count = uint32_t(rays.size());
  TraceOptions opt = options;
  HitRecords records;
  if (hitRecordsPerRay > 0) {
    records = createHitRecords(ctx, count, hitRecordsPerRay);
    fillBuffer(ctx, records.buffer, 0x7FC00000u);
    opt.hitRecords = &records;
    Buffer recordedResults = createBuffer(ctx, rays.size() * sizeof(GpuTraceResult));
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, tracer, proxies, gaussians, rayBuf, recordedResults, count, opt); });
  }
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdTraceBackward(cb, tracer, proxies, gaussians, rayBuf, fwdBuf, lossBuf, gradBuf, statBuf, rayGradBuf, count, opt);
  });
  out.params = downloadVector<float>(ctx, gradBuf, size_t(gaussians.count) * kGaussianFloats);
  out.stats = downloadVector<float>(ctx, statBuf, size_t(gaussians.count) * 2);
  out.rays = downloadVector<GpuRayGrad>(ctx, rayGradBuf, rays.size());
  return out;
}

}  // namespace refrax
