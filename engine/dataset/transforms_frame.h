#pragma once
// One frame of a transforms.json (NeRF/Blender, instant-ngp, nerfstudio) as a view: its image,
// mask, pose as written and camera (intrinsics and lens, the frame's own or the file's), with
// the conventions in engine/dataset/dataset.h. Shared by the Blender and nerfstudio loaders.
#include <string>

#include "engine/dataset/dataset.h"
#include "engine/io/json_io.h"

namespace refrax {

// maskPathField: the frame's mask_path names its mask (nerfstudio's); otherwise masks/<file_path>.png
// or <image>_mask.png. refrax::Error naming `where` (the file and frame) on anything malformed.
View loadTransformsFrame(const std::string& folder, const nlohmann::json& frame, const nlohmann::json& top, const std::string& where,
                         const DatasetOptions& options, bool maskPathField);

}  // namespace refrax
