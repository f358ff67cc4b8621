#pragma once
// readJson for the dataset files, also turning nlohmann's out-of-range errors (a number such
// as 1e999 overflows while parsing; readJson only converts parse errors) into refrax::Error.
#include <string>

#include "engine/base/error.h"
#include "engine/camera/lens.h"
#include "engine/io/json_io.h"

namespace refrax {

inline nlohmann::json readDatasetJson(const std::string& path) {
  try {
    return readJson(path);
  } catch (const nlohmann::json::exception& e) {
    fail("malformed JSON in " + path + ": " + e.what());
  }
}

// A distorting lens as a transforms.json frame's camera_model, k1..k4, p1, p2 (nerfstudio's
// fields, which the Blender loader reads back); nothing for a pinhole.
inline void addTransformsLens(nlohmann::json& frame, const Lens& lens) {
  if (!lens.distorts()) return;
  const LensFields f = transformsFieldsOf(lens);
  frame["camera_model"] = f.cameraModel;
  frame["k1"] = f.k1, frame["k2"] = f.k2, frame["k3"] = f.k3, frame["k4"] = f.k4;
  frame["p1"] = f.p1, frame["p2"] = f.p2;
}

}  // namespace refrax
