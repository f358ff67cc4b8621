#pragma once
// Training runs flattened into CSV rows (`refrax report`), so benchmark scripts collect
// metrics.json and config.json of many runs without a JSON tool: one row per run, or one
// row per evaluation of each run (metrics.json "evaluations": the accuracy-against-time curve).
#include <string>
#include <utility>
#include <vector>

namespace refrax {

struct ReportRequest {
  std::vector<std::string> runs;                            // run folders
  std::vector<std::pair<std::string, std::string>> extra;   // constant columns (--set k=v), first after "run"
  bool evaluations = false;                                 // a row per evaluation instead of per run
};

// The columns: "run" (the folder's name), the extra columns, then the fixed run columns.
std::vector<std::string> reportColumns(const ReportRequest& request);
// The rows, in run order. A value the run does not have (surface_rmse without a ground-truth
// surface, a null for a non-finite number) is an empty cell. refrax::Error naming the run
// when metrics.json or config.json is missing or is not a finished run's.
std::vector<std::vector<std::string>> reportRows(const ReportRequest& request);

// "k=v,k2=v2" into pairs; refrax::Error on an entry without '=' or with an empty key.
std::vector<std::pair<std::string, std::string>> parseReportColumns(const std::string& text);

// Writes the CSV atomically. With append and an existing file, its rows are kept and the new
// ones added after them; refrax::Error (file untouched) when its header differs.
void writeReportCsv(const std::string& path, const ReportRequest& request, bool append);

}  // namespace refrax
