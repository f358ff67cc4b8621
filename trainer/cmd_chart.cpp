// refrax chart DATA.csv -o OUT.svg --x COL --y COL [--series COL]: a line chart of CSV
// columns as plain SVG (engine/report/), for the benchmark scripts under bench/.
#include <cstdio>

#include "engine/base/error.h"
#include "engine/report/csv_chart.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

int runChart(const cli::Args& a) {
  if (a.positional.size() != 1) fail("refrax chart needs one CSV file");
  if (!a.has("output")) fail("refrax chart needs -o OUT.svg");
  if (!a.has("x") || !a.has("y")) fail("refrax chart needs --x COL and --y COL");
  CsvChartRequest r;
  r.x = a.get("x");
  r.y = a.get("y");
  r.series = a.get("series");
  r.spec.title = a.get("title");
  r.spec.xLabel = a.get("x-label", r.x);
  r.spec.yLabel = a.get("y-label", r.y);
  r.spec.logX = a.has("log-x");
  if (a.has("hline")) r.spec.hlines.push_back(parseChartLine(a.get("hline")));
  CsvChartData d = writeCsvChart(a.positional[0], a.get("output"), r);
  size_t points = 0;
  for (auto& s : d.series) points += s.x.size();
  std::printf("%s: %zu series, %zu points", a.get("output").c_str(), d.series.size(), points);
  if (d.skippedRows) std::printf(" (%zu rows without a finite %s or %s left out)", d.skippedRows, r.x.c_str(), r.y.c_str());
  std::printf("\n");
  return 0;
}

REFRAX_COMMAND({"chart", "line chart (SVG) of CSV columns, one line per series",
                "refrax chart DATA.csv -o OUT.svg --x COL --y COL [--series COL] [options]",
                {{"output", "OUT.svg", "the chart (-o), written atomically", ""},
                 {"x", "COL", "column on the x axis (numbers)", ""},
                 {"y", "COL", "column on the y axis (numbers; empty or nan cells are left out)", ""},
                 {"series", "COL", "one line per distinct value of this column", ""},
                 {"title", "T", "chart title", ""},
                 {"x-label", "L", "x axis label", "the x column"},
                 {"y-label", "L", "y axis label", "the y column"},
                 {"log-x", "", "logarithmic x axis (x > 0)", ""},
                 {"hline", "Y:LABEL", "dashed horizontal reference line at Y", ""}},
                runChart});

}  // namespace
}  // namespace refrax
