#include "engine/report/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/base/error.h"

namespace refrax {

namespace {

// Colours that stay apart for the usual handful of series (Tableau 10).
const char* const kPalette[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};

std::string escaped(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string num(double v) {  // coordinates: two decimals are far below a pixel
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

std::string label(double v) {  // tick labels: short, no float noise (0.30000000004)
  if (std::fabs(v) < 1e-12) return "0";
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

struct Axis {
  double lo, hi;  // data range shown
  bool log;
  double a0, a1;  // pixel positions of lo and hi
  double map(double v) const {
    double t = log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
    return a0 + t * (a1 - a0);
  }
};

// Range [lo, hi] of the values, widened so that a single value or a flat series still
// spans an axis.
void widen(double& lo, double& hi, bool log) {
  if (log) {
    if (hi <= lo * 1.0001) {
      lo /= 2;
      hi *= 2;
    }
    return;
  }
  if (hi - lo <= 1e-12 * std::max(1.0, std::fabs(hi))) {
    double pad = std::max(std::fabs(hi) * 0.1, 1e-3);
    lo -= pad;
    hi += pad;
  }
}

// Ticks for a linear axis, the range [lo, hi] widened to the ticks just outside it, so that
// both ends of the axis carry a label.
std::vector<double> toTicks(double& lo, double& hi, int target) {
  std::vector<double> t = niceTicks(lo, hi, target);
  double step = t.size() > 1 ? t[1] - t[0] : std::max(hi - lo, 1e-9);
  if (t.front() > lo + 1e-9 * step) t.insert(t.begin(), t.front() - step);
  if (t.back() < hi - 1e-9 * step) t.push_back(t.back() + step);
  lo = std::min(lo, t.front());
  hi = std::max(hi, t.back());
  return t;
}

}  // namespace

PlotBox chartPlotBox(const ChartSpec& s) { return {72.0, 48.0, double(s.width) - 200.0, double(s.height) - 58.0}; }

std::vector<double> niceTicks(double lo, double hi, int target) {
  double span = hi - lo;
  if (!(span > 0)) return {lo};
  double raw = span / std::max(1, target), mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  std::vector<double> t;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + step * 1e-9; k++) t.push_back(std::fabs(k) < 1e-12 ? 0.0 : k * step);
  return t;
}

std::vector<double> logTicks(double lo, double hi) {
  std::vector<double> t;
  bool fine = std::log10(hi) - std::log10(lo) < 3;
  for (double d = std::pow(10.0, std::floor(std::log10(lo))); d <= hi * (1 + 1e-9); d *= 10)
    for (double m : {1.0, 2.0, 5.0}) {
      if (m != 1.0 && !fine) continue;
      double v = d * m;
      if (v >= lo * (1 - 1e-9) && v <= hi * (1 + 1e-9)) t.push_back(v);
    }
  return t;
}

std::string renderSvgChart(const std::vector<ChartSeries>& series, const ChartSpec& spec) {
  double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
  size_t points = 0;
  for (const auto& s : series) {
    if (s.x.size() != s.y.size()) fail("chart series '" + s.name + "' has " + std::to_string(s.x.size()) + " x values and " + std::to_string(s.y.size()) + " y values");
    for (size_t i = 0; i < s.x.size(); i++) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) fail("chart series '" + s.name + "' has a value that is not finite");
      if (spec.logX && s.x[i] <= 0) fail("a log x axis needs x > 0; series '" + s.name + "' has x = " + label(s.x[i]));
      xlo = std::min(xlo, s.x[i]);
      xhi = std::max(xhi, s.x[i]);
      ylo = std::min(ylo, s.y[i]);
      yhi = std::max(yhi, s.y[i]);
      points++;
    }
  }
  if (points == 0) fail("nothing to chart: no series has a point");
  for (const auto& h : spec.hlines) {
    if (!std::isfinite(h.y)) fail("a reference line needs a finite y");
    ylo = std::min(ylo, h.y);
    yhi = std::max(yhi, h.y);
  }
  widen(xlo, xhi, spec.logX);
  widen(ylo, yhi, false);
  // Linear axes end on ticks, so the box edges carry labels; the log axis ends at the data
  // (padded by 5% of a decade-scaled span).
  std::vector<double> xt, yt;
  if (spec.logX) {
    double pad = std::pow(10.0, 0.03 * (std::log10(xhi) - std::log10(xlo)));
    xlo /= pad;
    xhi *= pad;
    xt = logTicks(xlo, xhi);
  } else {
    xt = toTicks(xlo, xhi, 7);
  }
  yt = toTicks(ylo, yhi, 6);
  PlotBox box = chartPlotBox(spec);
  Axis ax{xlo, xhi, spec.logX, box.left, box.right}, ay{ylo, yhi, false, box.bottom, box.top};

  std::string o;
  o += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  o += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(spec.width) + "\" height=\"" + std::to_string(spec.height) +
       "\" viewBox=\"0 0 " + std::to_string(spec.width) + " " + std::to_string(spec.height) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  o += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!spec.title.empty())
    o += "<text class=\"title\" x=\"" + num((box.left + box.right) / 2) + "\" y=\"26\" text-anchor=\"middle\" font-size=\"15\">" + escaped(spec.title) + "</text>\n";
  // Grid and ticks.
  for (double v : xt) {
    double px = ax.map(v);
    o += "<line class=\"grid\" x1=\"" + num(px) + "\" y1=\"" + num(box.top) + "\" x2=\"" + num(px) + "\" y2=\"" + num(box.bottom) + "\" stroke=\"#e4e4e4\"/>\n";
    o += "<text class=\"xtick\" x=\"" + num(px) + "\" y=\"" + num(box.bottom + 16) + "\" text-anchor=\"middle\">" + label(v) + "</text>\n";
  }
  for (double v : yt) {
    double py = ay.map(v);
    o += "<line class=\"grid\" x1=\"" + num(box.left) + "\" y1=\"" + num(py) + "\" x2=\"" + num(box.right) + "\" y2=\"" + num(py) + "\" stroke=\"#e4e4e4\"/>\n";
    o += "<text class=\"ytick\" x=\"" + num(box.left - 6) + "\" y=\"" + num(py + 4) + "\" text-anchor=\"end\">" + label(v) + "</text>\n";
  }
  o += "<rect class=\"plot-box\" x=\"" + num(box.left) + "\" y=\"" + num(box.top) + "\" width=\"" + num(box.right - box.left) + "\" height=\"" +
       num(box.bottom - box.top) + "\" fill=\"none\" stroke=\"#444\"/>\n";
  if (!spec.xLabel.empty())
    o += "<text class=\"xlabel\" x=\"" + num((box.left + box.right) / 2) + "\" y=\"" + num(box.bottom + 38) + "\" text-anchor=\"middle\">" +
         escaped(spec.xLabel) + (spec.logX ? " (log scale)" : "") + "</text>\n";
  if (!spec.yLabel.empty())
    o += "<text class=\"ylabel\" x=\"16\" y=\"" + num((box.top + box.bottom) / 2) + "\" text-anchor=\"middle\" transform=\"rotate(-90 16 " +
         num((box.top + box.bottom) / 2) + ")\">" + escaped(spec.yLabel) + "</text>\n";
  for (const auto& h : spec.hlines) {
    double py = ay.map(h.y);
    o += "<line class=\"hline\" x1=\"" + num(box.left) + "\" y1=\"" + num(py) + "\" x2=\"" + num(box.right) + "\" y2=\"" + num(py) +
         "\" stroke=\"#888\" stroke-dasharray=\"6 4\"/>\n";
    if (!h.label.empty())
      o += "<text class=\"hline-label\" x=\"" + num(box.right - 4) + "\" y=\"" + num(py - 4) + "\" text-anchor=\"end\" fill=\"#666\">" + escaped(h.label) + "</text>\n";
  }
  // Series, then the legend to the right of the plot box.
  for (size_t k = 0; k < series.size(); k++) {
    const auto& s = series[k];
    if (s.x.empty()) continue;
    std::string colour = kPalette[k % (sizeof kPalette / sizeof kPalette[0])], pts;
    for (size_t i = 0; i < s.x.size(); i++) pts += (i ? " " : "") + num(ax.map(s.x[i])) + "," + num(ay.map(s.y[i]));
    o += "<polyline class=\"series\" data-series=\"" + escaped(s.name) + "\" points=\"" + pts + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"2\"/>\n";
    for (size_t i = 0; i < s.x.size(); i++)
      o += "<circle class=\"marker\" cx=\"" + num(ax.map(s.x[i])) + "\" cy=\"" + num(ay.map(s.y[i])) + "\" r=\"3.5\" fill=\"" + colour + "\"/>\n";
  }
  double ly = box.top + 8;
  for (size_t k = 0; k < series.size(); k++) {
    if (series[k].x.empty()) continue;
    std::string colour = kPalette[k % (sizeof kPalette / sizeof kPalette[0])];
    double lx = box.right + 16;
    o += "<line class=\"legend\" x1=\"" + num(lx) + "\" y1=\"" + num(ly) + "\" x2=\"" + num(lx + 22) + "\" y2=\"" + num(ly) + "\" stroke=\"" + colour +
         "\" stroke-width=\"2\"/>\n";
    o += "<circle cx=\"" + num(lx + 11) + "\" cy=\"" + num(ly) + "\" r=\"3.5\" fill=\"" + colour + "\"/>\n";
    o += "<text class=\"legend-label\" x=\"" + num(lx + 28) + "\" y=\"" + num(ly + 4) + "\">" + escaped(series[k].name) + "</text>\n";
    ly += 18;
  }
  o += "</svg>\n";
  return o;
}

}  // namespace refrax
