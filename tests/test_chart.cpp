// refrax chart: CSV parsing and its errors, the SVG it writes (read back: one polyline per
// series, points in the plot box and in the order of their values, the log axis), and that
// a failing chart leaves no file behind.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <regex>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/report/csv_chart.h"
#include "engine/report/csv_table.h"
#include "engine/report/svg_chart.h"
#include "tests/gpu_test.h"

using namespace refrax;
namespace fs = std::filesystem;

namespace {

struct ChartDir {
  fs::path path;
  ChartDir() {
    path = fs::temp_directory_path() / ("refrax-chart-" + std::to_string(test::freshSeed()));
    fs::create_directories(path);
  }
  ~ChartDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
  size_t fileCount() const {
    size_t n = 0;
    for (auto& e : fs::directory_iterator(path)) n += e.is_regular_file();
    return n;
  }
};

struct Point {
  double x, y;
};

// Each <polyline class="series"> of an SVG, by its data-series name, with its points.
std::map<std::string, std::vector<Point>> polylines(const std::string& svg) {
  std::map<std::string, std::vector<Point>> out;
  std::regex line(R"re(<polyline class="series" data-series="([^"]*)" points="([^"]*)")re");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), line); it != std::sregex_iterator(); ++it) {
    std::vector<Point> pts;
    std::string list = (*it)[2];
    std::regex pair(R"re((-?[0-9.]+),(-?[0-9.]+))re");
    for (auto p = std::sregex_iterator(list.begin(), list.end(), pair); p != std::sregex_iterator(); ++p)
      pts.push_back({std::stod((*p)[1]), std::stod((*p)[2])});
    out[(*it)[1]] = pts;
  }
  return out;
}

PlotBox plotBoxOf(const std::string& svg) {
  std::smatch m;
  std::regex box(R"re(<rect class="plot-box" x="([0-9.]+)" y="([0-9.]+)" width="([0-9.]+)" height="([0-9.]+)")re");
  REQUIRE(std::regex_search(svg, m, box));
  double x = std::stod(m[1]), y = std::stod(m[2]);
  return {x, y, x + std::stod(m[3]), y + std::stod(m[4])};
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("CSV parsing: quotes, blank lines, CRLF, and one clear error per defect") {
  CsvTable t = parseCsv("name,value\r\n\"a, quoted\",1.5\n\n plain , 2e3 \n\"say \"\"hi\"\"\",\n", "t.csv");
  REQUIRE(t.header == std::vector<std::string>{"name", "value"});
  REQUIRE(t.rows.size() == 3);
  CHECK(t.rows[0][0] == "a, quoted");
  CHECK(t.rows[1][0] == "plain");
  CHECK(t.rows[2][0] == "say \"hi\"");
  CHECK(t.lines == std::vector<int>{2, 4, 5});
  size_t v = csvColumn(t, "value");
  CHECK(*csvNumber(t, 0, v) == 1.5);
  CHECK(*csvNumber(t, 1, v) == 2000.0);
  CHECK_FALSE(csvNumber(t, 2, v).has_value());

  CHECK(errorOf([&] { csvColumn(t, "psnr"); }) == "t.csv has no column 'psnr' (columns: name, value)");
  CsvTable bad = parseCsv("x,y\n1,2\n3,4.5x\n", "b.csv");
  CHECK(errorOf([&] { csvNumber(bad, 1, 1); }) == "b.csv line 3, column 'y': '4.5x' is not a number");
  CHECK(errorOf([] { parseCsv("x,y\n1,2,3\n", "c.csv"); }) == "c.csv line 2: 3 fields, the header has 2");
  CHECK(errorOf([] { parseCsv("x,y\n\"1,2\n", "d.csv"); }) == "d.csv line 2: a quoted field is not closed");
  CHECK(errorOf([] { parseCsv("\n\n", "e.csv"); }) == "e.csv is empty (no header row)");
  CHECK(errorOf([] { parseCsv("x,,y\n", "f.csv"); }) == "f.csv: column 2 of the header has no name");
  CHECK(errorOf([] { readCsv("/no/such/dir/data.csv"); }).find("cannot read /no/such/dir/data.csv") == 0);

  // csvLine quotes what needs quoting, and parses back to the same fields.
  std::vector<std::string> fields = {"plain", "with,comma", "with \"quote\"", " edge", ""};
  CsvTable round = parseCsv(csvLine({"a", "b", "c", "d", "e"}) + csvLine(fields), "r.csv");
  CHECK(round.rows.at(0) == fields);
}

TEST_CASE("chart: one polyline per series, points sorted by x, inside the plot box, in value order") {
  std::mt19937 rng(test::freshSeed());
  std::uniform_real_distribution<double> U(-50, 300);
  // Three series with 4, 6 and 9 points, rows shuffled, plus one row without a y.
  std::vector<std::string> names = {"defaults", "reference 6x256", "no \"density\" loss"};
  std::vector<int> counts = {4, 6, 9};
  std::vector<std::vector<std::string>> rows;
  for (size_t s = 0; s < names.size(); s++)
    for (int i = 0; i < counts[s]; i++) rows.push_back({names[s], std::to_string(U(rng)), std::to_string(U(rng) / 10)});
  std::shuffle(rows.begin(), rows.end(), rng);
  rows.push_back({names[1], "12", ""});
  std::string text = csvLine({"config", "seconds", "psnr"});
  for (auto& r : rows) text += csvLine(r);
  ChartDir dir;
  writeTextAtomic(dir / "data.csv", text);

  CsvChartRequest req;
  req.x = "seconds";
  req.y = "psnr";
  req.series = "config";
  req.spec.title = "PSNR <vs> time";
  req.spec.hlines.push_back(parseChartLine("20:20 dB"));
  CsvChartData d = writeCsvChart(dir / "data.csv", dir / "chart.svg", req);
  CHECK(d.skippedRows == 1);
  std::string svg = readFile(dir / "chart.svg");
  CHECK(svg.find("PSNR &lt;vs&gt; time") != std::string::npos);
  CHECK(svg.find("<line class=\"hline\"") != std::string::npos);
  auto lines = polylines(svg);
  REQUIRE(lines.size() == 3);
  PlotBox box = plotBoxOf(svg);

  // Every data point, (value, pixel) pairs over all series: the mapping must keep the order
  // of the values on both axes (x grows right, y grows up) and stay in the plot box.
  std::vector<std::pair<double, double>> xs, ys;
  for (size_t s = 0; s < names.size(); s++) {
    std::string escapedName = s == 2 ? "no &quot;density&quot; loss" : names[s];
    REQUIRE(lines.count(escapedName));
    const auto& pts = lines[escapedName];
    REQUIRE(pts.size() == size_t(counts[s]));
    std::vector<double> vx, vy;
    for (auto& r : rows)
      if (r[0] == names[s] && !r[2].empty()) {
        vx.push_back(std::stod(r[1]));
        vy.push_back(std::stod(r[2]));
      }
    std::vector<size_t> order(vx.size());
    for (size_t i = 0; i < order.size(); i++) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return vx[a] < vx[b]; });
    for (size_t i = 0; i < pts.size(); i++) {
      CHECK(pts[i].x >= box.left - 0.01);
      CHECK(pts[i].x <= box.right + 0.01);
      CHECK(pts[i].y >= box.top - 0.01);
      CHECK(pts[i].y <= box.bottom + 0.01);
      if (i) CHECK(pts[i].x >= pts[i - 1].x);  // polyline drawn left to right
      xs.push_back({vx[order[i]], pts[i].x});
      ys.push_back({vy[order[i]], pts[i].y});
    }
  }
  std::sort(xs.begin(), xs.end());
  std::sort(ys.begin(), ys.end());
  for (size_t i = 1; i < xs.size(); i++) CHECK(xs[i].second >= xs[i - 1].second - 0.011);
  for (size_t i = 1; i < ys.size(); i++) CHECK(ys[i].second <= ys[i - 1].second + 0.011);
  // The map is affine: the middle point in value lies where interpolation puts it.
  double t = (xs[5].first - xs.front().first) / (xs.back().first - xs.front().first);
  CHECK(xs[5].second == doctest::Approx(xs.front().second + t * (xs.back().second - xs.front().second)).epsilon(0.002));
  double u = (ys[7].first - ys.front().first) / (ys.back().first - ys.front().first);
  CHECK(ys[7].second == doctest::Approx(ys.front().second + u * (ys.back().second - ys.front().second)).epsilon(0.002));

  // Without a series column: a single series named after y.
  req.series.clear();
  writeCsvChart(dir / "data.csv", dir / "one.svg", req);
  auto one = polylines(readFile(dir / "one.svg"));
  REQUIRE(one.size() == 1);
  CHECK(one.begin()->first == "psnr");
  CHECK(one.begin()->second.size() == 19);
}

TEST_CASE("chart: a log x axis spaces decades evenly and refuses x <= 0") {
  ChartSpec spec;
  spec.logX = true;
  ChartSeries s{"budget", {2000, 5000, 20000, 100000}, {20, 22, 23, 23.5}};
  std::string svg = renderSvgChart({s}, spec);
  auto pts = polylines(svg)["budget"];
  REQUIRE(pts.size() == 4);
  double perDecade = (pts[3].x - pts[0].x) / std::log10(100000.0 / 2000.0);
  CHECK(perDecade > 0);
  CHECK(pts[1].x - pts[0].x == doctest::Approx(perDecade * std::log10(2.5)).epsilon(0.01));
  CHECK(pts[2].x - pts[1].x == doctest::Approx(perDecade * std::log10(4.0)).epsilon(0.01));
  // On a linear axis the same points are spaced by value instead.
  spec.logX = false;
  auto lin = polylines(renderSvgChart({s}, spec))["budget"];
  CHECK((lin[1].x - lin[0].x) / (lin[3].x - lin[0].x) == doctest::Approx(3000.0 / 98000.0).epsilon(0.01));
  // Tick labels at decades (with 2 and 5 between them under three decades).
  CHECK(logTicks(1500, 120000) == std::vector<double>{2000, 5000, 10000, 20000, 50000, 100000});
  CHECK(logTicks(15, 90000) == std::vector<double>{100, 1000, 10000});
  CHECK(logTicks(15, 900) == std::vector<double>{20, 50, 100, 200, 500});
  spec.logX = true;
  CHECK(errorOf([&] { renderSvgChart({{"bad", {0, 1}, {1, 2}}}, spec); }) == "a log x axis needs x > 0; series 'bad' has x = 0");
  CHECK(errorOf([&] { renderSvgChart({{"empty", {}, {}}}, spec); }) == "nothing to chart: no series has a point");
  std::vector<double> ticks = niceTicks(0.13, 0.87, 6), expected = {0.2, 0.4, 0.6, 0.8};
  REQUIRE(ticks.size() == expected.size());
  for (size_t i = 0; i < ticks.size(); i++) CHECK(ticks[i] == doctest::Approx(expected[i]));
}

TEST_CASE("chart: errors name the problem and leave no output behind") {
  ChartDir dir;
  writeTextAtomic(dir / "ok.csv", "run,steps,psnr\na,100,20.5\na,200,22\n");
  writeTextAtomic(dir / "bad.csv", "run,steps,psnr\na,100,20.5\na,2OO,22\n");
  writeTextAtomic(dir / "old.svg", "previous chart");
  CsvChartRequest req;
  req.x = "steps";
  req.y = "psnr";
  CHECK(errorOf([&] { writeCsvChart(dir / "bad.csv", dir / "new.svg", req); }) == dir / "bad.csv" + " line 3, column 'steps': '2OO' is not a number");
  CHECK(errorOf([&] { writeCsvChart(dir / "bad.csv", dir / "old.svg", req); }) != "");
  CHECK(readFile(dir / "old.svg") == "previous chart");
  req.y = "ssim";
  CHECK(errorOf([&] { writeCsvChart(dir / "ok.csv", dir / "new.svg", req); }) == dir / "ok.csv" + " has no column 'ssim' (columns: run, steps, psnr)");
  CHECK(errorOf([&] { parseChartLine("twenty:20 dB"); }) == "--hline expects Y or Y:label with a number Y, got 'twenty:20 dB'");
  CHECK_FALSE(fileExists(dir / "new.svg"));
  CHECK(dir.fileCount() == 3);  // no temporary file left either

  // The CLI: one error line, non-zero exit, no file; and a chart on success.
  auto missing = test::runCli("chart " + dir / "missing.csv" + " -o " + dir / "c.svg" + " --x steps --y psnr");
  CHECK(missing.exitCode != 0);
  CHECK(missing.output.find("refrax: error: cannot read " + dir / "missing.csv") != std::string::npos);
  auto badCol = test::runCli("chart " + dir / "ok.csv" + " -o " + dir / "c.svg" + " --x steps --y nope");
  CHECK(badCol.exitCode != 0);
  CHECK(badCol.output.find("has no column 'nope'") != std::string::npos);
  CHECK_FALSE(fileExists(dir / "c.svg"));
  auto ok = test::runCli("chart " + dir / "ok.csv" + " -o " + dir / "c.svg" + " --x steps --y psnr --series run --log-x --hline 21:target");
  CHECK(ok.exitCode == 0);
  REQUIRE(fileExists(dir / "c.svg"));
  auto lines = polylines(readFile(dir / "c.svg"));
  REQUIRE(lines.count("a"));
  CHECK(lines["a"].size() == 2);
  CHECK(readFile(dir / "c.svg").find("hline-label") != std::string::npos);
}
