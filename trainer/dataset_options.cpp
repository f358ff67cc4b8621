#include "trainer/dataset_options.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "engine/base/error.h"

namespace refrax {

std::vector<cli::Option> datasetOptions() {
  return {
      {"ior", "X", std::string("index of refraction of the water (overrides water.json), ") + kIorRange,
       "water.json, else " + [] { std::ostringstream s; s << kWaterIor; return s.str(); }()},
      {"water-height", "Z", "initial (mean) water height, world z (overrides water.json)", ""},
      {"water-depth", "D", "how far under the water the scene reaches (overrides water.json)", "derived"},
      {"domain", "X0,Y0,X1,Y1", "height-field domain (overrides water.json)", "derived from the cameras"},
      {"background", "R,G,B", "colour RGBA images are composited on, in [0,1]", "0,0,0"},
      {"llff-factor", "N", "LLFF and COLMAP: read images_<N>/ (1: images/)", "1"},
      {"llff-hold", "N", "LLFF and COLMAP: every N-th image (from the first) is a test view (0: none)", "8"},
      {"test-views", "LIST", "LLFF and COLMAP: the test views instead, by index in name order (from 0) or file name, comma-separated "
                             "(NeRFrac's real scenes: 4)", "every --llff-hold-th"},
      {"up", "X,Y,Z", "COLMAP: the water's up (toward the cameras) in the model's frame", "derived from the cameras"},
  };
}

std::vector<double> parseNumbers(const std::string& text, size_t count, const std::string& what, const std::string& shape) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  bool ok = true;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    double d = std::strtod(item.c_str(), &end);
    ok = ok && !item.empty() && !*end && std::isfinite(d);
    v.push_back(d);
  }
  if (!ok || v.empty() || (count > 0 && v.size() != count)) fail(what + " expects " + shape + ", got '" + text + "'");
  return v;
}

Rect parseRect(const std::string& text, const std::string& what) {
  auto v = parseNumbers(text, 4, what, "four numbers x0,y0,x1,y1");
  return {v[0], v[1], v[2], v[3]};
}

DatasetOptions datasetOptionsFrom(const cli::Args& args) {
  DatasetOptions o;
  if (args.has("ior")) o.ior = args.getDouble("ior", kWaterIor);
  if (args.has("water-height")) o.waterHeight = args.getDouble("water-height", 0);
  if (args.has("water-depth")) o.waterDepth = args.getDouble("water-depth", 1);
  if (args.has("domain")) o.domain = parseRect(args.get("domain"), "--domain");
  if (args.has("background")) {
    auto c = parseNumbers(args.get("background"), 3, "--background", "three numbers in [0,1] as R,G,B");
    for (double x : c)
      if (x < 0 || x > 1) fail("--background expects three numbers in [0,1] as R,G,B, got '" + args.get("background") + "'");
    o.background = glm::dvec3(c[0], c[1], c[2]);
  }
  if (args.has("up")) {
    auto u = parseNumbers(args.get("up"), 3, "--up", "three numbers X,Y,Z");
    if (glm::length(glm::dvec3(u[0], u[1], u[2])) < 1e-9) fail("--up expects a direction, got '" + args.get("up") + "'");
    o.up = glm::dvec3(u[0], u[1], u[2]);
  }
  o.llffFactor = int(args.getInt("llff-factor", 1));
  o.llffHold = int(args.getInt("llff-hold", 8));
  if (args.has("test-views")) {
    if (args.has("llff-hold")) fail("--test-views and --llff-hold both choose the test views: give one");
    std::stringstream list(args.get("test-views"));
    for (std::string item; std::getline(list, item, ',');) {
      if (item.empty()) fail("--test-views expects a comma-separated list of indices or file names, got '" + args.get("test-views") + "'");
      o.testViews.push_back(item);
    }
    if (o.testViews.empty()) fail("--test-views expects a comma-separated list of indices or file names, got ''");
  }
  return o;
}

}  // namespace refrax
