#include "engine/dataset/scene_bounds.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "engine/camera/camera.h"

namespace refrax {
namespace {

// Refraction from air (index 1) into water (index ior) at a horizontal plane with normal +Z
// (the flat-plane case of Snell's law in vector form; only used for these bounds).
glm::dvec3 refractDown(const glm::dvec3& d, double ior) {
  const glm::dvec3 n(0, 0, 1);
  double eta = 1.0 / ior, cosI = -glm::dot(n, d);
  double k = 1.0 - eta * eta * (1.0 - cosI * cosI);  // > 0: no total reflection entering water
  return eta * d + (eta * cosI - std::sqrt(k)) * n;
}

// A fisheye sees up to its horizon and past it (a 180-degree lens looking down): its rays that
// pass within kFisheyeReachDeg of the nadir are taken as they are, the others at that angle
// in their own azimuth, so its footprint reaches tan(75 deg) = 3.7 times its height out.
constexpr double kFisheyeReachDeg = 75;
glm::dvec3 withinFisheyeReach(const glm::dvec3& d) {
  const double reach = kFisheyeReachDeg * M_PI / 180;
  const glm::dvec2 across(d.x, d.y);
  if (d.z <= -std::cos(reach) || !(glm::length(across) > 0)) return d;
  const glm::dvec2 azimuth = across / glm::length(across);
  return glm::dvec3(azimuth * std::sin(reach), -std::cos(reach));
}

}  // namespace

std::vector<glm::dvec3> footprintOnPlane(const Camera& c, double h, std::vector<glm::dvec3>* directions) {
  if (c.width <= 0 || c.height <= 0 || !(c.fx > 0) || !(c.fy > 0)) fail("scene bounds: a camera has no valid image size or focal length");
  glm::dvec3 o = c.position();
  if (!(o.z > h))
    fail("scene bounds: a camera at z = " + std::to_string(o.z) + " is not above the water plane z = " + std::to_string(h));
  const double W = c.width, H = c.height;
  std::vector<glm::dvec3> hits;
  const double uv[5][2] = {{0, 0}, {W, 0}, {0, H}, {W, H}, {0.5 * W, 0.5 * H}};
  for (const auto& p : uv) {
    glm::dvec3 d = c.rayDirection(p[0], p[1]);
    if (c.lens.kind == LensKind::Fisheye) d = withinFisheyeReach(d);
    if (!(d.z < -1e-6))
      fail("scene bounds: a camera at (" + std::to_string(o.x) + ", " + std::to_string(o.y) + ", " + std::to_string(o.z) +
           ") sees above the water plane's horizon; give the surface domain and Gaussian box in water.json");
    hits.push_back(o + d * ((h - o.z) / d.z));
    if (directions) directions->push_back(d);
  }
  return hits;
}

Rect surfaceDomainFromCameras(const std::vector<Camera>& cameras, double h, double margin) {
  if (cameras.empty()) fail("scene bounds: no cameras");
  Rect r{INFINITY, INFINITY, -INFINITY, -INFINITY};
  for (const auto& c : cameras)
    for (const auto& p : footprintOnPlane(c, h)) {
      r.xMin = std::min(r.xMin, p.x);
      r.yMin = std::min(r.yMin, p.y);
      r.xMax = std::max(r.xMax, p.x);
      r.yMax = std::max(r.yMax, p.y);
    }
  double mx = margin * (r.xMax - r.xMin), my = margin * (r.yMax - r.yMin);
  return {r.xMin - mx, r.yMin - my, r.xMax + mx, r.yMax + my};
}

Box gaussianBoxFromRefractedFrusta(const std::vector<Camera>& cameras, double h, double ior, double depth) {
  if (cameras.empty()) fail("scene bounds: no cameras");
  if (!(ior >= 1.0) || !(depth > 0)) fail("scene bounds: need ior >= 1 and a positive depth");
  Box b{glm::dvec3(INFINITY), glm::dvec3(-INFINITY)};
  auto grow = [&](const glm::dvec3& p) {
    b.min = glm::min(b.min, p);
    b.max = glm::max(b.max, p);
  };
  for (const auto& c : cameras) {
    std::vector<glm::dvec3> dirs;
    auto hits = footprintOnPlane(c, h, &dirs);
    for (size_t i = 0; i < hits.size(); i++) {
      glm::dvec3 w = refractDown(dirs[i], ior);  // w.z < 0 since dirs[i].z < 0
      grow(hits[i]);
      grow(hits[i] + w * (-depth / w.z));
    }
  }
  return b;
}

double estimateWaterDepth(const std::vector<View>& views, double h, double ior) {
  if (views.empty()) fail("scene bounds: no views");
  double deepest = 0, heightSum = 0;
  for (const auto& v : views) {
    const Camera& c = v.camera;
    heightSum += c.position().z - h;
    if (v.farBound > 0) {
      // the far bound along the view axis (-back), below the plane
      double z = c.position().z - v.farBound * c.back().z;
      deepest = std::max(deepest, h - z);
    }
  }
  if (deepest > 0) return ior * deepest;
  double mean = heightSum / double(views.size());
  if (!(mean > 0)) fail("scene bounds: the cameras are not above the water plane");
  return mean;
}

double sceneExtent(const std::vector<Camera>& cameras) {
  if (cameras.empty()) fail("scene bounds: no cameras");
  glm::dvec3 mean(0);
  for (const auto& c : cameras) mean += c.position();
  mean /= double(cameras.size());
  double radius = 0;
  for (const auto& c : cameras) radius = std::max(radius, glm::length(c.position() - mean));
  return 1.1 * radius;
}

}  // namespace refrax
