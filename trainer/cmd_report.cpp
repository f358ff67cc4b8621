// refrax report RUN... -o OUT.csv: flattens the metrics.json and config.json of training runs
// into CSV rows (engine/report/run_report.h), for the benchmark scripts under bench/.
#include <cstdio>

#include "engine/base/error.h"
#include "engine/report/run_report.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

int runReport(const cli::Args& a) {
  if (a.positional.empty()) fail("refrax report needs at least one run folder");
  if (!a.has("output")) fail("refrax report needs -o OUT.csv");
  ReportRequest r;
  r.runs = a.positional;
  if (a.has("set")) r.extra = parseReportColumns(a.get("set"));
  r.evaluations = a.has("evaluations");
  writeReportCsv(a.get("output"), r, a.has("append"));
  std::printf("%s: %zu run%s %s\n", a.get("output").c_str(), r.runs.size(), r.runs.size() == 1 ? "" : "s", a.has("append") ? "appended" : "written");
  return 0;
}

REFRAX_COMMAND({"report", "training runs' metrics and configuration as CSV rows",
                "refrax report RUN... -o OUT.csv [--set key=value,...] [--evaluations] [--append]",
                {{"output", "OUT.csv", "the CSV (-o), written atomically", ""},
                 {"set", "K=V,...", "constant columns added after 'run' (e.g. config=defaults,preset=nerfrac-hybrid)", ""},
                 {"evaluations", "", "one row per evaluation (metrics.json 'evaluations': step, training seconds, psnr, ssim, surface_rmse)", ""},
                 {"append", "", "add the rows to OUT.csv (its header must match)", ""}},
                runReport});

}  // namespace
}  // namespace refrax
