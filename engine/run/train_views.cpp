#include "engine/run/train_views.h"

#include <cmath>
#include <string>

#include "engine/base/error.h"

namespace refrax {

std::vector<size_t> spreadViewIndices(size_t available, size_t count) {
  if (count < 1 || count > available)
    fail("--train-views must be between 1 and " + std::to_string(available) + " (the training views of the dataset), got " +
         std::to_string(count));
  std::vector<size_t> indices;
  for (size_t i = 0; i < count; i++)
    indices.push_back(count == 1 ? 0 : size_t(std::lround(double(i) * double(available - 1) / double(count - 1))));
  return indices;
}

void keepTrainViews(Dataset& dataset, size_t count) {
  if (count == 0) return;
  const std::vector<View>& all = dataset.split("train");
  std::vector<View> kept;
  for (size_t i : spreadViewIndices(all.size(), count)) kept.push_back(all[i]);
  dataset.splits["train"] = std::move(kept);
}

}  // namespace refrax
