#pragma once
// CSV columns to an SVG chart (`refrax chart`): one series per distinct value of a series
// column (in order of first appearance), each series' points sorted by x. Rows whose x or
// y cell is empty, "nan" or "inf" are left out and counted (a failed run in a sweep is a
// row without a number, not a reason to lose the chart).
#include <string>
#include <vector>

#include "engine/report/csv_table.h"
#include "engine/report/svg_chart.h"

namespace refrax {

struct CsvChartRequest {
  std::string x, y;    // column names
  std::string series;  // column name; empty: a single series named after y
  ChartSpec spec;
};

struct CsvChartData {
  std::vector<ChartSeries> series;
  size_t skippedRows = 0;  // rows left out for an empty or non-finite x or y
};

// refrax::Error for a missing column or a malformed number (naming file, line and column).
CsvChartData chartDataFromCsv(const CsvTable& table, const CsvChartRequest& request);

// "Y:label" (or "Y") as a reference line; refrax::Error when Y is not a finite number.
ChartLine parseChartLine(const std::string& text);

// Reads csvPath, renders, and writes svgPath atomically: on any error nothing is written
// and a previous svgPath is left as it was. Returns the data drawn.
CsvChartData writeCsvChart(const std::string& csvPath, const std::string& svgPath, const CsvChartRequest& request);

}  // namespace refrax
