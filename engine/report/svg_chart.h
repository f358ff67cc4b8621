#pragma once
// Line charts as plain SVG text (no dependencies): one polyline with point markers per
// series, axes with "nice" ticks (or decades on a log x axis), labels, a legend, and
// optional horizontal reference lines. `refrax chart` turns CSV columns into this.
//
// The output is meant to be read back by tests as well as by people: the plot box is
// <rect class="plot-box" .../>, each series is <polyline class="series" data-series="NAME"
// points="x,y x,y ..."/> with one <circle class="marker"/> per point, and each reference
// line is <line class="hline" .../>.
#include <string>
#include <vector>

namespace refrax {

struct ChartSeries {
  std::string name;
  std::vector<double> x, y;  // same length; drawn in the given order
};

struct ChartLine {  // a horizontal reference line at y, labelled
  double y = 0;
  std::string label;
};

struct ChartSpec {
  std::string title, xLabel, yLabel;
  bool logX = false;  // every x must then be > 0
  std::vector<ChartLine> hlines;
  int width = 760, height = 460;
};

// Plot-box geometry, in SVG user units (y grows downwards).
struct PlotBox {
  double left, top, right, bottom;
};
PlotBox chartPlotBox(const ChartSpec& spec);

// Tick values covering [lo, hi]: multiples of 1, 2 or 5 x 10^k, about `target` of them.
std::vector<double> niceTicks(double lo, double hi, int target);
// Tick values on a log axis over [lo, hi] (lo > 0): the decades, with 2 and 5 between
// them when the range spans fewer than three decades.
std::vector<double> logTicks(double lo, double hi);

// The SVG document. refrax::Error when there is no point at all, a series' x and y differ
// in length, a value is not finite, or (log x) an x is <= 0.
std::string renderSvgChart(const std::vector<ChartSeries>& series, const ChartSpec& spec);

}  // namespace refrax
