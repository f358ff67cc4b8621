#pragma once
// The Gaussians' Adam: a parameter table (engine/optim/table_adam.h) of kGaussianFloats per
// Gaussian, one group per parameter with the reference learning rates
// (engine/optim/adam.h referenceLearningRate).
#include <cstddef>

#include "engine/optim/table_adam.h"

namespace refrax {

// Groups position, rotation, scale, density, sh_dc, sh_rest with the reference rates for
// `extent`, the decaying ones over `lrSteps`; zero moments for `count` Gaussians.
TableAdam createGaussianAdam(double extent, int lrSteps, size_t count);

}  // namespace refrax
