#include "engine/loss/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "engine/base/error.h"
#include "engine/reference/image_loss_ref.h"

namespace refrax {
namespace {

void checkSameShape(const Image& a, const Image& b, const char* metric) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.pixels.empty() ||
      a.pixels.size() != size_t(a.width) * a.height * a.channels || b.pixels.size() != a.pixels.size())
    fail(std::string(metric) + ": images differ in shape (" + std::to_string(a.width) + "x" + std::to_string(a.height) + "x" +
         std::to_string(a.channels) + " against " + std::to_string(b.width) + "x" + std::to_string(b.height) + "x" +
         std::to_string(b.channels) + ")");
}

// A mask of the image's size with some pixel counting, or none.
void checkMask(const Image& image, const Image& mask, const char* metric) {
  if (mask.pixels.empty()) return;
  if (mask.width != image.width || mask.height != image.height || mask.channels != 1 || mask.pixels.size() != size_t(mask.width) * mask.height)
    fail(std::string(metric) + ": the mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) + "x" +
         std::to_string(mask.channels) + ", the image " + std::to_string(image.width) + "x" + std::to_string(image.height) + " (one channel needed)");
  if (std::none_of(mask.pixels.begin(), mask.pixels.end(), [](float w) { return w > 0; }))
    fail(std::string(metric) + ": the mask leaves no pixel to measure");
}
double maskAt(const Image& mask, size_t pixel) { return mask.pixels.empty() ? 1.0 : double(mask.pixels[pixel]); }

std::vector<double> toDouble(const std::vector<float>& v) { return std::vector<double>(v.begin(), v.end()); }

// Closest point of the bilinear patch over cell (i, j) to p: squared distance.
double closestInCell(const HeightGrid& g, int i, int j, const glm::dvec3& p) {
  const double hx = (g.xMax - g.xMin) / (g.nx - 1), hy = (g.yMax - g.yMin) / (g.ny - 1);
  const double x0 = g.xMin + i * hx, y0 = g.yMin + j * hy;
  const double z00 = g.heights[size_t(j) * g.nx + i], z10 = g.heights[size_t(j) * g.nx + i + 1];
  const double z01 = g.heights[size_t(j + 1) * g.nx + i], z11 = g.heights[size_t(j + 1) * g.nx + i + 1];
  auto dist2 = [&](double u, double v) {
    double z = z00 * (1 - u) * (1 - v) + z10 * u * (1 - v) + z01 * (1 - u) * v + z11 * u * v;
    double dx = x0 + u * hx - p.x, dy = y0 + v * hy - p.y, dz = z - p.z;
    return dx * dx + dy * dy + dz * dz;
  };
  double best = std::numeric_limits<double>::infinity();
  // a few starts (the patch can have more than one local minimum), then alternate exact
  // minimisations: for fixed v, x and z are linear in u, so the squared distance is a parabola.
  for (double u0 : {0.0, 0.5, 1.0})
    for (double v0 : {0.0, 0.5, 1.0}) {
      double u = u0, v = v0, prev = dist2(u, v);
      for (int it = 0; it < 200; it++) {
        {  // u: z = a + b u
          double a = z00 * (1 - v) + z01 * v, b = (z10 - z00) * (1 - v) + (z11 - z01) * v;
          double num = -(hx * (x0 - p.x) + b * (a - p.z)), den = hx * hx + b * b;
          u = std::clamp(num / den, 0.0, 1.0);
        }
        {  // v: z = a + b v
          double a = z00 * (1 - u) + z10 * u, b = (z01 - z00) * (1 - u) + (z11 - z10) * u;
          double num = -(hy * (y0 - p.y) + b * (a - p.z)), den = hy * hy + b * b;
          v = std::clamp(num / den, 0.0, 1.0);
        }
        double d = dist2(u, v);
        bool settled = prev - d <= 1e-15 * (prev + 1e-300);
        prev = d;
        if (settled) break;
      }
      best = std::min(best, prev);
    }
  return best;
}

}  // namespace

double psnr(const Image& a, const Image& b, const Image& mask) {
  checkSameShape(a, b, "PSNR");
  checkMask(a, mask, "PSNR");
  double sum = 0, counted = 0;
  for (size_t i = 0; i < a.pixels.size(); i++) {
    const double w = maskAt(mask, i / size_t(a.channels));
    double d = double(a.pixels[i]) - double(b.pixels[i]);
    sum += w * d * d;
    counted += w;
  }
  double mse = sum / counted;
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
}

double ssim(const Image& a, const Image& b, const Image& mask) {
  checkSameShape(a, b, "SSIM");
  checkMask(a, mask, "SSIM");
  if (mask.pixels.empty()) return ref::ssim(toDouble(a.pixels), toDouble(b.pixels), a.width, a.height, a.channels);
  // Windows over the counted pixels only: a masked-out pixel (the rim, a person) changes no score.
  const std::vector<double> map = ref::maskedSsimMap(toDouble(a.pixels), toDouble(b.pixels), toDouble(mask.pixels), a.width, a.height, a.channels);
  double sum = 0, counted = 0;
  for (size_t i = 0; i < map.size(); i++) {
    const double w = maskAt(mask, i / size_t(a.channels));
    sum += w * map[i];
    counted += w;
  }
  return sum / counted;
}

void validateHeightGrid(const HeightGrid& g) {
  if (g.nx < 2 || g.ny < 2) fail("height grid: needs at least 2x2 samples, has " + std::to_string(g.nx) + "x" + std::to_string(g.ny));
  if (!(g.xMax > g.xMin) || !(g.yMax > g.yMin)) fail("height grid: empty domain");
  if (g.heights.size() != size_t(g.nx) * g.ny)
    fail("height grid: " + std::to_string(g.heights.size()) + " heights for a " + std::to_string(g.nx) + "x" + std::to_string(g.ny) + " grid");
  for (double h : g.heights)
    if (!std::isfinite(h)) fail("height grid: a height is not finite");
}

double sampleHeight(const HeightGrid& g, double x, double y) {
  double fx = std::clamp((x - g.xMin) / (g.xMax - g.xMin), 0.0, 1.0) * (g.nx - 1);
  double fy = std::clamp((y - g.yMin) / (g.yMax - g.yMin), 0.0, 1.0) * (g.ny - 1);
  int i = std::min(int(fx), g.nx - 2), j = std::min(int(fy), g.ny - 2);
  double u = fx - i, v = fy - j;
  const auto& h = g.heights;
  return h[size_t(j) * g.nx + i] * (1 - u) * (1 - v) + h[size_t(j) * g.nx + i + 1] * u * (1 - v) +
         h[size_t(j + 1) * g.nx + i] * (1 - u) * v + h[size_t(j + 1) * g.nx + i + 1] * u * v;
}

double verticalDistance(const HeightGrid& g, const glm::dvec3& p) { return std::abs(p.z - sampleHeight(g, p.x, p.y)); }

double closestDistance(const HeightGrid& g, const glm::dvec3& p) {
  // Upper bound: the surface point above/below p's position clamped into the domain.
  double cx = std::clamp(p.x, g.xMin, g.xMax), cy = std::clamp(p.y, g.yMin, g.yMax);
  double bound = glm::length(p - glm::dvec3(cx, cy, sampleHeight(g, cx, cy)));
  const double hx = (g.xMax - g.xMin) / (g.nx - 1), hy = (g.yMax - g.yMin) / (g.ny - 1);
  int i0 = std::max(0, int(std::floor((p.x - bound - g.xMin) / hx)));
  int i1 = std::min(g.nx - 2, int(std::floor((p.x + bound - g.xMin) / hx)));
  int j0 = std::max(0, int(std::floor((p.y - bound - g.yMin) / hy)));
  int j1 = std::min(g.ny - 2, int(std::floor((p.y + bound - g.yMin) / hy)));
  double best = bound * bound;
  for (int j = j0; j <= j1; j++)
    for (int i = i0; i <= i1; i++) {
      // skip cells whose xy-rectangle is already farther than the best distance
      double dx = std::max({0.0, g.xMin + i * hx - p.x, p.x - (g.xMin + (i + 1) * hx)});
      double dy = std::max({0.0, g.yMin + j * hy - p.y, p.y - (g.yMin + (j + 1) * hy)});
      if (dx * dx + dy * dy >= best) continue;
      best = std::min(best, closestInCell(g, i, j, p));
    }
  return std::sqrt(best);
}

std::optional<double> surfaceRmse(const HeightGrid& g, const std::vector<glm::dvec3>& points) {
  validateHeightGrid(g);
  if (points.empty()) return std::nullopt;
  double sum = 0;
  for (const auto& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) fail("surface RMSE: a surface point is not finite");
    double d = closestDistance(g, p);
    sum += d * d;
  }
  return std::sqrt(sum / double(points.size()));
}

double surfaceCorrelation(const HeightGrid& g, const std::vector<glm::dvec3>& points) {
  validateHeightGrid(g);
  const double n = double(points.size());
  if (points.size() < 2) return std::nan("");
  // Two passes (means first): the heights are centimetres on an offset of metres.
  double meanLearned = 0, meanTrue = 0;
  std::vector<double> truth(points.size());
  for (size_t i = 0; i < points.size(); i++) {
    truth[i] = sampleHeight(g, points[i].x, points[i].y);
    meanLearned += points[i].z / n;
    meanTrue += truth[i] / n;
  }
  double cross = 0, learned2 = 0, true2 = 0;
  for (size_t i = 0; i < points.size(); i++) {
    const double a = points[i].z - meanLearned, b = truth[i] - meanTrue;
    cross += a * b;
    learned2 += a * a;
    true2 += b * b;
  }
  if (!(learned2 > 0) || !(true2 > 0)) return std::nan("");
  return cross / std::sqrt(learned2 * true2);
}

}  // namespace refrax
