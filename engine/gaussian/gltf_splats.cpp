#include "engine/gaussian/gltf_splats.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/quaternion.hpp>

#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"

namespace refrax {
namespace {

// Solves A x = b for an n x n row-major A (Gaussian elimination with partial pivoting).
std::vector<double> solve(std::vector<double> a, std::vector<double> b, size_t n) {
  for (size_t c = 0; c < n; c++) {
    size_t p = c;
    for (size_t r = c + 1; r < n; r++)
      if (std::abs(a[r * n + c]) > std::abs(a[p * n + c])) p = r;
    for (size_t k = 0; k < n; k++) std::swap(a[c * n + k], a[p * n + k]);
    std::swap(b[c], b[p]);
    for (size_t r = 0; r < n; r++) {
      if (r == c) continue;
      const double f = a[r * n + c] / a[c * n + c];
      for (size_t k = c; k < n; k++) a[r * n + k] -= f * a[c * n + k];
      b[r] -= f * b[c];
    }
  }
  for (size_t c = 0; c < n; c++) b[c] /= a[c * n + c];
  return b;
}

}  // namespace

std::vector<double> shRotationToGltf(uint32_t l) {
  // A degree's basis functions span a space every rotation maps to itself, so T is exact:
  // found by least squares over directions spread on the sphere, Y_l(d) T = Y_l(R^-1 d).
  const uint32_t n = 2 * l + 1, first = l * l;
  constexpr int kDirections = 64;
  std::vector<double> ata(n * n, 0.0), atb(n * n, 0.0);
  for (int i = 0; i < kDirections; i++) {
    // a Fibonacci spiral
    const double z = 1.0 - (2.0 * i + 1.0) / kDirections, r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.399963229728653 * i;
    const glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);  // glTF axes
    const glm::dvec3 back(d.x, -d.z, d.y);                         // R^-1 d: Refrax (x, y, z) = glTF (x, -z, y)
    for (uint32_t j = 0; j < n; j++)
      for (uint32_t k = 0; k < n; k++) {
        ata[j * n + k] += f64::shBasis(first + j, d) * f64::shBasis(first + k, d);
        atb[j * n + k] += f64::shBasis(first + j, d) * f64::shBasis(first + k, back);
      }
  }
  std::vector<double> t(n * n);
  for (uint32_t k = 0; k < n; k++) {  // column k of T
    std::vector<double> column(n);
    for (uint32_t j = 0; j < n; j++) column[j] = atb[j * n + k];
    column = solve(ata, column, n);
    for (uint32_t j = 0; j < n; j++) t[j * n + k] = column[j];
  }
  return t;
}

GltfSplats gltfSplatsFrom(const GaussianSet& set, uint32_t shDegree) {
  if (shDegree > 3) fail("KHR_gaussian_splatting holds SH up to degree 3, not " + std::to_string(shDegree));
  validateGaussians(set, "the glTF export");
  GltfSplats g;
  g.count = set.count();
  g.shDegree = shDegree;
  const uint32_t coefficients = (shDegree + 1) * (shDegree + 1);
  g.positions.resize(3 * g.count);
  g.rotations.resize(4 * g.count);
  g.scales.resize(3 * g.count);
  g.opacities.resize(g.count);
  g.colors.resize(4 * g.count);
  g.sh.assign(coefficients, std::vector<float>(3 * g.count));
  std::vector<std::vector<double>> turn(shDegree + 1);
  for (uint32_t l = 0; l <= shDegree; l++) turn[l] = shRotationToGltf(l);
  const glm::dquat axes = glm::angleAxis(-0.5 * M_PI, glm::dvec3(1, 0, 0));  // Refrax -> glTF
  for (size_t i = 0; i < g.count; i++) {
    const float* p = set.at(i);
    toGltfAxes(p + f32::kGaussMean, &g.positions[3 * i]);
    const glm::dquat q = axes * glm::normalize(glm::dquat(p[f32::kGaussRotation], p[f32::kGaussRotation + 1], p[f32::kGaussRotation + 2],
                                                          p[f32::kGaussRotation + 3]));
    g.rotations[4 * i] = float(q.x), g.rotations[4 * i + 1] = float(q.y), g.rotations[4 * i + 2] = float(q.z), g.rotations[4 * i + 3] = float(q.w);
    for (int a = 0; a < 3; a++) g.scales[3 * i + a] = std::exp(p[f32::kGaussLogScale + a]);
    g.opacities[i] = float(f64::sigmoidOf(p[f32::kGaussLogitDensity]));
    for (uint32_t l = 0; l <= shDegree; l++) {
      const uint32_t n = 2 * l + 1, first = l * l;
      for (uint32_t j = 0; j < n; j++)
        for (int c = 0; c < 3; c++) {
          double v = 0;
          for (uint32_t k = 0; k < n; k++) v += turn[l][j * n + k] * p[f32::kGaussSH + 3 * (first + k) + c];
          g.sh[first + j][3 * i + c] = float(v);
        }
    }
    for (int c = 0; c < 3; c++)
      g.colors[4 * i + c] = float(std::clamp(0.2820947917738781 * p[f32::kGaussSH + c] + 0.5, 0.0, 1.0));
    g.colors[4 * i + 3] = g.opacities[i];
  }
  return g;
}

}  // namespace refrax
