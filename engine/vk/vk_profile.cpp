#include "engine/vk/vk_profile.h"

#include <algorithm>
#include <cstdio>

#include "engine/vk/vk_context.h"

namespace refrax {

namespace {
// Stamps one submission can hold: the surface trace's longest submission has about ten.
constexpr uint32_t kStampsPerSubmit = 64;

double perStep(const GpuProfiler& p, double ms) { return ms / std::max(1, p.steps); }

double total(const std::map<std::string, StageTotals>& stages) {
  double sum = 0;
  for (const auto& [name, t] : stages) sum += t.ms;
  return sum;
}
}  // namespace

void attachProfiler(Context& ctx, GpuProfiler& p) {
  if (!p.timer.ctx) createTimer(ctx, p.timer, kStampsPerSubmit);
  p.gpu = p.timer.pool != VK_NULL_HANDLE;
  ctx.profiler = &p;
}

void detachProfiler(Context& ctx) { ctx.profiler = nullptr; }

void profileStage(VkCommandBuffer cb, Context& ctx, const std::string& stage) {
  GpuProfiler* p = ctx.profiler;
  if (p && p->gpu) cmdTimerStamp(cb, p->recording ? *p->recording : p->timer, stage);
}

HostStage::HostStage(Context& c, std::string s) : ctx(c), stage(std::move(s)), start(std::chrono::steady_clock::now()) {
  if (ctx.profiler) deviceMsAtStart = ctx.profiler->deviceMs;
}

HostStage::~HostStage() {
  if (!ctx.profiler) return;
  StageTotals& t = ctx.profiler->host[stage];
  double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  t.ms += std::max(0.0, wall - (ctx.profiler->deviceMs - deviceMsAtStart));
  t.calls++;
}

void profileSubmitBegin(VkCommandBuffer cb, Context& ctx) {
  if (ctx.profiler) profileSubmitBegin(cb, ctx, ctx.profiler->timer);
}

void profileSubmitBegin(VkCommandBuffer cb, Context& ctx, GpuTimer& timer) {
  GpuProfiler* p = ctx.profiler;
  if (!p) return;
  p->submits++;
  p->recording = &timer;
  if (!p->gpu) return;
  if (!timer.ctx) createTimer(ctx, timer, kStampsPerSubmit);
  cmdTimerStart(cb, timer);
}

void profileSubmitDone(GpuProfiler& p, GpuTimer& timer) {
  if (!p.gpu || !timer.ctx) return;
  for (auto& [stage, ms] : readTimer(timer)) {
    StageTotals& t = p.device[stage];
    t.ms += ms;
    p.deviceMs += ms;
    t.calls++;
  }
  timer.labels.clear();
}

void profileSubmitEnd(Context& ctx) {
  GpuProfiler* p = ctx.profiler;
  if (!p || !p->gpu) return;
  profileSubmitDone(*p, p->timer);
}

void profileStepEnd(GpuProfiler& p, double wallMs) {
  p.wallMs += wallMs;
  p.steps++;
  p.stepMs.push_back(float(wallMs));
}

double medianStepMs(const GpuProfiler& p) {
  if (p.stepMs.empty()) return 0;
  std::vector<float> v = p.stepMs;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

std::vector<ProfileRow> profileRows(const GpuProfiler& p) {
  std::vector<ProfileRow> rows;
  for (const auto& [name, t] : p.device) rows.push_back({name, true, perStep(p, t.ms)});
  for (const auto& [name, t] : p.host) rows.push_back({name, false, perStep(p, t.ms)});
  // The wall time no named stage accounts for: submissions, waits, uploads and downloads,
  // and the host work between them.
  double rest = perStep(p, p.wallMs - total(p.device) - total(p.host));
  rows.push_back({"other host (submits, transfers, glue)", false, std::max(0.0, rest)});
  std::stable_sort(rows.begin(), rows.end(), [](const ProfileRow& a, const ProfileRow& b) { return a.msPerStep > b.msPerStep; });
  return rows;
}

std::string profileTop(const GpuProfiler& p, size_t n) {
  std::string out;
  char buf[160];
  std::vector<ProfileRow> rows = profileRows(p);
  for (size_t i = 0; i < std::min(n, rows.size()); i++) {
    std::snprintf(buf, sizeof buf, "%s%s %.1f ms", i ? ", " : "", rows[i].stage.c_str(), rows[i].msPerStep);
    out += buf;
  }
  return out;
}

std::string profileTable(const GpuProfiler& p) {
  std::string out;
  char buf[256];
  double wall = perStep(p, p.wallMs);
  double slowest = p.stepMs.empty() ? 0.0 : *std::max_element(p.stepMs.begin(), p.stepMs.end());
  std::snprintf(buf, sizeof buf, "profile: %d steps, %.2f ms per step (median %.2f, slowest %.1f), %.2f submits and %.1f dispatches per step%s\n",
                p.steps, wall, medianStepMs(p), slowest, double(p.submits) / std::max(1, p.steps), double(p.dispatches) / std::max(1, p.steps),
                p.gpu ? "" : "; this device writes no timestamps: host stages only");
  out += buf;
  std::snprintf(buf, sizeof buf, "  %-44s %6s %10s %7s\n", "stage", "where", "ms/step", "share");
  out += buf;
  for (const ProfileRow& r : profileRows(p)) {
    std::snprintf(buf, sizeof buf, "  %-44s %6s %10.3f %6.1f%%\n", r.stage.c_str(), r.gpu ? "GPU" : "host", r.msPerStep,
                  wall > 0 ? 100.0 * r.msPerStep / wall : 0.0);
    out += buf;
  }
  return out;
}

nlohmann::json profileJson(const GpuProfiler& p) {
  nlohmann::json gpu = nlohmann::json::object(), host = nlohmann::json::object();
  for (const auto& [name, t] : p.device) gpu[name] = perStep(p, t.ms);
  for (const auto& [name, t] : p.host) host[name] = perStep(p, t.ms);
  double gpuTotal = perStep(p, total(p.device));
  return {{"steps", p.steps},
          {"timestamps", p.gpu},
          {"wall_ms_per_step", perStep(p, p.wallMs)},
          {"median_step_ms", medianStepMs(p)},
          {"slowest_step_ms", p.stepMs.empty() ? 0.0 : double(*std::max_element(p.stepMs.begin(), p.stepMs.end()))},
          {"gpu_ms_per_step", gpuTotal},
          {"host_ms_per_step", perStep(p, p.wallMs) - gpuTotal},
          {"submits_per_step", double(p.submits) / std::max(1, p.steps)},
          {"dispatches_per_step", double(p.dispatches) / std::max(1, p.steps)},
          {"gpu", gpu},
          {"host", host}};
}

}  // namespace refrax
