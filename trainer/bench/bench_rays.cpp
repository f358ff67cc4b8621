// refrax bench rays: ray-query throughput of the engine on the rqprobe's own scenes (a
// 201x201 sine-wave grid surface; 10k and 100k random Gaussian boxes), 400x400 rays, beside
// the probe itself run in the same process tree, so the ratio is measured in one run.
#include <cmath>
#include <functional>
#include <glm/glm.hpp>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "engine/base/error.h"
#include "engine/surface/grid_mesh.h"
#include "engine/io/json_io.h"
#include "engine/trace/presort.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_pipeline.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

struct Camera {  // mirrors PinholeCamera + size in shaders/include/camera.glsl
  float position[4], forward[4], right[4], up[4];
  uint32_t size[4];
};

Camera lookAt(glm::vec3 pos, glm::vec3 target, float tanHalf, uint32_t w, uint32_t h) {
  glm::vec3 f = glm::normalize(target - pos), r = glm::normalize(glm::cross(f, glm::vec3(0, 0, 1))), u = glm::cross(r, f);
  r *= tanHalf;
  u *= tanHalf;
  Camera c{};
  for (int a = 0; a < 3; a++) {
    c.position[a] = pos[a];
    c.forward[a] = f[a];
    c.right[a] = r[a];
    c.up[a] = u[a];
  }
  c.size[0] = w;
  c.size[1] = h;
  return c;
}

// The probe's Gaussians (rqprobe.cpp makeGaussians, seed 1234): same draws in the same order.
struct BenchGaussian {
  float meanDensity[4], p0[4], p1[4];
};
void probeGaussians(int n, std::vector<BenchGaussian>& gs, std::vector<Box>& boxes) {
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> U(0.f, 1.f);
  gs.resize(n);
  boxes.resize(n);
  for (int i = 0; i < n; i++) {
    float mx = U(rng) - 0.5f, my = U(rng) - 0.5f, mz = -U(rng);
    float s[3];
    for (int k = 0; k < 3; k++) s[k] = (0.01f + 0.02f * U(rng)) / 6.f;
    float q0 = U(rng) * 2 - 1, q1 = U(rng) * 2 - 1, q2 = U(rng) * 2 - 1, q3 = U(rng) * 2 - 1;
    float qn = std::sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3);
    q0 /= qn, q1 /= qn, q2 /= qn, q3 /= qn;
    float R[3][3] = {{1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)},
                     {2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)},
                     {2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)}};
    double A[3][3], C[3][3];
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) {
        A[a][b] = C[a][b] = 0;
        for (int k = 0; k < 3; k++) {
          A[a][b] += R[a][k] * R[b][k] / (s[k] * s[k]);
          C[a][b] += R[a][k] * R[b][k] * s[k] * s[k];
        }
      }
    BenchGaussian& g = gs[i];
    g.meanDensity[0] = mx, g.meanDensity[1] = my, g.meanDensity[2] = mz, g.meanDensity[3] = 0.05f + 0.9f * U(rng);
    g.p0[0] = float(A[0][0]), g.p0[1] = float(A[0][1]), g.p0[2] = float(A[0][2]), g.p0[3] = float(A[1][1]);
    g.p1[0] = float(A[1][2]), g.p1[1] = float(A[2][2]), g.p1[2] = g.p1[3] = 0;
    float e[3] = {3 * float(std::sqrt(C[0][0])), 3 * float(std::sqrt(C[1][1])), 3 * float(std::sqrt(C[2][2]))};
    boxes[i] = {mx - e[0], my - e[1], mz - e[2], mx + e[0], my + e[1], mz + e[2]};
  }
}

double traceMs(Context& ctx, int runs, const std::function<void(VkCommandBuffer)>& record) {
  return bench::medianMs(1, runs, [&] { submitAndWait(ctx, record); });
}

// The surface: 200x200 cells, the probe's sine wave, Morton-ordered cells. Traced: built for
// tracing only, as the probe builds it. Refit: a twin allowing updates, timed separately (an
// updatable BVH may trace slower).
struct SurfaceScene {
  Buffer vertices, indices;
  AccelStruct blas, traceBlas;
  TopLevel top, traceTop;
  double buildMs = 0, refitMs = 0;
};
SurfaceScene buildSurfaceScene(Context& ctx, int runs, bool traceUpdatable) {
  SurfaceScene s;
  GridMesh mesh = makeGridMesh(200, 200, -1, -1, 1, 1, [](float x, float y) {
    return 0.04f * std::sin(7.f * x + 1.f) * std::cos(5.f * y) + 0.015f * std::sin(13.f * x + 9.f * y);
  });
  s.vertices = createBufferFrom(ctx, mesh.vertices, kAccelInput);
  s.indices = createBufferFrom(ctx, mesh.indices, kAccelInput);
  s.blas = createTriangleBlas(ctx, s.vertices, mesh.vertexCount(), 12, s.indices, mesh.triangleCount(), {true});
  s.top = createTopLevel(ctx, {makeInstance(s.blas, 0, nullptr, VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR)}, {true});
  s.traceBlas = createTriangleBlas(ctx, s.vertices, mesh.vertexCount(), 12, s.indices, mesh.triangleCount(), {traceUpdatable});
  s.traceTop =
      createTopLevel(ctx, {makeInstance(s.traceBlas, 0, nullptr, VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR)}, {traceUpdatable});
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBuild(cb, s.traceBlas);
    cmdBarrier(cb);
    cmdBuild(cb, s.traceTop.tlas);
  });
  s.buildMs = traceMs(ctx, runs, [&](VkCommandBuffer cb) {
    cmdBuild(cb, s.blas);
    cmdBarrier(cb);
    cmdBuild(cb, s.top.tlas);
  });
  s.refitMs = traceMs(ctx, runs, [&](VkCommandBuffer cb) {
    cmdRefit(cb, s.blas);
    cmdBarrier(cb);
    cmdRefit(cb, s.top.tlas);
  });
  return s;
}

// Boxes: the probe's Gaussians, median-split order, visiting every candidate.
struct BoxScene {
  int n;
  Buffer gaussians, boxes;
  AccelStruct blas;
  TopLevel top;
};
BoxScene buildBoxScene(Context& ctx, int n) {
  std::vector<BenchGaussian> gs;
  std::vector<Box> boxes;
  probeGaussians(n, gs, boxes);
  auto order = medianSplitOrder(boxes);
  BoxScene s{n};
  s.gaussians = createBufferFrom(ctx, permuted(gs, order));
  s.boxes = createBufferFrom(ctx, permuted(boxes, order), kAccelInput);
  s.blas = createAabbBlas(ctx, s.boxes, uint32_t(n));
  s.top = createTopLevel(ctx, {makeInstance(s.blas, 0, nullptr, VK_GEOMETRY_INSTANCE_FORCE_NO_OPAQUE_BIT_KHR)});
  submitAndWait(ctx, [&](VkCommandBuffer cb) {
    cmdBuild(cb, s.blas);
    cmdBarrier(cb);
    cmdBuild(cb, s.top.tlas);
  });
  return s;
}

struct RaysRow {
  std::string name, probeKey;
  double mrays;
};
// The table beside the probe's rates; true when every scene is at >= 0.9x the probe's.
bool reportRays(const std::vector<RaysRow>& rows, const std::map<std::string, double>& probeBest, nlohmann::json& report) {
  std::printf("%-48s %12s %12s %8s\n", "scene", "refrax Mr/s", "probe Mr/s", "ratio");
  bool meets = true;
  for (auto& r : rows) {
    nlohmann::json row = {{"scene", r.name}, {"refrax_mrays", r.mrays}};
    if (probeBest.count(r.probeKey)) {
      double p = probeBest.at(r.probeKey), ratio = r.mrays / p;
      meets &= ratio >= 0.9;
      std::printf("%-48s %12.3f %12.3f %7.2fx\n", r.name.c_str(), r.mrays, p, ratio);
      row["probe_mrays"] = p;
      row["ratio"] = ratio;
    } else {
      std::printf("%-48s %12.3f %12s %8s\n", r.name.c_str(), r.mrays, "-", "-");
    }
    report["scenes"].push_back(row);
  }
  return meets;
}

int runBenchRays(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  const int runs = int(args.getInt("runs", 5));
  const uint32_t size = uint32_t(args.getInt("size", 400));
  const double rays = double(size) * size;
  std::string probe = args.get("probe");
  nlohmann::json report = {{"device", ctx->caps.name}, {"driver", ctx->caps.driver}, {"rays", rays}, {"runs", runs}};
  std::printf("device: %s (%s)\n%u x %u rays, median of %d runs after 1 warm-up\n\n", ctx->caps.name.c_str(), ctx->caps.driver.c_str(),
              size, size, runs);

  SurfaceScene surface = buildSurfaceScene(*ctx, runs, args.has("trace-updatable"));
  ComputePipeline triPipe = createComputePipeline(*ctx, "bench_camera_triangles", {kAccelStruct, kStorageBuffer}, sizeof(Camera));
  Buffer out = createBuffer(*ctx, size_t(rays) * 16);
  Camera triCam = lookAt({0.f, -1.5f, 1.1f}, {0.f, 0.f, -0.3f}, 0.30f, size, size);
  auto traceSurface = [&] {
    return traceMs(*ctx, runs, [&](VkCommandBuffer cb) {
      cmdDispatch(cb, triPipe, {bind(surface.traceTop.tlas), bind(out)}, &triCam, groupsFor(size, 8), groupsFor(size, 8));
    });
  };
  std::vector<BoxScene> boxScenes;
  for (int n : {10000, 100000}) boxScenes.push_back(buildBoxScene(*ctx, n));
  struct BoxPush {
    Camera cam;
    float thresholds[4];
  } boxPush{lookAt({0.f, -2.0f, 1.2f}, {0.f, 0.f, -0.5f}, 0.36f, size, size), {1.f / 255.f, 1e-3f, 0, 0}};
  ComputePipeline boxPipe =
      createComputePipeline(*ctx, "bench_camera_boxes", {kAccelStruct, kStorageBuffer, kStorageBuffer}, sizeof(BoxPush));
  auto traceBoxes = [&](BoxScene& s) {
    return traceMs(*ctx, runs, [&](VkCommandBuffer cb) {
      cmdDispatch(cb, boxPipe, {bind(s.top.tlas), bind(out), bind(s.gaussians)}, &boxPush, groupsFor(size, 8), groupsFor(size, 8));
    });
  };

  // Alternate engine and probe (--rounds times) and keep each side's best median, so a burst
  // of load from elsewhere on a shared machine does not land on one side only.
  const int rounds = probe.empty() ? 1 : int(args.getInt("rounds", 4));
  if (rounds < 1) fail("--rounds must be at least 1");
  double surfaceMs = 1e30, boxMs[2] = {1e30, 1e30};
  std::map<std::string, double> probeBest;
  for (int r = 0; r < rounds; r++) {
    surfaceMs = std::min(surfaceMs, traceSurface());
    for (int i = 0; i < 2; i++) boxMs[i] = std::min(boxMs[i], traceBoxes(boxScenes[i]));
    if (!probe.empty()) {
      if (size != 400) fail("--probe compares at the probe's 400x400 only");
      for (auto& kv : bench::runProbe(probe, "tri")) probeBest[kv.first] = std::max(probeBest[kv.first], kv.second);
      for (auto& kv : bench::runProbe(probe, "aabb 10000 100000")) probeBest[kv.first] = std::max(probeBest[kv.first], kv.second);
    }
  }

  std::vector<RaysRow> rows = {{"surface 201x201 grid (80k tris), closest hit", "tri_morton_trace_PREFER_FAST_TRACE_Mrays", rays / (surfaceMs * 1e3)},
                               {"10k Gaussian boxes, all candidates", "aabb10000s_all_PREFER_FAST_TRACE_Mrays", rays / (boxMs[0] * 1e3)},
                               {"100k Gaussian boxes, all candidates", "aabb100000s_all_PREFER_FAST_TRACE_Mrays", rays / (boxMs[1] * 1e3)}};
  bool meets = reportRays(rows, probeBest, report);
  std::printf("\nsurface BLAS+TLAS build %.2f ms, refit %.2f ms (%s)\n", surface.buildMs, surface.refitMs,
              surface.refitMs < surface.buildMs ? "refit is cheaper" : "refit costs as much as a build on this driver");
  report["surface_build_ms"] = surface.buildMs;
  report["surface_refit_ms"] = surface.refitMs;
  if (!probe.empty()) std::printf("%s\n", meets ? "every scene at >= 0.9x the probe's rate" : "some scene below 0.9x the probe's rate");
  if (args.has("out")) writeJson(args.get("out"), report);
  return 0;
}

REFRAX_BENCH_SUITE({"rays",
                    "ray-query throughput: 80k-triangle surface and 10k/100k Gaussian boxes, beside the rqprobe floor",
                    {{"probe", "PATH", "rqprobe binary to run on the same scenes in the same run (bench/rays.sh builds it)", ""},
                     {"runs", "N", "timed runs per measurement (median)", "5"},
                     {"rounds", "N", "with --probe: alternations of refrax and the probe (best median of each side)", "4"},
                     {"size", "PIXELS", "image side in rays", "400"},
                     {"out", "FILE", "write the figures as JSON", ""},
                     {"trace-updatable", "", "trace the surface BVH built with ALLOW_UPDATE (as training refits it)", ""}},
                    runBenchRays});

}  // namespace
}  // namespace refrax
