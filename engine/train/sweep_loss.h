#pragma once
// A loss on the water that does not pass through the Gaussians (--sweep-loss): each training
// view's rays, refracted by the learned water, against the colour the views agree on where
// they land. A plane sweep through the same water (plane_sweep.h) gives per cell of the floor
// its depth and the views' mean colour there, T; a ray lands where it meets its cell's depth
// plane, x(origin, dir), and costs |I - T(x)|^2 (T bilinear between cell centres, held fixed).
// Why: the Gaussians absorb the warp of a water learned at part of its height, so the images
// pull the water little; the sweep's agreement does not pass through them and is least at the
// true water (docs/experiments/2026-12-05-water-valley.md). With T the views' mean, the sum over
// views is their colour variance, and its gradient in the water at fixed T is the variance's
// (T minimises it).
#include <cstddef>
#include <vector>

#include "engine/train/plane_sweep.h"
#include "engine/trace/rays.h"

namespace refrax {

// Adds weight * dLoss/d(origin, dir) of each ray of `view` into grads (one per ray) for
// Loss = sum over the rays that land on the map of sum_c (I_c - T_c(x))^2; returns that loss
// (unweighted) and the rays it counted in `used`. A ray lands on the plane of the cell it meets
// at the map's median depth, then on the plane of the cell it meets there (its depth held
// fixed); a ray that does not point down, starts under that plane, or lands where a cell of
// its bilinear sample has no depth counts for nothing.
double sweepTextureLoss(const SweepView& view, const DepthMap& map, double weight, std::vector<GpuRayGrad>& grads, size_t& used);

// The views' agreed colour per cell at the map's depths, view by view (landing as above): each
// view's mean colour in a cell, then the mean over the views. Why: between full sweeps, T follows
// the water at the sweep's depths for the cost of one pass over the rays, not one per plane.
struct AgreedColours {
  std::vector<double> viewSums;  // per cell: r, g, b, rays of the view being added
  std::vector<double> sums;      // per cell: the views' mean r, g, b summed, the views counted
  std::vector<uint32_t> touched;
};
void addViewColours(const SweepView& view, const DepthMap& map, AgreedColours& colours);
// map.rgb = the agreed colours where at least minViews views reached the cell; elsewhere unchanged.
void setAgreedColours(DepthMap& map, const AgreedColours& colours, uint32_t minViews);

}  // namespace refrax
