#include "engine/train/init_gaussians.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "engine/gaussian/gaussian_math.h"

namespace refrax {

std::vector<double> nearestNeighbourDistances(const std::vector<double>& xyz, double fallback) {
  size_t n = xyz.size() / 3;
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t(0));
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return xyz[3 * a] < xyz[3 * b]; });
  std::vector<double> best(n, fallback * fallback);
  for (size_t r = 0; r < n; r++) {
    size_t i = order[r];
    auto visit = [&](size_t s) {
      size_t j = order[s];
      double dx = xyz[3 * j] - xyz[3 * i];
      if (dx * dx >= best[i]) return false;
      double dy = xyz[3 * j + 1] - xyz[3 * i + 1], dz = xyz[3 * j + 2] - xyz[3 * i + 2];
      best[i] = std::min(best[i], dx * dx + dy * dy + dz * dz);
      return true;
    };
    for (size_t s = r + 1; s < n && visit(s); s++) {
    }
    for (size_t s = r; s-- > 0 && visit(s);) {
    }
  }
  for (double& b : best) b = std::sqrt(b);
  return best;
}

namespace {

// Gaussians at the given means and colours (in [0, 1]), the rest as docs/method.md §1.6 initialises it.
GaussianSet gaussiansAt(const std::vector<double>& xyz, const std::vector<double>& rgb, const double boxMin[3], const double boxMax[3],
                        double density) {
  size_t count = xyz.size() / 3;
  double diagonal = std::sqrt(std::pow(boxMax[0] - boxMin[0], 2) + std::pow(boxMax[1] - boxMin[1], 2) + std::pow(boxMax[2] - boxMin[2], 2));
  std::vector<double> nn = nearestNeighbourDistances(xyz, diagonal > 0 ? diagonal : 1.0);
  GaussianSet set;
  set.params.assign(count * kGaussianFloats, 0.0f);
  float logit = float(std::log(density / (1.0 - density)));
  for (size_t i = 0; i < count; i++) {
    float* g = set.at(i);
    for (int a = 0; a < 3; a++) g[f32::kGaussMean + a] = float(xyz[3 * i + a]);
    g[f32::kGaussRotation] = 1.0f;
    float logScale = float(std::log(std::max(nn[i], 1e-7)));
    for (int a = 0; a < 3; a++) g[f32::kGaussLogScale + a] = logScale;
    g[f32::kGaussLogitDensity] = logit;
    // DC term: SH0 * c + 0.5 is the colour.
    for (int c = 0; c < 3; c++) g[f32::kGaussSH + c] = float((rgb[3 * i + c] - 0.5) / 0.28209479177387814);
  }
  return set;
}

}  // namespace

GaussianSet initialGaussians(std::mt19937& rng, size_t count, const double boxMin[3], const double boxMax[3], double density) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> xyz(count * 3), rgb(count * 3);
  for (size_t i = 0; i < count; i++)
    for (int a = 0; a < 3; a++) xyz[3 * i + a] = boxMin[a] + (boxMax[a] - boxMin[a]) * U(rng);
  for (double& c : rgb) c = U(rng);  // a random colour, uniform in [0, 1]
  return gaussiansAt(xyz, rgb, boxMin, boxMax, density);
}

GaussianSet initialGaussiansOnDepth(std::mt19937& rng, size_t count, const double boxMin[3], const double boxMax[3], double density,
                                    const DepthMap& depth) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<double> xyz(count * 3), rgb(count * 3);
  for (size_t i = 0; i < count; i++) {
    double* p = &xyz[3 * i];
    for (int a = 0; a < 3; a++) p[a] = boxMin[a] + (boxMax[a] - boxMin[a]) * U(rng);
    long cell = depth.cellAt(p[0], p[1]);
    bool known = cell >= 0 && std::isfinite(depth.z[size_t(cell)]);
    if (known) p[2] = std::clamp(depth.z[size_t(cell)], boxMin[2], boxMax[2]);
    for (int c = 0; c < 3; c++) rgb[3 * i + c] = known ? double(depth.rgb[3 * size_t(cell) + c]) : U(rng);
  }
  return gaussiansAt(xyz, rgb, boxMin, boxMax, density);
}

bool underWater(const SparsePoint& point, double waterHeight) {
  return point.position.z < waterHeight - 1e-9 * std::max(1.0, std::abs(waterHeight));
}

GaussianSet initialGaussiansAtPoints(std::mt19937& rng, size_t count, const std::vector<SparsePoint>& points, double waterHeight, double ior,
                                     const double boxMin[3], const double boxMax[3], double density, size_t& used) {
  std::vector<const SparsePoint*> under;
  for (const SparsePoint& p : points)
    if (underWater(p, waterHeight)) under.push_back(&p);
  std::shuffle(under.begin(), under.end(), rng);
  under.resize(std::min(under.size(), count));
  used = under.size();
  std::vector<double> xyz, rgb;
  for (const SparsePoint* p : under) {
    xyz.insert(xyz.end(), {p->position.x, p->position.y, waterHeight - (waterHeight - p->position.z) * ior});
    rgb.insert(rgb.end(), {p->colour.x, p->colour.y, p->colour.z});
  }
  return gaussiansAt(xyz, rgb, boxMin, boxMax, density);
}

}  // namespace refrax
