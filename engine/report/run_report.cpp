#include "engine/report/run_report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/report/csv_table.h"

namespace refrax {

namespace {

// metrics.json fields, then config.json fields (prefixed where a name would be ambiguous).
const char* const kMetricColumns[] = {"model", "step", "psnr", "ssim", "surface_rmse", "initial_flat_surface_rmse", "surface_correlation",
                                      "water_removal_psnr", "surface_sweep_ratio", "surface_roughened", "missed_rays", "gaussians", "model_bytes",
                                      "training_seconds", "between_psnr", "between_ssim"};
const char* const kConfigColumns[] = {"steps", "patch", "max_sh_degree", "initial_gaussians", "max_gaussians", "mlp_width", "mlp_hidden_layers",
                                      "mlp_octaves", "mlp_init_range", "grid_cells", "subdivision_levels", "face_normals_until", "density_loss",
                                      "ior", "seed"};
const char* const kEvaluationColumns[] = {"eval_step", "eval_seconds", "eval_psnr", "eval_ssim", "eval_surface_rmse"};

std::string cell(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_number_integer() || v.is_number_unsigned()) return v.dump();
  if (v.is_number_float()) {
    double d = v.get<double>();
    if (!std::isfinite(d)) return "";
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", d);
    return b;
  }
  return v.dump();
}

std::string field(const nlohmann::json& object, const std::string& key) { return object.contains(key) ? cell(object[key]) : ""; }

nlohmann::json runFile(const std::string& run, const char* name, const char* what) {
  std::string path = (std::filesystem::path(run) / name).string();
  if (!fileExists(path)) fail(run + " has no " + name + " (" + what + ")");
  nlohmann::json j = readJson(path);
  if (!j.is_object()) fail(path + ": not a JSON object");
  return j;
}

}  // namespace

std::vector<std::string> reportColumns(const ReportRequest& r) {
  std::vector<std::string> c = {"run"};
  for (auto& e : r.extra) c.push_back(e.first);
  if (r.evaluations)
    for (auto* n : kEvaluationColumns) c.push_back(n);
  for (auto* n : kMetricColumns) c.push_back(n);
  for (auto* n : kConfigColumns) c.push_back(std::string("config_") + n);
  return c;
}

std::vector<std::vector<std::string>> reportRows(const ReportRequest& r) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& run : r.runs) {
    nlohmann::json m = runFile(run, "metrics.json", "not a finished training run");
    nlohmann::json c = runFile(run, "config.json", "not a training run");
    if (!m.contains("psnr") || !m.contains("step")) fail(run + "/metrics.json is not a training run's metrics (no psnr or step)");
    nlohmann::json schedule = c.contains("schedule") ? c["schedule"] : nlohmann::json::object();
    std::vector<std::string> base = {std::filesystem::path(run).lexically_normal().filename().string()};
    if (base[0].empty()) base[0] = std::filesystem::path(run).lexically_normal().parent_path().filename().string();
    for (auto& e : r.extra) base.push_back(e.second);
    std::vector<std::string> tail;
    for (auto* n : kMetricColumns) tail.push_back(field(m, n));
    for (auto* n : kConfigColumns) tail.push_back(std::string(n) == "face_normals_until" ? field(schedule, n) : field(c, n));
    if (!r.evaluations) {
      std::vector<std::string> row = base;
      row.insert(row.end(), tail.begin(), tail.end());
      rows.push_back(row);
      continue;
    }
    if (!m.contains("evaluations") || !m["evaluations"].is_array() || m["evaluations"].empty())
      fail(run + "/metrics.json has no evaluations (a run from before they were recorded)");
    for (const auto& e : m["evaluations"]) {
      std::vector<std::string> row = base;
      for (auto* n : {"step", "seconds", "psnr", "ssim", "surface_rmse"}) row.push_back(field(e, n));
      row.insert(row.end(), tail.begin(), tail.end());
      rows.push_back(row);
    }
  }
  return rows;
}

std::vector<std::pair<std::string, std::string>> parseReportColumns(const std::string& text) {
  std::vector<std::pair<std::string, std::string>> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t comma = text.find(',', start);
    std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0) fail("--set expects key=value[,key=value...], got '" + item + "'");
    out.push_back({item.substr(0, eq), item.substr(eq + 1)});
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

void writeReportCsv(const std::string& path, const ReportRequest& r, bool append) {
  std::vector<std::string> header = reportColumns(r);
  std::vector<std::vector<std::string>> rows = reportRows(r);  // every run read before anything is written
  std::string text;
  if (append && fileExists(path)) {
    CsvTable old = readCsv(path);
    if (old.header != header) fail(path + " has other columns than this report (" + std::to_string(old.header.size()) + " against " +
                                   std::to_string(header.size()) + "): write a new file, or use the same --set keys and --evaluations");
    text = readFile(path);
    if (!text.empty() && text.back() != '\n') text += '\n';
  } else {
    text = csvLine(header);
  }
  for (auto& row : rows) text += csvLine(row);
  writeTextAtomic(path, text);
}

}  // namespace refrax
