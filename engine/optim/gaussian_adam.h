#pragma once
// Adam for the Gaussian table on the host. The table is interleaved (kGaussianFloats per
// Gaussian: mean, rotation, scale, density, SH), and each column range is its own parameter
// group with its own learning rate (engine/optim/adam.h referenceLearningRates): the device Adam
// updates contiguous ranges only, so the table's update runs here, with torch.optim.Adam's
// formula in float as the shader computes it (engine/optim/adam.h). On lavapipe the "device"
// memory is host memory and this costs about as much as the shader would.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/optim/adam.h"
#include "engine/gaussian/gaussians.h"

namespace refrax {

struct GaussianAdamGroup {
  std::string name;  // as in referenceLearningRates
  uint32_t first = 0, width = 0;  // columns [first, first + width) of every row
  LearningRateSchedule lr;
  int step = 0;  // updates taken (the bias correction's t); reset with the group's moments
};

struct GaussianAdam {
  std::vector<GaussianAdamGroup> groups;
  std::vector<float> m, v;  // kGaussianFloats per Gaussian, as the table
};

// The six groups position, rotation, scale, density, sh_dc, sh_rest with the reference rates
// for `extent`, the decaying ones over `lrSteps`; zero moments for `count` Gaussians.
GaussianAdam createGaussianAdam(double extent, int lrSteps, size_t count);
// One update of every group from `grads` (same layout as the table; non-finite gradients
// count as 0, so one bad ray cannot poison a Gaussian).
void gaussianAdamStep(GaussianAdam& adam, GaussianSet& set, const std::vector<float>& grads, const AdamSettings& settings = {});
// Zero moments (and step) of one group, as 3DGS's replacement of the density tensor at a reset.
void resetGaussianAdamGroup(GaussianAdam& adam, const std::string& name);
// Rows for a rebuilt table (densification): row i from old row sourceRow[i], or zero moments
// for kNewRow (engine/optim/adam.h).
void remapGaussianAdamRows(GaussianAdam& adam, const std::vector<uint32_t>& sourceRow);

}  // namespace refrax
