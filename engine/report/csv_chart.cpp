#include "engine/report/csv_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

CsvChartData chartDataFromCsv(const CsvTable& t, const CsvChartRequest& r) {
  size_t xc = csvColumn(t, r.x), yc = csvColumn(t, r.y);
  bool bySeries = !r.series.empty();
  size_t sc = bySeries ? csvColumn(t, r.series) : 0;
  CsvChartData d;
  for (size_t i = 0; i < t.rows.size(); i++) {
    auto x = csvNumber(t, i, xc), y = csvNumber(t, i, yc);  // parsed first: a malformed cell fails even in a skipped row
    std::string name = bySeries ? t.rows[i][sc] : r.y;
    auto it = std::find_if(d.series.begin(), d.series.end(), [&](const ChartSeries& s) { return s.name == name; });
    if (it == d.series.end()) {
      d.series.push_back({name, {}, {}});
      it = d.series.end() - 1;
    }
    if (!x || !y || !std::isfinite(*x) || !std::isfinite(*y)) {
      d.skippedRows++;
      continue;
    }
    it->x.push_back(*x);
    it->y.push_back(*y);
  }
  for (auto& s : d.series) {  // sort each series by x (stable: equal x keep file order)
    std::vector<size_t> order(s.x.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return s.x[a] < s.x[b]; });
    ChartSeries sorted{s.name, {}, {}};
    for (size_t k : order) {
      sorted.x.push_back(s.x[k]);
      sorted.y.push_back(s.y[k]);
    }
    s = sorted;
  }
  return d;
}

ChartLine parseChartLine(const std::string& text) {
  size_t colon = text.find(':');
  std::string y = text.substr(0, colon);
  char* end = nullptr;
  double v = std::strtod(y.c_str(), &end);
  if (y.empty() || end == y.c_str() || *end || !std::isfinite(v)) fail("--hline expects Y or Y:label with a number Y, got '" + text + "'");
  return {v, colon == std::string::npos ? std::string() : text.substr(colon + 1)};
}

CsvChartData writeCsvChart(const std::string& csvPath, const std::string& svgPath, const CsvChartRequest& r) {
  CsvChartData d = chartDataFromCsv(readCsv(csvPath), r);
  std::string svg = renderSvgChart(d.series, r.spec);
  writeTextAtomic(svgPath, svg);
  return d;
}

}  // namespace refrax
