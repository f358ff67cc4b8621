#pragma once
// An end-to-end check of the water's gradient in training: the backward's derivative of one
// batch's image loss along a direction in the height MLP's weights, against central
// differences of the forward's loss (camera rays -> water -> Gaussians -> loss, every stage
// re-run). Each stage has its own check against finite differences in the tests; this one
// checks their chain, with the batch, Gaussians and schedule of a real run (`refrax gradcheck`).
// The loss is piecewise smooth (the triangle a ray hits, the Gaussians it blends, the
// leaky-ReLU kinks), so the differences are taken at several step sizes.
#include <vector>

#include "engine/train/train_session.h"

namespace refrax {

struct SurfaceGradientCheck {
  double loss = 0;         // the batch's image loss at the session's weights
  double gradientNorm = 0; // |dL/dweights| from the backward
  double slope = 0;        // dL/dweights . direction, from the backward
  std::vector<double> steps;              // step sizes along the unit direction (weight units)
  std::vector<double> centralDifferences; // (L(w + h d) - L(w - h d)) / 2h for each step h
  std::vector<double> heightChanges;      // the largest |height change| of the coarse grid at +h, m
  // The Gaussian backward's dL/d(refracted ray) times the rays' central difference: the loss
  // change the Gaussian side predicts from how the water actually moved the rays. Near the
  // central difference, not the slope: the surface backward is off; near the slope, not the
  // central difference: the Gaussian side or the loss is.
  std::vector<double> rayPredictions;
};

// Along `direction` (normalised here; empty: the backward's own gradient, so slope is its
// norm). Needs the MLP water (the refraction model). The session's weights, surface, Gaussians
// and pending surface-gradient sum are as before when it returns (the per-step scratch is not);
// its rng and view order are untouched.
SurfaceGradientCheck checkSurfaceGradient(TrainSession& session, const StepBatch& batch, std::vector<double> direction,
                                          const std::vector<double>& steps);

}  // namespace refrax
