#include "engine/dataset/dataset.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "engine/base/error.h"
#include "engine/dataset/colmap_model.h"
#include "engine/io/atomic_file.h"

namespace refrax {

const std::vector<View>& Dataset::split(const std::string& name) const {
  auto it = splits.find(name);
  if (it == splits.end()) fail("dataset " + root + " has no '" + name + "' split");
  return it->second;
}

Dataset loadDataset(const std::string& folder, const DatasetOptions& options) {
  const bool colmap = hasColmapModel(folder + "/sparse/0") || hasColmapModel(folder + "/sparse") || hasColmapModel(folder);
  const bool blender = fileExists(folder + "/transforms_train.json"), llff = fileExists(folder + "/poses_bounds.npy");
  const bool nerfstudio = !blender && fileExists(folder + "/transforms.json");
  if (options.up && (blender || llff || !(colmap || nerfstudio)))
    fail("--up applies to COLMAP and nerfstudio datasets only (" + folder + " is not one)");
  if (!options.testViews.empty() && blender)
    fail("--test-views applies to LLFF, COLMAP and nerfstudio datasets (" + folder + " is a Blender dataset: its test views are transforms_test.json's)");
  if (blender) return loadBlenderDataset(folder, options);
  if (llff) return loadLlffDataset(folder, options);
  if (nerfstudio) return loadNerfstudioDataset(folder, options);
  if (colmap) return loadColmapDataset(folder, options);
  fail("no dataset in " + folder + ": expected transforms_train.json (NeRF/Blender), poses_bounds.npy (LLFF), transforms.json "
       "(nerfstudio) or a COLMAP model (sparse/0/cameras.bin or .txt)");
}

void noteMasks(Dataset& d) {
  size_t views = 0, masked = 0;
  for (const auto& [name, split] : d.splits)
    for (const View& v : split) {
      views++;
      masked += v.mask.pixels.empty() ? 0 : 1;
    }
  if (masked) d.notes.push_back("masks: " + std::to_string(masked) + " of " + std::to_string(views) + " views (their 0 pixels do not count)");
}

std::vector<bool> testViewFlags(const std::vector<std::string>& files, const DatasetOptions& options, const std::string& where) {
  std::vector<bool> test(files.size(), false);
  if (options.testViews.empty()) {
    if (options.llffHold < 0) fail("--llff-hold must be at least 0 (0: no test views), got " + std::to_string(options.llffHold));
    for (size_t i = 0; options.llffHold > 0 && i < files.size(); i += size_t(options.llffHold)) test[i] = true;
  } else {
    for (const std::string& name : options.testViews) {
      size_t index = files.size();
      char* end = nullptr;
      const unsigned long long n = std::strtoull(name.c_str(), &end, 10);
      if (!name.empty() && name[0] != '-' && !*end) index = size_t(n);  // an index
      for (size_t i = 0; i < files.size() && index == files.size(); i++)
        if (files[i] == name) index = i;
      if (index >= files.size())
        fail("--test-views: '" + name + "' is neither an image of " + where + " nor an index below its " + std::to_string(files.size()) +
             " images");
      test[index] = true;
    }
  }
  if (std::find(test.begin(), test.end(), false) == test.end())
    fail(where + ": no training views remain after holding out " +
         (options.testViews.empty() ? "every " + std::to_string(options.llffHold) + "th image" : "the --test-views"));
  return test;
}

std::string imageFolder(const std::string& folder, int factor) {
  return folder + (factor == 1 ? "/images" : "/images_" + std::to_string(factor));
}

std::string maskFolder(const std::string& folder, int factor) {
  return folder + (factor == 1 ? "/masks" : "/masks_" + std::to_string(factor));
}

void validateCameraToWorld(const glm::dmat4& m, const std::string& where) {
  for (int c = 0; c < 4; c++)
    for (int r = 0; r < 4; r++)
      if (!std::isfinite(m[c][r])) fail(where + ": the camera pose has a non-finite value");
  if (std::abs(m[0][3]) > 1e-6 || std::abs(m[1][3]) > 1e-6 || std::abs(m[2][3]) > 1e-6 || std::abs(m[3][3] - 1.0) > 1e-6)
    fail(where + ": the camera pose's last row is not (0 0 0 1)");
  glm::dmat3 r(m);
  glm::dmat3 rtr = glm::transpose(r) * r;
  double worst = 0;
  for (int c = 0; c < 3; c++)
    for (int k = 0; k < 3; k++) worst = std::max(worst, std::abs(rtr[c][k] - (c == k ? 1.0 : 0.0)));
  if (worst > 1e-3) fail(where + ": the camera rotation is not orthonormal (|R^T R - I| = " + std::to_string(worst) + ")");
  if (glm::determinant(r) < 0) fail(where + ": the camera rotation is a reflection (determinant -1)");
}

}  // namespace refrax
