#pragma once
// The command-line options every dataset-reading command shares (train, evaluate, inspect),
// turned into DatasetOptions; they override the dataset's water.json.
#include <vector>

#include "engine/dataset/dataset.h"
#include "engine/app/cli.h"

namespace refrax {

std::vector<cli::Option> datasetOptions();
DatasetOptions datasetOptionsFrom(const cli::Args& args);
// `count` comma-separated finite numbers (0: any number, at least one), or one clear error
// naming the option `what` and the expected `shape`.
std::vector<double> parseNumbers(const std::string& text, size_t count, const std::string& what, const std::string& shape);
// "xmin,ymin,xmax,ymax" (refrax::Error naming `what` otherwise).
Rect parseRect(const std::string& text, const std::string& what);

}  // namespace refrax
