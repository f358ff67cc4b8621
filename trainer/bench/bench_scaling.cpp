// refrax bench scaling: how the time per training step, the time per rendered frame and the
// peak memory grow with the image size, the Gaussian count and the surface grid size.
// Each setting builds a training session in this process (the refraction model, no
// densification, so the Gaussian count stays what it is set to, the surface already unfrozen
// so every step runs the full surface forward and backward), takes a few warm-up steps, then
// the median wall time of --runs steps on whole training images (no patches: the step covers
// every pixel, so it scales with the image) and of --runs renders of the first test view.
// Peak memory: the process's peak resident set (VmHWM of /proc/self/status), reset before each
// setting through /proc/self/clear_refs; on lavapipe and integrated GPUs the device buffers
// are host memory and are counted in it, on a discrete GPU they are not.
// The datasets come from the caller (bench/scaling.sh makes them with refrax synth --width):
// the image-size sweep runs over all of them, the other two sweeps over the first.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/dataset/dataset.h"
#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/model/render_model.h"
#include "engine/train/train_run.h"
#include "engine/train/train_session.h"
#include "engine/vk/vk_context.h"
#include "trainer/bench/bench.h"

namespace refrax {
namespace {

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) v.push_back(item);
  return v;
}

std::vector<long> parseCounts(const std::string& text, const std::string& option, long lo, long hi) {
  std::vector<long> v;
  for (const auto& item : splitList(text)) {
    char* end = nullptr;
    long n = std::strtol(item.c_str(), &end, 10);
    if (*end || n < lo || n > hi)
      fail("--" + option + " expects comma-separated integers in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text + "'");
    v.push_back(n);
  }
  if (v.empty()) fail("--" + option + " expects at least one value");
  return v;
}

// Peak resident set (MiB) since the last resetPeakMemory(); 0 when /proc is not there.
double peakMemoryMiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::strtod(line.c_str() + 6, nullptr) / 1024.0;  // kB
  return 0;
}
void resetPeakMemory() {
  std::ofstream f("/proc/self/clear_refs");
  f << "5";  // 5: reset the peak RSS to the current RSS (Linux >= 4.0)
}

struct Setting {
  std::string sweep;
  size_t dataset = 0;
  long gaussians = 0, gridCells = 0;
};

struct Timing {
  int width = 0, height = 0;
  size_t gaussians = 0;   // what the session trained, not what was asked for (the CSV's columns)
  uint32_t gridCells = 0;
  double stepMs = 0, renderMs = 0, peakMiB = 0;
};

Timing measure(Context& ctx, const std::string& datasetDir, const Setting& s, const cli::Args& args) {
  resetPeakMemory();
  Dataset dataset = loadDataset(datasetDir);
  TrainConfig c;
  c.dataset = datasetDir;
  c.steps = 15000;
  c.initialGaussians = uint32_t(s.gaussians);
  c.maxGaussians = uint32_t(s.gaussians);
  c.gridCells = uint32_t(s.gridCells);
  c.maxShDegree = uint32_t(args.getInt("sh-degree", 0));
  c.densify = false;
  c.schedule.surfaceFreeze = 0;  // the surface learns from the first step: the full step is timed
  c.progressEvery = c.checkpointEvery = 1000000;
  resolveSceneConfig(c, dataset);
  auto session = createTrainSession(ctx, c, std::move(dataset));
  TrainSession& ts = *session;
  Timing t;
  const Camera& cam = ts.dataset.split("test").front().camera;
  t.width = cam.width;
  t.height = cam.height;
  int warmup = int(args.getInt("warmup", 2)), runs = int(args.getInt("runs", 5));
  t.stepMs = bench::medianMs(warmup, runs, [&] { trainStep(ts); });
  t.renderMs = bench::medianMs(1, runs, [&] { renderView(ts.model, cam, WaterView::Keep); });
  t.peakMiB = peakMemoryMiB();
  t.gaussians = ts.model.gaussians.count();
  t.gridCells = ts.model.surface ? ts.model.surface->config.gridCells : 0;
  return t;
}

int runBenchScaling(const cli::Args& args) {
  if (!args.has("datasets")) fail("refrax bench scaling needs --datasets DIR[,DIR...] (bench/scaling.sh makes them with refrax synth --width)");
  std::vector<std::string> datasets = splitList(args.get("datasets"));
  if (datasets.empty()) fail("--datasets expects comma-separated dataset folders");
  std::vector<long> gaussianCounts = parseCounts(args.get("gaussians", "10000,20000,50000,100000,200000"), "gaussians", 1, 50000000);
  std::vector<long> grids = parseCounts(args.get("grid-cells", "32,64,128,256"), "grid-cells", 1, 4096);
  long baseGaussians = parseCounts(args.get("base-gaussians", "20000"), "base-gaussians", 1, 50000000)[0];
  long baseGrid = parseCounts(args.get("base-grid-cells", "64"), "base-grid-cells", 1, 4096)[0];
  if (args.getInt("runs", 5) < 1 || args.getInt("warmup", 2) < 0) fail("--runs must be >= 1 and --warmup >= 0");
  long sh = args.getInt("sh-degree", 0);
  if (sh < 0 || sh > 3) fail("--sh-degree must be 0..3");
  std::string csvPath = args.get("csv");
  for (const auto& d : datasets) loadDataset(d);  // every dataset readable before the first timing

  auto ctx = cli::openContext(args);
  std::vector<Setting> settings;
  for (size_t i = 0; i < datasets.size(); i++) settings.push_back({"image_size", i, baseGaussians, baseGrid});
  for (long g : gaussianCounts) settings.push_back({"gaussians", 0, g, baseGrid});
  for (long g : grids) settings.push_back({"grid_cells", 0, baseGaussians, g});

  std::string csv = "sweep,width,height,pixels,gaussians,grid_cells,sh_degree,step_ms,render_ms,peak_rss_mib,device\n";
  std::printf("device: %s\n", ctx->caps.name.c_str());
  std::printf("%-10s %9s %9s %6s %10s %10s %10s\n", "sweep", "image", "gaussians", "grid", "step ms", "render ms", "peak MiB");
  // lavapipe compiles each pipeline on its first use: one untimed pass over the first setting
  // keeps that out of the first row (measured: 1.6 s against 0.9 s for the same setting later).
  measure(*ctx, datasets[0], settings[0], args);
  for (const auto& s : settings) {
    Timing t = measure(*ctx, datasets[s.dataset], s, args);
    std::printf("%-10s %4dx%-4d %9zu %6u %10.1f %10.1f %10.0f\n", s.sweep.c_str(), t.width, t.height, t.gaussians, t.gridCells, t.stepMs,
                t.renderMs, t.peakMiB);
    std::fflush(stdout);
    char row[320];
    std::snprintf(row, sizeof row, "%s,%d,%d,%d,%zu,%u,%ld,%.3f,%.3f,%.1f,\"%s\"\n", s.sweep.c_str(), t.width, t.height, t.width * t.height,
                  t.gaussians, t.gridCells, sh, t.stepMs, t.renderMs, t.peakMiB, ctx->caps.name.c_str());
    csv += row;
    if (!csvPath.empty()) writeTextAtomic(csvPath, csv);  // rows so far survive an interrupted run
  }
  return 0;
}

REFRAX_BENCH_SUITE({"scaling",
                    "time per training step and per rendered frame, peak memory, against image size, Gaussian count, grid size",
                    {{"datasets", "DIR,DIR", "datasets, one per image size (the first is used for the other sweeps)", ""},
                     {"gaussians", "N,N", "Gaussian counts to sweep", "10000,20000,50000,100000,200000"},
                     {"grid-cells", "N,N", "surface grid sizes (cells per side) to sweep", "32,64,128,256"},
                     {"base-gaussians", "N", "Gaussian count of the image-size and grid sweeps", "20000"},
                     {"base-grid-cells", "N", "grid size of the image-size and Gaussian sweeps", "64"},
                     {"sh-degree", "D", "SH degree of the Gaussians", "0"},
                     {"runs", "N", "timed steps and renders per setting (median)", "5"},
                     {"warmup", "N", "untimed steps before each measurement", "2"},
                     {"csv", "FILE", "write the rows as CSV (rewritten after every setting)", ""}},
                    runBenchScaling});

}  // namespace
}  // namespace refrax
