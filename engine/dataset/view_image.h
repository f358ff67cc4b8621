#pragma once
// Loading one view's image for the dataset loaders: decode, check its size, make it RGB
// (grey replicated, alpha composited on the background: rgb * a + background * (1 - a)).
#include <string>

#include <glm/glm.hpp>

#include "engine/io/image_io.h"

namespace refrax {

// expectWidth/Height 0: any size. `where` names the file that referenced the image.
Image loadViewImage(const std::string& path, int expectWidth, int expectHeight, const glm::dvec3& background, const std::string& where);

}  // namespace refrax
