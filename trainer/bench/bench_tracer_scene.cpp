// refrax bench tracer-scene: where the Gaussian tracer's time goes on a given (trained) scene.
// Renders a 3DGS PLY along straight camera rays (as render-gaussians does) and reports
// - the proxies: density and proxy-box size distributions, faint Gaussians;
// - a CPU emulation of lavapipe's BVH (binary tree over the proxies in slot order, split at
//   the middle index) on a subsample of the rays: internal nodes and leaf candidates a full
//   ray visits, how many of those candidates are accepted hits, and how many candidates
//   still lie before the point where the forward stops (transmittance < 1e-3);
// - the device forward (and backward) time per k-buffer size, hits and rounds per ray.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <string>
#include <vector>

#include "engine/camera/camera_rays.h"
#include "engine/base/error.h"
#include "engine/view/fly_camera.h"
#include "engine/view/view_camera.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/trace/presort.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/gaussian/water_removal.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

// lavapipe's BVH over boxes in slot order (rqprobe's emulation): node i has two children,
// each an internal node (>= 0) or a leaf (~slot), or none (kNoChild).
constexpr int kNoChild = -2147483647 - 1;
struct SimNode {
  Box child[2];
  int index[2];
};
Box unionOf(const Box& a, const Box& b) {
  return {std::min(a.minX, b.minX), std::min(a.minY, b.minY), std::min(a.minZ, b.minZ),
          std::max(a.maxX, b.maxX), std::max(a.maxY, b.maxY), std::max(a.maxZ, b.maxZ)};
}
int simBuild(std::vector<SimNode>& nodes, const std::vector<Box>& boxes, int first, int last, Box& bounds) {
  int id = int(nodes.size());
  nodes.push_back({});
  int split = (first + last) / 2;
  Box b0, b1;
  int c0 = first < split ? simBuild(nodes, boxes, first, split, b0) : (b0 = boxes[first], ~first);
  int c1 = kNoChild;
  if (first < last) c1 = split + 1 < last ? simBuild(nodes, boxes, split + 1, last, b1) : (b1 = boxes[last], ~last);
  nodes[id].index[0] = c0;
  nodes[id].index[1] = c1;
  nodes[id].child[0] = b0;
  if (c1 != kNoChild) nodes[id].child[1] = b1;
  bounds = c1 != kNoChild ? unionOf(b0, b1) : b0;
  return id;
}

bool slab(const Box& b, const glm::dvec3& o, const glm::dvec3& inv, double tmax, double& t0) {
  double lo[3] = {b.minX, b.minY, b.minZ}, hi[3] = {b.maxX, b.maxY, b.maxZ};
  double a = 0, z = tmax;
  for (int k = 0; k < 3; k++) {
    double u = (lo[k] - o[k]) * inv[k], v = (hi[k] - o[k]) * inv[k];
    a = std::max(a, std::min(u, v));
    z = std::min(z, std::max(u, v));
  }
  t0 = a;
  return a <= z;
}

struct Candidate {
  uint32_t slot;
  double tEnter;
};
// Every leaf a ray [0, tmax] overlaps, and the number of internal nodes visited.
void simTraverse(const std::vector<SimNode>& nodes, const glm::dvec3& o, const glm::dvec3& d, double tmax, long& visits,
                 std::vector<Candidate>& leaves) {
  glm::dvec3 inv = 1.0 / d;
  std::vector<int> stack{0};
  while (!stack.empty()) {
    int id = stack.back();
    stack.pop_back();
    visits++;
    for (int c = 0; c < 2; c++) {
      int idx = nodes[id].index[c];
      double t0;
      if (idx == kNoChild || !slab(nodes[id].child[c], o, inv, tmax, t0)) continue;
      if (idx < 0) leaves.push_back({uint32_t(~idx), t0});
      else stack.push_back(idx);
    }
  }
}

std::vector<int> parseList(const std::string& text) {
  std::vector<int> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) v.push_back(std::stoi(item));
  if (v.empty()) fail("--k expects comma-separated k-buffer sizes");
  return v;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  size_t i = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + long(i), v.end());
  return v[i];
}

double cpuNowMs() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// The Gaussians' proxy boxes, with their bounds, densities and sizes printed.
std::vector<Box> proxyBoxes(const GaussianSet& set) {
  using namespace f64;
  const size_t n = set.count();
  std::vector<Box> boxes(n);
  std::vector<double> side(n), density(n);
  Box scene;
  gaussianProxyBox(set.at(0), &scene.minX);
  size_t faint = 0, unreachable = 0;
  for (size_t i = 0; i < n; i++) {
    gaussianProxyBox(set.at(i), &boxes[i].minX);
    scene = unionOf(scene, boxes[i]);
    side[i] = std::max({boxes[i].maxX - boxes[i].minX, boxes[i].maxY - boxes[i].minY, boxes[i].maxZ - boxes[i].minZ});
    density[i] = sigmoidOf(real(set.at(i)[kGaussLogitDensity]));
    if (density[i] < kMinKernelResponse) faint++;
    if (density[i] < kMinAlpha) unreachable++;
  }
  std::printf("%zu Gaussians; proxy bounds x %.3f..%.3f y %.3f..%.3f z %.3f..%.3f\n", n, scene.minX, scene.maxX, scene.minY, scene.maxY,
              scene.minZ, scene.maxZ);
  std::printf("density quantiles 10/50/90%%: %.4f %.4f %.4f; below the 0.0113 response cut-off: %zu; below alpha 1/255 (never hit): %zu\n",
              quantile(density, 0.1), quantile(density, 0.5), quantile(density, 0.9), faint, unreachable);
  std::printf("proxy box longest side quantiles 50/90/99/100%%: %.4f %.4f %.4f %.4f\n", quantile(side, 0.5), quantile(side, 0.9),
              quantile(side, 0.99), quantile(side, 1.0));

  return boxes;
}

// The forward (and with --backward the backward) per K on the device, timed; returns the
// camera rays it traced (for the emulation).
std::vector<GpuRay> timeDeviceTracer(const cli::Args& args, const GaussianSet& set, const FlyCamera& cam, long size, int runs,
                                     const std::vector<int>& ks, uint32_t recordsPerRay) {
  const uint32_t count = uint32_t(size * size);
  const size_t n = set.count();
  auto ctx = cli::openContext(args);
  ProxyKind kind = proxyKindFor(args.get("proxy", "aabb"), ctx->caps);
  DeviceGaussians dev = uploadGaussians(*ctx, set);
  CameraRayPipelines cameraPipelines = createCameraRayPipelines(*ctx);
  Camera camera = cameraFromFly(cam, int(size), int(size));
  TraceOptions opt;
  opt.shDegree = uint32_t(args.getInt("sh-degree", 3));
  Buffer rayBuf = createBuffer(*ctx, VkDeviceSize(count) * sizeof(GpuRay));
  Buffer results = createBuffer(*ctx, VkDeviceSize(count) * sizeof(GpuTraceResult));
  Buffer dLoss = createBuffer(*ctx, VkDeviceSize(count) * 16);
  Buffer grads = createBuffer(*ctx, VkDeviceSize(n) * kGaussianFloats * 4);
  Buffer stats = createBuffer(*ctx, VkDeviceSize(n) * 8);
  Buffer rayGrads = createBuffer(*ctx, VkDeviceSize(count) * sizeof(GpuRayGrad));
  fillBuffer(*ctx, dLoss, 0x3C23D70Au);  // 0.01 per channel
  submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, cameraPipelines, camera, rayBuf, 0.0f, 1e6f); });
  std::vector<GpuRay> rays = downloadVector<GpuRay>(*ctx, rayBuf, count);
  std::vector<GpuTraceResult> res;
  HitRecords records;  // training's pair, timed with --backward only
  if (args.has("backward")) records = createHitRecords(*ctx, count, recordsPerRay);
  for (int K : ks) {
    GaussianTracer tracer = createGaussianTracer(*ctx, uint32_t(K));
    GaussianProxies proxies = buildGaussianProxies(*ctx, tracer, dev, set, kind, false);
    auto forward = [&](const TraceOptions& o) {
      submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, tracer, proxies, dev, rayBuf, results, count, o); });
    };
    auto backward = [&](const TraceOptions& o) {
      submitAndWait(*ctx, [&](VkCommandBuffer cb) {
        cmdTraceBackward(cb, tracer, proxies, dev, rayBuf, results, dLoss, grads, stats, rayGrads, count, o);
      });
    };
    forward(opt);
    double c0 = cpuNowMs();
    double fwdMs = bench::medianMs(0, runs, [&] { forward(opt); });
    double fwdCpu = (cpuNowMs() - c0) / runs;
    res = downloadVector<GpuTraceResult>(*ctx, results, count);
    double hits = 0, rounds = 0, recorded = 0;
    for (const auto& r : res) hits += r.hits, rounds += r.rounds, recorded += r.hits <= recordsPerRay;
    char backwardText[192] = "";
    if (args.has("backward")) {
      backward(opt);
      double bwdMs = bench::medianMs(0, runs, [&] { backward(opt); });
      // training's pair: a forward that records the hits, a backward that reads them
      TraceOptions recording = opt;
      recording.hitRecords = &records;
      double recFwdMs = bench::medianMs(0, runs, [&] { forward(recording); });
      double recBwdMs = bench::medianMs(0, runs, [&] { backward(recording); });
      std::snprintf(backwardText, sizeof backwardText,
                    ", re-tracing backward %.1f ms; training pair %.1f + %.1f ms (backward/forward %.2f, %.1f%% of rays recorded)", bwdMs,
                    recFwdMs, recBwdMs, recBwdMs / recFwdMs, 100.0 * recorded / count);
    }
    std::printf("K=%d %s: forward %.1f ms (%.3f Mrays/s, cpu %.0f ms/run)%s; %.2f hits/ray, %.3f rounds/ray\n", K, proxyKindName(kind),
                fwdMs, count / (fwdMs * 1e3), fwdCpu, backwardText, hits / count, rounds / count);
  }

  return rays;
}

// A CPU emulation of the BVH on every stride-th pixel in x and y: nodes visited, candidates,
// accepted hits, and how many of them come before the forward would stop.
void emulateBvh(const GaussianSet& set, const std::vector<Box>& boxes, const std::vector<GpuRay>& rays, long size, long stride) {
  using namespace f64;
  const size_t n = set.count();
  std::vector<uint32_t> order = medianSplitOrder(boxes);
  std::vector<Box> slotBoxes = permuted(boxes, order);
  std::vector<SimNode> nodes;
  nodes.reserve(n);
  Box bounds;
  simBuild(nodes, slotBoxes, 0, int(n) - 1, bounds);
  long visits = 0, leaves = 0, accepted = 0, beforeStop = 0, acceptedBeforeStop = 0, sampled = 0;
  std::vector<Candidate> cands;
  for (long y = stride / 2; y < size; y += stride)
    for (long x = stride / 2; x < size; x += stride) {
      const GpuRay& r = rays[size_t(y * size + x)];
      glm::dvec3 o(r.origin[0], r.origin[1], r.origin[2]), d(r.dir[0], r.dir[1], r.dir[2]);
      cands.clear();
      simTraverse(nodes, o, d, r.tmax, visits, cands);
      leaves += long(cands.size());
      // accepted hits along the whole ray, sorted, blended until the forward would stop
      std::vector<std::pair<double, double>> hitsTA;
      for (const Candidate& c : cands) {
        const float* g = set.at(order[c.slot]);
        real3 mu(g[kGaussMean], g[kGaussMean + 1], g[kGaussMean + 2]);
        real3x3 R = rotationOf(real4(g[kGaussRotation], g[kGaussRotation + 1], g[kGaussRotation + 2], g[kGaussRotation + 3]));
        real3 s = glm::exp(real3(g[kGaussLogScale], g[kGaussLogScale + 1], g[kGaussLogScale + 2]));
        real3x3 M = worldToLocalOf(R, real3(1) / s);
        real t;
        real3 rr, xx;
        real m = gaussianPeak(o, d, mu, M, t, rr, xx);
        real a = acceptedAlpha(m, sigmoidOf(real(g[kGaussLogitDensity])));
        if (a > 0 && t > 0 && t < r.tmax) hitsTA.push_back({t, a});
      }
      accepted += long(hitsTA.size());
      std::sort(hitsTA.begin(), hitsTA.end());
      double T = 1, tStop = r.tmax;
      for (const auto& h : hitsTA) {
        acceptedBeforeStop++;
        T *= 1 - clampedAlpha(h.second);
        if (T < kMinTransmittance) {
          tStop = h.first;
          break;
        }
      }
      for (const Candidate& c : cands) beforeStop += c.tEnter <= tStop ? 1 : 0;
      sampled++;
    }
  double s = double(std::max(sampled, 1L));
  std::printf("BVH emulation (%ld rays, whole ray): %.1f internal nodes, %.1f leaf candidates, %.1f accepted hits per ray; "
              "up to the stop: %.1f candidates, %.1f accepted hits\n",
              sampled, visits / s, leaves / s, accepted / s, beforeStop / s, acceptedBeforeStop / s);
}

int runBenchTracerScene(const cli::Args& args) {
  if (!args.has("ply")) fail("refrax bench tracer-scene needs --ply FILE");
  GaussianSet set = readGaussiansPly(args.get("ply"));
  if (set.count() == 0) fail("the PLY has no Gaussians");
  FlyCamera cam = parseLookAt(args.get("camera", "0,-2,1.2,0,0,-0.5"));
  cam.tanHalfFovY = 0.36f;
  long size = args.getInt("size", 256);
  if (size <= 0 || size > 4096) fail("--size must be between 1 and 4096");
  int runs = int(args.getInt("runs", 3));
  long stride = std::max(1L, args.getInt("sample-stride", 8));
  std::vector<int> ks = parseList(args.get("k", "16,48"));
  const uint32_t recordsPerRay = uint32_t(args.getIntIn("hit-records", kDefaultHitRecordsPerRay, 1, 1024));
  const std::vector<Box> boxes = proxyBoxes(set);
  const std::vector<GpuRay> rays = timeDeviceTracer(args, set, cam, size, runs, ks, recordsPerRay);
  emulateBvh(set, boxes, rays, size, stride);
  return 0;
}

REFRAX_BENCH_SUITE({"tracer-scene",
                    "where the Gaussian tracer's time goes on a PLY scene: proxy sizes, emulated BVH candidates vs hits, forward ms per K",
                    {{"ply", "FILE", "3DGS PLY (e.g. a run's point_cloud.ply)", ""},
                     {"camera", "x,y,z,tx,ty,tz", "camera position and target (world up is +z)", "0,-2,1.2,0,0,-0.5"},
                     {"size", "PIXELS", "image side in rays", "256"},
                     {"k", "K,K", "k-buffer sizes to time", "16,48"},
                     {"proxy", "aabb|instanced|auto", "Gaussian proxies", "aabb"},
                     {"hit-records", "N", "with --backward: hit records per ray of training's forward/backward pair", std::to_string(kDefaultHitRecordsPerRay)},
                     {"sh-degree", "D", "SH degree evaluated", "3"},
                     {"runs", "N", "timed runs per measurement (median)", "3"},
                     {"backward", "", "also time the backward (re-tracing) and training's pair (recording forward, reading backward)", ""},
                     {"sample-stride", "S", "emulate every S-th pixel in x and y", "8"}},
                    runBenchTracerScene});

}  // namespace
}  // namespace refrax
