#pragma once
// Adam on the host for parameter tables: rows of rowWidth floats, each column range its own
// parameter group with its own learning rate and step count (as torch.optim.Adam with one
// param group per tensor). The Gaussians are such a table (kGaussianFloats per Gaussian:
// mean, rotation, scale, density, SH; engine/gaussian/gaussian_adam.h makes it),
// and the flat-water model's height a table of one row and one column. The update is the
// device's (shaders/include/adam_update.glsl), in float as the shader computes it; on lavapipe
// the "device" memory is host memory and this costs about as much as the shader would.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/optim/adam.h"

namespace refrax {

struct AdamColumns {
  std::string name;               // e.g. as in referenceLearningRates
  uint32_t first = 0, width = 0;  // columns [first, first + width) of every row
  LearningRateSchedule lr;
  int step = 0;  // updates taken (the bias correction's t); reset with the group's moments
};

struct TableAdam {
  uint32_t rowWidth = 1;
  std::vector<AdamColumns> groups;
  std::vector<float> m, v;  // rowWidth floats per row, as the table
};

// Zero moments for `rows` rows.
TableAdam createTableAdam(uint32_t rowWidth, std::vector<AdamColumns> groups, size_t rows);
// One update of every group from `grads` (the table's layout; non-finite gradients count as
// 0, so one bad ray cannot poison a parameter).
void tableAdamStep(TableAdam& adam, std::vector<float>& params, const std::vector<float>& grads, const AdamSettings& settings = {});
// The learning rate the named group's last update took (fails for an unknown name).
double groupLearningRate(const TableAdam& adam, const std::string& name);
// Zero moments (and step) of one group, as 3DGS's replacement of the density tensor at a reset.
void resetAdamColumns(TableAdam& adam, const std::string& name);
// Rows for a rebuilt table (densification): row i from old row sourceRow[i], or zero moments
// for kNewRow (engine/optim/adam.h).
void remapTableAdamRows(TableAdam& adam, const std::vector<uint32_t>& sourceRow);

}  // namespace refrax
