#pragma once
// Evaluation metrics on the CPU in double: image PSNR and SSIM (the training loss's SSIM:
// 11x11 Gaussian window, sigma 1.5, zero padding as 3DGS, engine/reference/image_loss_ref.h),
// and the surface error the paper reports: RMSE of the distance from each recovered surface
// point (a test ray's hit on the water) to the ground-truth surface.
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "engine/io/image_io.h"

namespace refrax {

// 10 log10(1 / MSE) over every pixel and channel (data range 1); +infinity for equal images.
// Both images must have the same size and channel count (refrax::Error otherwise).
// With a mask (one channel, the images' size; engine/dataset/dataset.h View::mask), over the
// pixels whose mask is nonzero only: PSNR from their squared error, SSIM the mask-weighted
// mean of the SSIM map at them, each window's statistics over its counted pixels
// (ref::maskedSsimMap), so no masked-out pixel moves either. An empty mask: every pixel. refrax::Error when
// the mask's size differs or no pixel counts.
double psnr(const Image& a, const Image& b, const Image& mask = {});
double ssim(const Image& a, const Image& b, const Image& mask = {});

// A height field z = H(x, y) given on a regular grid over [xMin, xMax] x [yMin, yMax]:
// heights[j * nx + i] at x = xMin + i (xMax - xMin) / (nx - 1), y likewise; bilinear between.
struct HeightGrid {
  int nx = 0, ny = 0;
  double xMin = 0, yMin = 0, xMax = 1, yMax = 1;
  std::vector<double> heights;
};
// Throws refrax::Error when the grid is smaller than 2x2, its domain empty, its size does
// not match, or a height is not finite.
void validateHeightGrid(const HeightGrid& grid);
// H at (x, y), the point clamped into the domain.
double sampleHeight(const HeightGrid& grid, double x, double y);
// |p.z - H(p.x, p.y)|: the vertical distance, an upper bound of the true distance.
double verticalDistance(const HeightGrid& grid, const glm::dvec3& p);
// Euclidean distance from p to the closest point of the bilinear surface (over the domain
// only: the surface is not extended past its edges). Local search: every cell within the
// vertical distance of p, the closest point of each cell's bilinear patch found by exact
// alternating minimisation (the squared distance is quadratic in u for fixed v and vice versa).
double closestDistance(const HeightGrid& grid, const glm::dvec3& p);
// sqrt(mean closestDistance^2) over the points; none for no points (no error was measured,
// which 0 would report as a perfect surface).
std::optional<double> surfaceRmse(const HeightGrid& grid, const std::vector<glm::dvec3>& points);
// Pearson's correlation of the points' heights p.z with the true heights H(p.x, p.y) under
// them: 1 for the true waves at any amplitude, about 0 for flat or unrelated water, negative
// for waves learned upside down (a full-size run's surface was, at -0.9, which the RMSE alone
// cannot tell from noise). NaN with fewer than two points or a constant side.
double surfaceCorrelation(const HeightGrid& grid, const std::vector<glm::dvec3>& points);

}  // namespace refrax
