#include "engine/survey/bottom_maps.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/base/error.h"
#include "engine/model/render_model.h"

namespace refrax {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Straight down from `top` at every vertex, row by row from yMin.
std::vector<GpuRay> verticalRays(const BottomGrid& g, double top) {
  std::vector<GpuRay> rays(g.size());
  for (uint32_t j = 0; j < g.ny; j++)
    for (uint32_t i = 0; i < g.nx; i++) {
      GpuRay& r = rays[size_t(j) * g.nx + i];
      r = GpuRay{};
      r.origin[0] = float(g.x(i)), r.origin[1] = float(g.y(j)), r.origin[2] = float(top);
      r.dir[2] = -1.0f;
      r.tmin = 0.0f;
      r.tmax = 1e6f;
    }
  return rays;
}

// How many training views see the water's point above each vertex, and their rays' mean angle
// from the vertical (the straight ray from the camera: the views meet the water in air).
void confidence(const std::vector<View>& views, const BottomGrid& g, BottomMaps& out) {
  out.views.assign(g.size(), 0.0f);
  out.incidence.assign(g.size(), kNaN);
  for (uint32_t j = 0; j < g.ny; j++)
    for (uint32_t i = 0; i < g.nx; i++) {
      const size_t k = size_t(j) * g.nx + i;
      const glm::dvec3 p(g.x(i), g.y(j), out.surface[k]);
      double angles = 0;
      int seen = 0;
      for (const View& v : views) {
        if (!v.camera.sees(p)) continue;
        const glm::dvec3 d = glm::normalize(p - v.camera.position());
        angles += std::acos(std::clamp(-d.z, -1.0, 1.0)) * 180.0 / M_PI;
        seen++;
      }
      out.views[k] = float(seen);
      if (seen) out.incidence[k] = float(angles / seen);
    }
}

}  // namespace

BottomGrid bottomGridOver(const Rect& domain, uint32_t vertices) {
  if (vertices < 2) fail("the bottom's grid needs at least 2 vertices per side");
  if (!(domain.xMax > domain.xMin && domain.yMax > domain.yMin)) fail("the bottom's grid: the water's domain is empty");
  BottomGrid g;
  g.nx = g.ny = vertices;
  g.box = domain;
  return g;
}

BottomMaps mapBottom(Model& m, const std::vector<View>& trainViews, const BottomGrid& g) {
  const Rect& d = m.config.domain;
  if (g.box.xMin != d.xMin || g.box.yMin != d.yMin || g.box.xMax != d.xMax || g.box.yMax != d.yMax)
    fail("the bottom is mapped over the water's domain only");
  BottomMaps out;
  out.grid = g;
  const std::vector<double> heights = sampleWaterHeights(m, g.nx, g.ny);
  out.surface.assign(heights.begin(), heights.end());
  // Above the water and every Gaussian the run could have (its scene box), so the first thing a
  // ray meets is what a surveyor's vertical sounding would.
  const double top = std::max(m.config.boxMax[2], *std::max_element(heights.begin(), heights.end())) + 0.01 * m.config.extent;
  const std::vector<GpuRay> rays = verticalRays(g, top);
  const std::vector<GpuTraceResult> dry = traceModelRays(m, rays, WaterView::Remove, kBottomOpacity);
  const std::vector<GpuTraceResult> wet = traceModelRays(m, rays, WaterView::Keep);
  out.bottom.resize(g.size());
  out.opacity.resize(g.size());
  out.depth.resize(g.size());
  out.orthoDry.resize(3 * g.size());
  out.orthoWet.resize(3 * g.size());
  for (size_t k = 0; k < g.size(); k++) {
    out.opacity[k] = dry[k].opacity;
    out.bottom[k] = dry[k].opacity >= kBottomOpacity ? float(top - double(dry[k].depth)) : kNaN;
    out.depth[k] = out.surface[k] - out.bottom[k];
    for (int c = 0; c < 3; c++) {
      out.orthoDry[3 * k + c] = std::clamp(dry[k].rgb[c], 0.0f, 1.0f);
      out.orthoWet[3 * k + c] = std::clamp(wet[k].rgb[c], 0.0f, 1.0f);
    }
  }
  confidence(trainViews, g, out);
  return out;
}

}  // namespace refrax
