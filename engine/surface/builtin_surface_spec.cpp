#include "engine/surface/builtin_surface_spec.h"

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "engine/base/error.h"

namespace refrax {

BuiltinSurface parseBuiltinSurface(const std::string& spec, float defaultHeight) {
  std::vector<std::string> parts;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ':')) parts.push_back(item);
  if (parts.empty() || parts.size() > 5) fail("surface '" + spec + "' must be KIND[:height[:amplitude[:wavelength[:direction]]]]");
  BuiltinSurface b;
  b.kind = parts[0];
  b.height = defaultHeight;
  if (b.kind != "flat" && b.kind != "sine" && b.kind != "triangle") fail("surface '" + spec + "': unknown kind '" + b.kind + "' (flat, sine or triangle)");
  float* fields[] = {&b.height, &b.amplitude, &b.wavelength, &b.directionDeg};
  for (size_t i = 1; i < parts.size(); i++) {
    char* end = nullptr;
    double d = std::strtod(parts[i].c_str(), &end);
    if (parts[i].empty() || *end || !std::isfinite(d)) fail("surface '" + spec + "': '" + parts[i] + "' is not a number");
    *fields[i - 1] = float(d);
  }
  surfaceHeightFunction(b);  // validates the wavelength
  return b;
}

AnalyticWaves builtinSurfaceWaves(const BuiltinSurface& b) {
  if (b.kind != "flat" && b.kind != "sine") fail("a " + b.kind + " surface has no closed-form waves (flat or sine only)");
  surfaceHeightFunction(b);
  AnalyticWaves w;
  w.base = b.height;
  if (b.kind == "sine") {
    double k = 2 * M_PI / b.wavelength, a = b.directionDeg * M_PI / 180;
    w.waves[0][0] = b.amplitude;
    w.waves[0][1] = float(k * std::cos(a));
    w.waves[0][2] = float(k * std::sin(a));
  }
  return w;
}

}  // namespace refrax
