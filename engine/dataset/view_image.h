#pragma once
// Loading one view's image for the dataset loaders: decode, check its size, make it RGB
// (grey replicated, alpha composited on the background: rgb * a + background * (1 - a)).
#include <string>

#include <glm/glm.hpp>

#include "engine/io/image_io.h"

namespace refrax {

// expectWidth/Height 0: any size. `where` names the file that referenced the image.
Image loadViewImage(const std::string& path, int expectWidth, int expectHeight, const glm::dvec3& background, const std::string& where);

// A view's pixel mask, when it has one: `masksPath` (the masks/ folder mirroring the image
// folder), else the image's path with "_mask.png" for its extension (RefracGS's convention).
// A pixel counts where the mask's first channel is above one half (grey or red; masks are
// often JPEG-noisy or anti-aliased), so the result is 1 or 0 per pixel (one channel). An
// empty Image when neither file exists; refrax::Error naming the mask when it is not the
// image's size or leaves no pixel that counts.
Image loadViewMask(const std::string& imagePath, const std::string& masksPath, int width, int height, const std::string& where);

// The image's mean over blocks of factor x factor pixels (the remainder columns and rows
// cropped), as downscaledCamera's pixels see it: a coarser level of an image pyramid.
Image boxDownscaled(const Image& image, int factor);

// The path with its extension replaced by `ending` ("a/b.jpg", "_mask.png" -> "a/b_mask.png").
std::string replaceExtension(const std::string& path, const std::string& ending);

}  // namespace refrax
