// refrax bench surface: the water-surface stage (grid evaluation, refit, global trace, each
// subdivision level, normals, refraction, backward) for a camera looking down on the domain,
// per MLP width and per coarse grid (K raised to keep the finest spacing), beside the raw
// triangle ray-query rate of the same device on the same camera rays and the plain grid
// BLAS, measured in the same run. Also the intersection error |p.z - H(p.xy)| of each
// configuration (H evaluated by the same MLP), written with the times as a CSV.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/base/error.h"
#include "engine/surface/height_field_source.h"
#include "engine/trace/ray_trace.h"
#include "engine/vk/vk_commands.h"
#include "engine/vk/vk_context.h"
#include "engine/vk/vk_timer.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

std::vector<uint32_t> parseList(const std::string& s) {
  std::vector<uint32_t> v;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) v.push_back(uint32_t(std::stoul(item)));
  if (v.empty()) fail("empty list '" + s + "'");
  return v;
}

// A pinhole camera at height 2.5 above the centre of [-1, 1]^2, looking straight down,
// with a field of view that just covers the domain.
std::vector<GpuRay> cameraRays(uint32_t size) {
  std::vector<GpuRay> rays(size_t(size) * size);
  const float h = 2.5f, tanHalf = 1.02f / h;
  for (uint32_t y = 0; y < size; y++)
    for (uint32_t x = 0; x < size; x++) {
      float u = ((x + 0.5f) / size * 2 - 1) * tanHalf, v = ((y + 0.5f) / size * 2 - 1) * tanHalf;
      float len = std::sqrt(u * u + v * v + 1);
      GpuRay& r = rays[size_t(y) * size + x];
      r = {{0, 0, h}, 0, {u / len, v / len, -1 / len}, 100};
    }
  return rays;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

struct Row {
  uint32_t width, cells, levels;
  double spacing;
  std::map<std::string, double> stageMs;  // medians
  double updateMs = 0, traceMs = 0, backwardMs = 0, traceWallMs = 0;
  uint32_t points = 0, missed = 0, fallback = 0;
  double errMedian = 0, errP99 = 0, errMax = 0;
};

// What every setting's runs share: the camera rays, their outputs and made-up ray gradients.
struct SurfaceBenchRays {
  uint32_t count = 0;
  Buffer rays, refracted, records, grads;
  RayTracePipelines rt;
  bool rawTrace = false;  // the raw triangle ray-query rate (not on the compute backend: no triangle BLAS)
};

// The stage times of one surface, median over `runs` after a warm-up, into row.stageMs.
void timeSurfaceStages(Context& ctx, WaterSurface& ws, const HeightField& hf, const Buffer& dW, SurfaceBenchRays& b, int runs, Row& row) {
  GpuTimer timer;
  createTimer(ctx, timer, 16);
  std::map<std::string, std::vector<double>> samples;
  std::vector<double> wall;
  for (int run = 0; run < std::max(runs, 0) + 1; run++) {
    submitAndWait(ctx, [&](VkCommandBuffer cb) {
      cmdTimerStart(cb, timer);
      HeightSource hs = heightSource(hf);
      hs.evaluate(cb, ws.gridPoints, ws.gridPointCount, ws.gridHeights);
      cmdBarrier(cb);
      cmdTimerStamp(cb, timer, "update: grid heights");
      // the whole update as training runs it (grid heights again, vertices, refit), timed as one:
      // the vertices and refit alone as a difference of the two stamps came out negative on a GPU,
      // where each is a fraction of a millisecond and the second grid evaluation runs warm
      cmdUpdateSurface(cb, ws, hs);
      cmdTimerStamp(cb, timer, "update: whole");
    });
    auto upd = readTimer(timer);
    SurfaceTimings t;
    auto t0 = std::chrono::steady_clock::now();
    traceSurface(ctx, ws, hf, b.rays, b.count, b.refracted, b.records, &t);
    double w = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    submitAndWait(ctx, [&](VkCommandBuffer cb) {
      cmdTimerStart(cb, timer);
      cmdBackwardSurface(cb, ws, heightSource(hf), b.rays, b.records, b.grads, b.count);  // to dL/dz only
      cmdTimerStamp(cb, timer, "backward dz");
      cmdBackwardSurface(cb, ws, hf, b.rays, b.records, b.grads, b.count, dW);
      cmdTimerStamp(cb, timer, "backward dz + MLP");
    });
    auto bwd = readTimer(timer);
    // raw ray-query rate on the same rays against the plain grid BLAS; the compute backend walks
    // the grid instead and has no triangle acceleration structure to compare with
    std::vector<std::pair<std::string, double>> raw;
    if (b.rawTrace) {
      submitAndWait(ctx, [&](VkCommandBuffer cb) {
        cmdTimerStart(cb, timer);
        cmdDispatch(cb, b.rt.closestTriangle, {bind(ws.top.tlas), bind(b.rays), bind(b.refracted)}, &b.count, groupsFor(b.count, 64));
        cmdTimerStamp(cb, timer, "raw");
      });
      raw = readTimer(timer);
    }
    if (run == 0 && runs > 0) continue;  // warm-up (with --runs 0 the single run is kept)
    samples["update: grid heights alone"].push_back(upd[0].second);
    samples["update: whole (heights, refit)"].push_back(upd[1].second);
    for (auto& [k, v] : t) samples["trace: " + k].push_back(v);
    samples["backward: to dL/dz"].push_back(bwd[0].second);
    samples["backward: to dL/dz + MLP weights"].push_back(bwd[1].second);
    if (b.rawTrace) samples["raw"].push_back(raw[0].second);
    wall.push_back(w);
  }
  for (auto& [k, v] : samples) row.stageMs[k] = median(v);
  row.updateMs = row.stageMs["update: whole (heights, refit)"];
  for (auto& [k, v] : row.stageMs)
    if (k.rfind("trace: ", 0) == 0) row.traceMs += v;
  row.backwardMs = row.stageMs["backward: to dL/dz + MLP weights"];
  row.traceWallMs = median(wall);
}

// Intersection error |p.z - H(p.xy)| at the hit points of one more trace, and its counters.
void measureHitErrors(Context& ctx, WaterSurface& ws, const HeightField& hf, SurfaceBenchRays& b, Row& row) {
  traceSurface(ctx, ws, hf, b.rays, b.count, b.refracted, b.records);
  row.points = ws.lastCounters.points;
  row.missed = ws.lastCounters.missed;
  row.fallback = ws.lastCounters.fallback;
  auto out = downloadVector<GpuRay>(ctx, b.refracted, b.count);
  auto rec = downloadVector<SurfaceRecord>(ctx, b.records, b.count);
  std::vector<float> xy;
  std::vector<float> z;
  for (uint32_t i = 0; i < b.count; i++)
    if (surfaceRecordFlags(rec[i]) & kSurfaceHit) {
      xy.push_back(out[i].origin[0]);
      xy.push_back(out[i].origin[1]);
      z.push_back(out[i].origin[2]);
    }
  Buffer pts = createBufferFrom(ctx, xy), hts = createBuffer(ctx, std::max<size_t>(z.size(), 1) * 4);
  submitAndWait(ctx, [&](VkCommandBuffer cb) { cmdEvaluateHeights(cb, hf, pts, uint32_t(z.size()), hts); });
  auto H = downloadVector<float>(ctx, hts, z.size());
  std::vector<double> err(z.size());
  for (size_t i = 0; i < z.size(); i++) err[i] = std::abs(double(z[i]) - double(H[i]));
  std::sort(err.begin(), err.end());
  if (!err.empty()) {
    row.errMedian = err[err.size() / 2];
    row.errP99 = err[size_t(0.99 * double(err.size() - 1))];
    row.errMax = err.back();
  }
}

void printSurfaceRow(const Row& row, const SurfaceBenchRays& b) {
  double stage = row.updateMs + row.traceMs;
  char versusRaw[96] = "no ray queries: no raw rate";
  if (b.rawTrace) {
    double rawMs = row.stageMs.at("raw");
    std::snprintf(versusRaw, sizeof versusRaw, "vs raw %.2f Mrays/s = %.2fx", b.count / rawMs / 1e3, rawMs / stage);
  }
  std::printf("  grid %u K %u (finest %.5f): update %.1f ms, trace %.1f ms (wall %.1f), backward %.1f ms, %u points, %u missed, "
              "%u fallback | stage %.2f Mrays/s %s | |z-H| median %.2e p99 %.2e max %.2e\n",
              row.cells, row.levels, row.spacing, row.updateMs, row.traceMs, row.traceWallMs, row.backwardMs, row.points, row.missed,
              row.fallback, b.count / stage / 1e3, versusRaw, row.errMedian, row.errP99, row.errMax);
  for (auto& [k, v] : row.stageMs) std::printf("      %-36s %8.2f ms\n", k.c_str(), v);
}

void writeSurfaceCsv(const std::string& csvPath, const std::string& deviceName, uint32_t count, uint32_t hidden, const std::vector<Row>& rows) {
  std::filesystem::path p(csvPath);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  std::ofstream csv(csvPath);
  if (!csv) fail("cannot write " + csvPath);
  csv << "device,rays,mlp_width,hidden_layers,grid_cells,levels,finest_spacing,update_ms,trace_gpu_ms,trace_wall_ms,backward_ms,"
         "stage_mrays_per_s,raw_mrays_per_s,stage_over_raw,points,missed,fallback,err_median,err_p99,err_max\n";
  for (auto& r : rows) {
    double stage = r.updateMs + r.traceMs;
    csv << '"' << deviceName << '"' << ',' << count << ',' << r.width << ',' << hidden << ',' << r.cells << ',' << r.levels << ','
        << r.spacing << ',' << r.updateMs << ',' << r.traceMs << ',' << r.traceWallMs << ',' << r.backwardMs << ',' << count / stage / 1e3
        << ',';
    if (r.stageMs.count("raw")) csv << count / r.stageMs.at("raw") / 1e3 << ',' << r.stageMs.at("raw") / stage;
    else csv << ',';  // no ray queries: the raw rate's two columns stay empty
    csv << ',' << r.points << ',' << r.missed << ',' << r.fallback << ',' << r.errMedian << ',' << r.errP99 << ',' << r.errMax << '\n';
  }
  std::printf("wrote %s\n", csvPath.c_str());
}

int runBenchSurface(const cli::Args& args) {
  auto ctx = cli::openContext(args);
  const uint32_t size = uint32_t(args.getInt("rays", 392));
  const auto widths = parseList(args.get("widths", "256,64,32"));
  const auto grids = parseList(args.get("grids", "200,100,50"));
  const uint32_t finest = uint32_t(args.getInt("finest", 800));  // finest cells per side
  const uint32_t hidden = uint32_t(args.getInt("hidden", 6));
  const int runs = int(args.getInt("runs", 3));
  const uint32_t octaves = uint32_t(args.getInt("octaves", 6));
  const float initRange = float(args.getDouble("init-range", 0.1));
  std::string device = ctx->caps.name;
  for (char& c : device)
    if (!std::isalnum(uint8_t(c))) c = '_';
  std::string csvPath = args.get("csv", "bench/results/surface_" + device + ".csv");

  SurfaceBenchRays b;
  std::vector<GpuRay> rays = cameraRays(size);
  b.count = uint32_t(rays.size());
  b.rays = createBufferFrom(*ctx, rays);
  b.refracted = createBuffer(*ctx, b.count * sizeof(GpuRay));
  b.records = createBuffer(*ctx, b.count * sizeof(SurfaceRecord));
  std::vector<GpuRayGrad> gradsHost(b.count);
  for (size_t i = 0; i < b.count; i++) gradsHost[i] = {{0.1f, -0.2f, 0.3f}, 0, {0.2f, 0.1f, -0.1f}, 0};
  b.grads = createBufferFrom(*ctx, gradsHost);
  b.rt = createRayTracePipelines(*ctx);
  b.rawTrace = ctx->trace != TraceBackend::Compute;
  std::printf("device: %s; %u x %u camera rays; MLP %u hidden layers, %u octaves, init range %g; finest lattice %u cells per side\n",
              ctx->caps.name.c_str(), size, size, hidden, octaves, initRange, finest);

  std::vector<Row> rows;
  for (uint32_t width : widths) {
    HeightFieldConfig hc;
    hc.width = width;
    hc.hiddenLayers = hidden;
    hc.octaves = octaves;
    hc.lastLayerInitRange = initRange;  // an untrained surface: its roughness is set by octaves and this range
    HeightField hf = createHeightField(*ctx, hc, 7);
    double jit = warmUpHeightField(hf);
    std::printf("MLP width %u: %llu weights, kernel %s, pipeline creation %.0f ms\n", width, (unsigned long long)hf.parameterCount,
                hf.forwardKernelName().c_str(), jit);
    Buffer dW = createBuffer(*ctx, hf.parameterCount * 4);
    for (uint32_t cells : grids) {
      uint32_t levels = 0;
      while ((cells << levels) < finest) levels++;
      WaterSurfaceConfig cfg;
      cfg.gridCells = cells;
      cfg.subdivisionLevels = levels;
      cfg.maxRays = b.count;
      auto c0 = std::chrono::steady_clock::now();
      WaterSurface ws = createWaterSurface(*ctx, cfg);
      std::printf("  surface created in %.0f ms (pipelines included)\n",
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - c0).count());
      Row row{width, cells, levels, 2.0 / double(cells << levels)};
      timeSurfaceStages(*ctx, ws, hf, dW, b, runs, row);
      measureHitErrors(*ctx, ws, hf, b, row);
      printSurfaceRow(row, b);
      rows.push_back(row);
    }
  }
  writeSurfaceCsv(csvPath, ctx->caps.name, b.count, hidden, rows);
  return 0;
}

REFRAX_BENCH_SUITE({"surface",
                    "water surface stage per MLP width and grid, beside the raw triangle ray-query rate",
                    {{"rays", "N", "camera image side (N x N rays)", "392"},
                     {"widths", "LIST", "MLP widths", "256,64,32"},
                     {"hidden", "N", "MLP hidden layers", "6"},
                     {"grids", "LIST", "coarse grid cells per side", "200,100,50"},
                     {"finest", "N", "finest lattice cells per side (K raised per grid to reach it)", "800"},
                     {"runs", "N", "timed runs per configuration after one warm-up (median); 0: one unwarmed run", "3"},
                     {"octaves", "N", "MLP encoding octaves", "6"},
                     {"init-range", "X", "MLP last-layer init range (surface amplitude)", "0.1"},
                     {"csv", "PATH", "CSV output", "bench/results/surface_<device>.csv"}},
                    runBenchSurface});

}  // namespace
}  // namespace refrax
