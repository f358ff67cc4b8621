#include "engine/gaussian/gaussian_adam.h"

#include "engine/gaussian/gaussian_math.h"
#include "engine/gaussian/gaussians.h"

namespace refrax {

TableAdam createGaussianAdam(double extent, int lrSteps, size_t count) {
  struct Columns {
    const char* name;
    uint32_t first, width;
  };
  const Columns columns[] = {{"position", f32::kGaussMean, 3},        {"rotation", f32::kGaussRotation, 4},
                             {"scale", f32::kGaussLogScale, 3},       {"density", f32::kGaussLogitDensity, 1},
                             {"sh_dc", f32::kGaussSH, 3},             {"sh_rest", f32::kGaussSH + 3, 45}};
  std::vector<AdamColumns> groups;
  for (const auto& c : columns) {
    AdamColumns g;
    g.name = c.name;
    g.first = c.first;
    g.width = c.width;
    g.lr = referenceLearningRate(c.name, extent);
    g.lr.steps = lrSteps;
    groups.push_back(g);
  }
  return createTableAdam(kGaussianFloats, std::move(groups), count);
}

}  // namespace refrax
