#pragma once
// The command-line options every dataset-reading command shares (train, evaluate, inspect),
// turned into DatasetOptions; they override the dataset's water.json.
#include <vector>

#include "engine/dataset/dataset.h"
#include "trainer/cli.h"

namespace refrax {

std::vector<cli::Option> datasetOptions();
DatasetOptions datasetOptionsFrom(const cli::Args& args);
// "xmin,ymin,xmax,ymax" (refrax::Error naming `what` otherwise).
Rect parseRect(const std::string& text, const std::string& what);

}  // namespace refrax
