#pragma once
// The water's frame for datasets whose poses come in an arbitrary frame (a COLMAP model's, a
// nerfstudio transforms.json's): up toward the cameras becomes +Z, the mean camera the
// origin, one unit the median depth of the sparse points under the cameras, and the water
// height estimated from the points (the conventions in engine/dataset/dataset.h, COLMAP 1-4).
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/dataset/dataset.h"

namespace refrax {

struct WaterFrame {
  glm::dmat3 rotation{1.0};
  double scale = 1;
  std::vector<double> pointHeights;  // the sparse points' heights above the mean camera, rotated, not scaled
};

// poses: camera-to-world in the source frame (Blender axes); points: the sparse points there.
// Sets d.normalization (source -> loaded) and adds a note naming `source` ("COLMAP's frame").
WaterFrame deriveWaterFrame(const std::vector<glm::dvec3>& points, const std::vector<glm::dmat4>& poses, const DatasetOptions& options,
                            const std::string& source, Dataset& d);
// A source camera-to-world in the loaded frame: its axes turned, its position moved and scaled.
glm::dmat4 poseInWaterFrame(const glm::dmat4& pose, const WaterFrame& f, const Dataset& d);
// water.json and the options, the height (when neither gives it) the points' 95th percentile;
// refrax::Error naming `what` (the dataset) when there are too few points to estimate it.
WaterMetadata waterInFrame(const std::string& folder, const DatasetOptions& options, const WaterFrame& f, const std::string& what, Dataset& d);

}  // namespace refrax
