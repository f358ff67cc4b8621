// refrax bench tracer: the Gaussian ray tracer's forward and backward rates (Mrays/s) on
// the rqprobe's Gaussian scenes (10k and 100k Gaussians, seed 1234, unit-cube volume, the
// probe's camera) at 392x392, for both proxy variants, beside the probe's own k-buffer rate
// run in the same process tree; plus backward/forward ratio, proxy build/refit times and
// memory per Gaussian.
#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "engine/camera/camera_rays.h"
#include "engine/gaussian/water_removal.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/view/view_camera.h"
#include "engine/io/json_io.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

// The probe's Gaussians (rqprobe.cpp makeGaussians, seed 1234: the same draws in the same
// order) in Refrax's raw parameters; SH colours (which the probe has none of) from a
// separate generator so the geometry stays the probe's.
GaussianSet probeScene(int n) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> U(0.f, 1.f);
  std::mt19937 colourRng(99);
  std::uniform_real_distribution<float> C(-1.f, 1.f);
  GaussianSet set;
  set.params.assign(size_t(n) * kGaussianFloats, 0.0f);
  for (int i = 0; i < n; i++) {
    float* g = set.at(size_t(i));
    float mx = U(rng) - 0.5f, my = U(rng) - 0.5f, mz = -U(rng);
    float s[3];
    for (int k = 0; k < 3; k++) s[k] = (0.01f + 0.02f * U(rng)) / 6.f;
    float q[4];
    for (int k = 0; k < 4; k++) q[k] = U(rng) * 2 - 1;
    float density = 0.05f + 0.9f * U(rng);
    g[f32::kGaussMean] = mx, g[f32::kGaussMean + 1] = my, g[f32::kGaussMean + 2] = mz;
    for (int k = 0; k < 4; k++) g[f32::kGaussRotation + k] = q[k];  // q0 is w in the probe's matrix
    for (int k = 0; k < 3; k++) g[f32::kGaussLogScale + k] = std::log(s[k]);
    g[f32::kGaussLogitDensity] = std::log(density / (1 - density));
    for (uint32_t k = 0; k < f32::kShCoefficients; k++)
      for (int c = 0; c < 3; c++) g[f32::kGaussSH + 3 * k + c] = (k == 0 ? 1.5f : 0.2f / float(k)) * C(colourRng);
  }
  return set;
}

// Wall-clock and process CPU time (every lavapipe thread) of `once`, medians after one
// warm-up. CPU time per ray is the steadier figure on a machine shared with other jobs.
struct Timing {
  double wallMs = 0, cpuMs = 0;
};
double cpuNowMs() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
Timing timeRuns(int runs, const std::function<void()>& once) {
  once();
  std::vector<double> wall, cpu;
  for (int i = 0; i < std::max(runs, 1); i++) {
    double c0 = cpuNowMs();
    wall.push_back(bench::medianMs(0, 1, once));
    cpu.push_back(cpuNowMs() - c0);
  }
  std::sort(wall.begin(), wall.end());
  std::sort(cpu.begin(), cpu.end());
  return {wall[wall.size() / 2], cpu[cpu.size() / 2]};
}

std::vector<int> parseCounts(const std::string& s) {
  std::vector<int> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(std::stoi(item));
  if (out.empty()) fail("--counts needs a comma-separated list of Gaussian counts");
  return out;
}

// forward/backward: a render forward and a backward that re-traces every ray;
// recording*: training's pair, the forward writing hit records and the backward reading them.
struct VariantFigures {
  double buildMs = 0, refitMs = 0, forwardMs = 0, backwardMs = 0, meanHits = 0, meanRounds = 0;
  double forwardCpuMs = 0, backwardCpuMs = 0;
  double recordingForwardMs = 0, recordingBackwardMs = 0, recordingForwardCpuMs = 0, recordingBackwardCpuMs = 0;
  double recordedRays = 0;  // share of rays whose hits all fit the records
  double bytesPerGaussian = 0;
};

VariantFigures measureVariant(Context& ctx, GaussianTracer& tracer, const GaussianSet& set, DeviceGaussians& dev, ProxyKind kind,
                              const std::vector<GpuRay>& rays, int runs, uint32_t shDegree, uint32_t recordsPerRay) {
  VariantFigures f;
  const uint32_t count = uint32_t(rays.size());
  GaussianProxies proxies = buildGaussianProxies(ctx, tracer, dev, set, kind, true);
  f.buildMs = bench::medianMs(1, runs, [&] { updateGaussianProxies(ctx, tracer, proxies, dev, false); });
  f.refitMs = bench::medianMs(1, runs, [&] { updateGaussianProxies(ctx, tracer, proxies, dev, true); });

  Buffer rayBuf = createBufferFrom(ctx, rays);
  Buffer results = createBuffer(ctx, VkDeviceSize(count) * sizeof(GpuTraceResult));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> U(-1.f, 1.f);
  std::vector<float> dl(4 * size_t(count));
  for (float& v : dl) v = U(rng);
  Buffer dLoss = createBufferFrom(ctx, dl);
  Buffer grads = createBuffer(ctx, VkDeviceSize(dev.count) * kGaussianFloats * 4);
  Buffer stats = createBuffer(ctx, VkDeviceSize(dev.count) * 8);
  Buffer rayGrads = createBuffer(ctx, VkDeviceSize(count) * sizeof(GpuRayGrad));

  TraceOptions opt;
  opt.shDegree = shDegree;
  Timing fwd = timeRuns(runs, [&] {
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, tracer, proxies, dev, rayBuf, results, count, opt); });
  });
  f.forwardMs = fwd.wallMs;
  f.forwardCpuMs = fwd.cpuMs;
  auto res = downloadVector<GpuTraceResult>(ctx, results, count);
  for (auto& r : res) {
    f.meanHits += r.hits;
    f.meanRounds += r.rounds;
  }
  f.meanHits /= count;
  f.meanRounds /= count;
  auto backward = [&](const TraceOptions& o) {
    return timeRuns(runs, [&] {
      submitAndWait(ctx, [&](VkCommandBuffer cb) {
        vkCmdFillBuffer(cb, grads.buffer, 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(cb, stats.buffer, 0, VK_WHOLE_SIZE, 0);
        cmdBarrier(cb);
        cmdTraceBackward(cb, tracer, proxies, dev, rayBuf, results, dLoss, grads, stats, rayGrads, count, o);
      });
    });
  };
  Timing bwd = backward(opt);
  f.backwardMs = bwd.wallMs;
  f.backwardCpuMs = bwd.cpuMs;
  // training's pair: the forward records the hits, the backward reads them
  HitRecords records = createHitRecords(ctx, count, recordsPerRay);
  TraceOptions recording = opt;
  recording.hitRecords = &records;
  Timing recFwd = timeRuns(runs, [&] {
    submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdTraceForward(cb, tracer, proxies, dev, rayBuf, results, count, recording); });
  });
  Timing recBwd = backward(recording);
  f.recordingForwardMs = recFwd.wallMs;
  f.recordingForwardCpuMs = recFwd.cpuMs;
  f.recordingBackwardMs = recBwd.wallMs;
  f.recordingBackwardCpuMs = recBwd.cpuMs;
  for (auto& r : res) f.recordedRays += r.hits <= recordsPerRay;
  f.recordedRays /= count;
  // Memory that grows with the Gaussian count: parameters, gradients, statistics and the
  // proxies with their acceleration structures (build scratch included).
  double bytes = double(dev.params.size + grads.size + stats.size + proxies.trace.size + proxies.sh.size + proxies.orderBuffer.size + proxies.boxes.size +
                        proxies.instances.size + proxies.blas.storage.size + proxies.blas.scratch.size + proxies.tlas.storage.size +
                        proxies.tlas.scratch.size);
  f.bytesPerGaussian = bytes / dev.count;
  return f;
}

// Each figure the better of two measurements (times: the lower).
void keepBest(VariantFigures& b, const VariantFigures& f) {
  b.buildMs = std::min(b.buildMs, f.buildMs);
  b.refitMs = std::min(b.refitMs, f.refitMs);
  b.forwardMs = std::min(b.forwardMs, f.forwardMs);
  b.backwardMs = std::min(b.backwardMs, f.backwardMs);
  b.forwardCpuMs = std::min(b.forwardCpuMs, f.forwardCpuMs);
  b.backwardCpuMs = std::min(b.backwardCpuMs, f.backwardCpuMs);
  b.recordingForwardMs = std::min(b.recordingForwardMs, f.recordingForwardMs);
  b.recordingBackwardMs = std::min(b.recordingBackwardMs, f.recordingBackwardMs);
  b.recordingForwardCpuMs = std::min(b.recordingForwardCpuMs, f.recordingForwardCpuMs);
  b.recordingBackwardCpuMs = std::min(b.recordingBackwardCpuMs, f.recordingBackwardCpuMs);
}

// The probe's figures, each the best seen: the highest rate, the lowest time.
void keepProbeBest(std::map<std::string, double>& best, const std::map<std::string, double>& got) {
  for (auto& kv : got) {
    bool time = kv.first.size() > 3 && kv.first.compare(kv.first.size() - 3, 3, "_ms") == 0;
    if (!best.count(kv.first)) best[kv.first] = kv.second;
    best[kv.first] = time ? std::min(best[kv.first], kv.second) : std::max(best[kv.first], kv.second);
  }
}

struct TracerBenchSettings {
  int runs = 3;
  uint32_t shDegree = 3, recordsPerRay = 0;
  double nrays = 0;
  std::string probe;  // the rqprobe binary, or empty
};

// The two proxies' table rows; marks whether the faster one (training's CPU time) meets the goals.
void reportVariants(const VariantFigures best[2], double probeRate, double probeCpuRate, double nrays, nlohmann::json& scene, bool& allMeet) {
  std::printf("%-20s %8s %8s %9s %9s %9s %9s %9s %9s %9s %8s %8s %8s %8s\n", "proxy", "build ms", "refit ms", "fwd Mr/s", "vs probe",
              "fwd Mr/cs", "vs probe", "rec fwd", "train b/f", "retrace", "recorded", "hits/ray", "rounds", "B/Gauss");
  auto trainCpu = [](const VariantFigures& f) { return f.recordingForwardCpuMs + f.recordingBackwardCpuMs; };
  int winner = trainCpu(best[0]) <= trainCpu(best[1]) ? 0 : 1;
  for (int v = 0; v < 2; v++) {
    const VariantFigures& f = best[v];
    double fwd = nrays / (f.forwardMs * 1e3), bwd = nrays / (f.backwardMs * 1e3), retraceRatio = f.backwardMs / f.forwardMs;
    double ratio = f.recordingBackwardMs / f.recordingForwardMs;  // training's backward over training's forward
    double fwdCpu = nrays / (f.forwardCpuMs * 1e3);
    char vs[32] = "-", vsCpu[32] = "-";
    if (probeRate > 0) std::snprintf(vs, sizeof vs, "%.2fx", fwd / probeRate);
    if (probeCpuRate > 0) std::snprintf(vsCpu, sizeof vsCpu, "%.2fx", fwdCpu / probeCpuRate);
    std::printf("%-20s %8.1f %8.1f %9.3f %9s %9.3f %9s %8.2fx %9.2f %9.2f %7.1f%% %8.1f %8.2f %8.0f\n", proxyKindName(ProxyKind(v)), f.buildMs,
                f.refitMs, fwd, vs, fwdCpu, vsCpu, f.recordingForwardMs / f.forwardMs, ratio, retraceRatio, 100.0 * f.recordedRays,
                f.meanHits, f.meanRounds, f.bytesPerGaussian);
    nlohmann::json row = {{"proxy", proxyKindName(ProxyKind(v))},
                          {"build_ms", f.buildMs},
                          {"refit_ms", f.refitMs},
                          {"forward_mrays", fwd},
                          {"backward_mrays", bwd},
                          {"backward_over_forward", ratio},
                          {"backward_over_forward_cpu", f.recordingBackwardCpuMs / f.recordingForwardCpuMs},
                          {"recording_forward_over_forward", f.recordingForwardMs / f.forwardMs},
                          {"recorded_rays", f.recordedRays},
                          {"retrace_backward_over_forward", retraceRatio},
                          {"retrace_backward_over_forward_cpu", f.backwardCpuMs / f.forwardCpuMs},
                          {"forward_mrays_per_cpu_second", fwdCpu},
                          {"hits_per_ray", f.meanHits},
                          {"rounds_per_ray", f.meanRounds},
                          {"bytes_per_gaussian", f.bytesPerGaussian}};
    if (probeRate > 0) row["forward_over_probe_kbuffer"] = fwd / probeRate;
    if (probeCpuRate > 0) row["forward_over_probe_kbuffer_cpu"] = fwdCpu / probeCpuRate;
    scene["variants"].push_back(row);
    if (v == winner) allMeet &= (probeRate <= 0 || fwd >= probeRate) && ratio <= 1.5;
  }
  std::printf("(fwd: a render forward; Mr/cs: Mrays per CPU-second of the whole process, steadier than wall time on a shared machine;\n"
              " rec fwd: the recording forward's time over fwd's; train b/f: training's pair, the backward reading the records over\n"
              " the recording forward; retrace: a backward re-tracing every ray over fwd; recorded: rays whose hits all fit)\n");
  std::printf("faster proxy (training forward + backward CPU time): %s\n", proxyKindName(ProxyKind(winner)));
  scene["winner"] = proxyKindName(ProxyKind(winner));
}

void printProbe(const std::map<std::string, double>& probeBest, int n, const std::string& key, const std::string& keyCommit, double probeCpuRate,
                nlohmann::json& scene) {
  auto get = [&](const std::string& k) { return probeBest.count(k) ? probeBest.at(k) : 0.0; };
  std::printf("probe k-buffer (its aabb scene, 400x400): %.3f Mrays/s without commit, %.3f with tmax shrink; best %.3f Mrays/CPU-s\n",
              get(key), get(keyCommit), probeCpuRate);
  std::string wf = "water" + std::to_string(n) + "_fwd_ms", wb = "water" + std::to_string(n) + "_bwd_ms";
  if (probeBest.count(wf) && probeBest.count(wb))
    std::printf("probe water pass (surface + refraction + k-buffer, 392x392): forward %.1f ms (%.3f Mrays/s), backward-like %.1f ms "
                "(14 fake atomics per hit)\n",
                get(wf), 392.0 * 392.0 / (get(wf) * 1e3), get(wb));
  for (auto& kv : probeBest) scene["probe"][kv.first] = kv.second;
}

// One scene of n Gaussians: both proxies (and the probe), alternated; its report entry.
nlohmann::json benchTracerScene(Context& ctx, GaussianTracer& tracer, int n, const std::vector<GpuRay>& rays, const TracerBenchSettings& s,
                                bool& allMeet) {
  GaussianSet set = probeScene(n);
  DeviceGaussians dev = uploadGaussians(ctx, set);
  std::printf("== %d Gaussians (the probe's scene)\n", n);
  // Engine and probe alternate twice; each side keeps its best median, so a burst of
  // load from elsewhere does not land on one side only.
  const int rounds = s.probe.empty() ? 1 : 2;
  VariantFigures best[2];
  std::map<std::string, double> probeBest;
  for (int r = 0; r < rounds; r++) {
    for (ProxyKind kind : {ProxyKind::AabbBlas, ProxyKind::InstancedUnitBox}) {
      VariantFigures f = measureVariant(ctx, tracer, set, dev, kind, rays, s.runs, s.shDegree, s.recordsPerRay);
      if (r == 0) best[uint32_t(kind)] = f;
      keepBest(best[uint32_t(kind)], f);
    }
    if (!s.probe.empty()) {
      keepProbeBest(probeBest, bench::runProbe(s.probe, "aabb " + std::to_string(n)));
      keepProbeBest(probeBest, bench::runProbe(s.probe, "water " + std::to_string(n)));
    }
  }
  std::string key = "aabb" + std::to_string(n) + "s_kbuf_PREFER_FAST_TRACE_Mrays";
  std::string keyCommit = "aabb" + std::to_string(n) + "s_kbuf_commit_PREFER_FAST_TRACE_Mrays";
  double probeRate = std::max(probeBest.count(key) ? probeBest[key] : 0.0, probeBest.count(keyCommit) ? probeBest[keyCommit] : 0.0);
  nlohmann::json scene = {{"gaussians", n}};
  // the probe's k-buffer per CPU-second (400x400 rays), the better of with/without tmax shrink
  double probeCpuRate = 0;
  for (const char* k : {"kbuf_cpu_ms", "kbuf_commit_cpu_ms"})
    if (probeBest.count(k)) probeCpuRate = std::max(probeCpuRate, 400.0 * 400.0 / (probeBest[k] * 1e3));
  reportVariants(best, probeRate, probeCpuRate, s.nrays, scene, allMeet);
  if (!s.probe.empty()) printProbe(probeBest, n, key, keyCommit, probeCpuRate, scene);
  std::printf("\n");
  return scene;
}

int runBenchTracer(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  TracerBenchSettings s;
  s.runs = int(args.getInt("runs", 3));
  const uint32_t size = uint32_t(args.getInt("size", 392));
  const uint32_t K = uint32_t(args.getInt("k", kDefaultKBuffer));
  s.recordsPerRay = uint32_t(args.getIntIn("hit-records", kDefaultHitRecordsPerRay, 1, 1024));
  const long shDegreeArg = args.getInt("sh-degree", 3);
  if (shDegreeArg < 0 || shDegreeArg > 3) fail("--sh-degree must be 0..3");
  s.shDegree = uint32_t(shDegreeArg);
  std::vector<int> counts = parseCounts(args.get("counts", "10000,100000"));
  s.probe = args.get("probe");
  s.nrays = double(size) * size;
  std::printf("device: %s (%s)\n%u x %u camera rays, K = %u, SH degree %u, %u hit records per ray (%u bytes), median of %d runs after 1 warm-up\n",
              ctx->caps.name.c_str(), ctx->caps.driver.c_str(), size, size, K, s.shDegree, s.recordsPerRay, 8 * s.recordsPerRay, s.runs);
  std::printf("backward atomics: %s\n\n", ctx->caps.floatAtomicAdd ? "float atomicAdd" : "compare-and-swap loop");
  nlohmann::json report = {{"device", ctx->caps.name}, {"driver", ctx->caps.driver}, {"rays", s.nrays},        {"k", K},
                           {"sh_degree", s.shDegree}, {"runs", s.runs},                {"hit_records", s.recordsPerRay}};

  FlyCamera cam;  // the probe's aabb camera
  lookAt(cam, {0.f, -2.0f, 1.2f}, {0.f, 0.f, -0.5f});
  cam.tanHalfFovY = 0.36f;
  std::vector<GpuRay> rays;
  {
    CameraRayPipelines cameraPipelines = createCameraRayPipelines(*ctx);
    Buffer rayBuf = createBuffer(*ctx, VkDeviceSize(size) * size * sizeof(GpuRay));
    submitAndWait(*ctx, [&](VkCommandBuffer cb) { cmdCameraRays(cb, cameraPipelines, cameraFromFly(cam, int(size), int(size)), rayBuf, 0.0f, 100.0f); });
    rays = downloadVector<GpuRay>(*ctx, rayBuf, size_t(size) * size);
  }
  GaussianTracer tracer = createGaussianTracer(*ctx, K);
  bool allMeet = true;
  for (int n : counts) report["scenes"].push_back(benchTracerScene(*ctx, tracer, n, rays, s, allMeet));
  std::printf("goals (forward >= 1.0x the probe's k-buffer, training backward <= 1.5x training forward time) for the faster proxy: %s\n",
              allMeet ? "met" : "not met");
  report["goals_met"] = allMeet;
  if (args.has("out")) writeJson(args.get("out"), report);
  return 0;
}

REFRAX_BENCH_SUITE({"tracer",
                    "Gaussian ray tracer forward/backward Mrays/s at 10k/100k Gaussians, both proxies, beside the rqprobe k-buffer",
                    {{"probe", "PATH", "rqprobe binary to run on the same scenes in the same run (bench/tracer.sh builds it)", ""},
                     {"runs", "N", "timed runs per measurement (median)", "3"},
                     {"size", "PIXELS", "image side in rays", "392"},
                     {"k", "K", "k-buffer size", std::to_string(kDefaultKBuffer)},
                     {"hit-records", "N", "hit records per ray of training's forward/backward pair", std::to_string(kDefaultHitRecordsPerRay)},
                     {"sh-degree", "D", "SH degree evaluated (the probe evaluates no colour)", "3"},
                     {"counts", "N,N", "Gaussian counts", "10000,100000"},
                     {"out", "FILE", "write the figures as JSON", ""}},
                    runBenchTracer});

}  // namespace
}  // namespace refrax
