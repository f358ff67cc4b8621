#pragma once
// --train-views N (number-of-views sweeps): a training run that sees only N of the dataset's
// training views, spread evenly over them in their file order (the first and the last always
// among them, so two views are the widest pair), the test split untouched.
#include <cstddef>
#include <vector>

#include "engine/dataset/dataset.h"

namespace refrax {

// Indices of `count` of `available` views: round(i (available - 1) / (count - 1)), i = 0..count-1
// (count 1: the first). refrax::Error when count < 1 or count > available.
std::vector<size_t> spreadViewIndices(size_t available, size_t count);
// Keeps those views of the "train" split (count 0: all of them).
void keepTrainViews(Dataset& dataset, size_t count);

}  // namespace refrax
