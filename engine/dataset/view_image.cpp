#include "engine/dataset/view_image.h"

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {

Image loadViewImage(const std::string& path, int expectWidth, int expectHeight, const glm::dvec3& background, const std::string& where) {
  if (!fileExists(path)) fail(where + ": image " + path + " does not exist");
  Image in = readPng(path);
  if ((expectWidth > 0 && in.width != expectWidth) || (expectHeight > 0 && in.height != expectHeight))
    fail(where + ": image " + path + " is " + std::to_string(in.width) + "x" + std::to_string(in.height) + ", expected " +
         std::to_string(expectWidth) + "x" + std::to_string(expectHeight));
  Image out;
  out.width = in.width;
  out.height = in.height;
  out.channels = 3;
  out.pixels.resize(size_t(in.width) * in.height * 3);
  const bool hasAlpha = in.channels == 2 || in.channels == 4;
  const int colour = in.channels >= 3 ? 3 : 1;
  for (size_t p = 0; p < size_t(in.width) * in.height; p++) {
    const float* src = &in.pixels[p * in.channels];
    float a = hasAlpha ? src[in.channels - 1] : 1.0f;
    for (int c = 0; c < 3; c++) {
      float v = src[colour == 3 ? c : 0];
      out.pixels[p * 3 + c] = hasAlpha ? float(v * a + background[c] * (1.0 - a)) : v;
    }
  }
  return out;
}

std::string replaceExtension(const std::string& path, const std::string& ending) {
  const size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
  const bool hasExtension = dot != std::string::npos && (slash == std::string::npos || dot > slash + 1);
  return (hasExtension ? path.substr(0, dot) : path) + ending;
}

Image loadViewMask(const std::string& imagePath, const std::string& masksPath, int width, int height, const std::string& where) {
  std::string path = masksPath;
  if (!fileExists(path)) path = replaceExtension(imagePath, "_mask.png");
  if (!fileExists(path)) return {};
  Image in = readPng(path);
  if (in.width != width || in.height != height)
    fail(where + ": mask " + path + " is " + std::to_string(in.width) + "x" + std::to_string(in.height) + ", its image " +
         std::to_string(width) + "x" + std::to_string(height));
  Image mask{width, height, 1, std::vector<float>(size_t(width) * height)};
  bool any = false;
  for (size_t p = 0; p < mask.pixels.size(); p++) {
    mask.pixels[p] = in.pixels[p * in.channels] > 0.5f ? 1.0f : 0.0f;
    any = any || mask.pixels[p] > 0;
  }
  if (!any) fail(where + ": mask " + path + " leaves no pixel that counts (all below one half)");
  return mask;
}

Image boxDownscaled(const Image& image, int factor) {
  if (factor < 1) fail("boxDownscaled: a factor of " + std::to_string(factor));
  Image out;
  out.width = image.width / factor;
  out.height = image.height / factor;
  out.channels = image.channels;
  out.pixels.assign(size_t(out.width) * size_t(out.height) * size_t(out.channels), 0.0f);
  const double area = double(factor) * double(factor);
  for (int y = 0; y < out.height; y++)
    for (int x = 0; x < out.width; x++)
      for (int c = 0; c < out.channels; c++) {
        double sum = 0;
        for (int j = 0; j < factor; j++)
          for (int i = 0; i < factor; i++) sum += image.at(x * factor + i, y * factor + j, c);
        out.at(x, y, c) = float(sum / area);
      }
  return out;
}

}  // namespace refrax
