#pragma once
// readJson for the dataset files, also turning nlohmann's out-of-range errors (a number such
// as 1e999 overflows while parsing; readJson only converts parse errors) into refrax::Error.
#include <string>

#include "engine/base/error.h"
#include "engine/io/json_io.h"

namespace refrax {

inline nlohmann::json readDatasetJson(const std::string& path) {
  try {
    return readJson(path);
  } catch (const nlohmann::json::exception& e) {
    fail("malformed JSON in " + path + ": " + e.what());
  }
}

}  // namespace refrax
