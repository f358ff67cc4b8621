#pragma once
// The initial Gaussians (docs/method.md §1.6): means uniform in a box under the water, identity
// rotation, density `density`, isotropic log scale log(d) with d the distance to the nearest
// other mean (3DGS initialises from nearest neighbours too), a random colour (SH DC) and
// zero higher SH bands.
#include <random>

#include "engine/dataset/dataset.h"
#include "engine/gaussian/gaussians.h"
#include "engine/train/plane_sweep.h"

namespace refrax {

GaussianSet initialGaussians(std::mt19937& rng, size_t count, const double boxMin[3], const double boxMax[3], double density);
// The same, but (x, y) uniform in the box and z the depth map's there, coloured with its
// colour (--init-depth sweep); where the map has no depth, as initialGaussians.
GaussianSet initialGaussiansOnDepth(std::mt19937& rng, size_t count, const double boxMin[3], const double boxMax[3], double density,
                                    const DepthMap& depth);
// --init-points: Gaussians at a dataset's sparse points (COLMAP's), as 3DGS starts, for the
// scene under the water. Points above waterHeight (the dry rim, the banks) are dropped: the
// model holds only what lies under the water. Points under it were triangulated along
// straight rays, so they sit where refraction shows them, shallower than they are; each is
// moved down to its paraxial true depth through the flat water, (waterHeight - z) * ior
// below the surface (the apparent-depth rule, exact for rays near the vertical). At most
// `count` of them (a random subset when there are more); `used` says how many.
GaussianSet initialGaussiansAtPoints(std::mt19937& rng, size_t count, const std::vector<SparsePoint>& points, double waterHeight, double ior,
                                     const double boxMin[3], const double boxMax[3], double density, size_t& used);

// Whether a sparse point lies under the water for --init-points: below waterHeight by more
// than rounding (a rim at the water's level is dry, however the loader's frame rounds it).
bool underWater(const SparsePoint& point, double waterHeight);

// Distance from each point to its nearest other point (sweep over points sorted by x);
// 0 where points coincide; a lone point gets the box diagonal it is given.
std::vector<double> nearestNeighbourDistances(const std::vector<double>& xyz, double fallback);

}  // namespace refrax
