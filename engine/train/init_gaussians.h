#pragma once
// The initial Gaussians (docs/method.md §1.6): means uniform in a box under the water, identity
// rotation, density `density`, isotropic log scale log(d) with d the distance to the nearest
// other mean (3DGS initialises from nearest neighbours too), a random colour (SH DC) and
// zero higher SH bands.
#include <random>

#include "engine/gaussian/gaussians.h"
#include "engine/train/plane_sweep.h"

namespace refrax {

GaussianSet initialGaussians(std::mt19937& rng, size_t count, const double boxMin[3], const double boxMax[3], double density);
// The same, but (x, y) uniform in the box and z the depth map's there, coloured with its
// colour (--init-depth sweep); where the map has no depth, as initialGaussians.
GaussianSet initialGaussiansOnDepth(std::mt19937& rng, size_t count, const double boxMin[3], const double boxMax[3], double density,
                                    const DepthMap& depth);
// Distance from each point to its nearest other point (sweep over points sorted by x);
// 0 where points coincide; a lone point gets the box diagonal it is given.
std::vector<double> nearestNeighbourDistances(const std::vector<double>& xyz, double fallback);

}  // namespace refrax
