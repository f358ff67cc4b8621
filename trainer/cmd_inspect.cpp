// refrax inspect <dataset>: loads a dataset as training would (every check included) and
// prints its splits, cameras, water metadata and the bounds derived from the cameras: the
// scene extent, the height-field domain, the depth under the water and the initial Gaussian box.
#include <cstdio>

#include "engine/dataset/dataset.h"
#include "engine/dataset/scene_bounds.h"
#include "engine/base/error.h"
#include "engine/app/cli.h"
#include "trainer/dataset_options.h"

namespace refrax {
namespace {

std::vector<Camera> camerasOf(const std::vector<View>& views) {
  std::vector<Camera> c;
  for (const auto& v : views) c.push_back(v.camera);
  return c;
}

int runInspect(const cli::Args& args) {
  if (args.positional.size() != 1) fail("refrax inspect needs one dataset folder");
  Dataset d = loadDataset(args.positional[0], datasetOptionsFrom(args));
  std::printf("dataset %s (%s)\n", d.root.c_str(), d.format.c_str());
  for (const std::string& note : d.notes) std::printf("  %s\n", note.c_str());
  for (const auto& [name, views] : d.splits) {
    const Camera& c = views[0].camera;
    std::printf("  %-6s %3zu views, %dx%d, fx %.2f fy %.2f cx %.2f cy %.2f, lens %s (first view)\n", name.c_str(), views.size(), c.width,
                c.height, c.fx, c.fy, c.cx, c.cy, lensDescription(c.lens).c_str());
  }
  const auto& train = d.split("train");
  std::vector<Camera> cams = camerasOf(train);
  std::printf("scene extent %.4f (1.1 x largest camera distance from their mean)\n", sceneExtent(cams));
  std::printf("water: ior %.4f", d.water.ior);
  if (!d.water.height) {
    std::printf(", no height given (water.json 'height' or --water-height): no bounds derived\n");
    return 0;
  }
  double h = *d.water.height;
  std::printf(", height %.4f\n", h);
  Rect r = d.water.domain ? *d.water.domain : surfaceDomainFromCameras(cams, h);
  std::printf("surface domain x [%.4f, %.4f] y [%.4f, %.4f] (%s)\n", r.xMin, r.xMax, r.yMin, r.yMax,
              d.water.domain ? "given" : "camera footprints + 5%");
  double depth = d.water.depth ? *d.water.depth : estimateWaterDepth(train, h, d.water.ior);
  std::printf("depth under the water %.4f (%s)\n", depth, d.water.depth ? "given" : "estimated");
  Box b = gaussianBoxFromRefractedFrusta(cams, h, d.water.ior, depth);
  std::printf("initial Gaussian box [%.4f, %.4f] x [%.4f, %.4f] x [%.4f, %.4f]\n", b.min.x, b.max.x, b.min.y, b.max.y, b.min.z, b.max.z);
  return 0;
}

REFRAX_COMMAND({"inspect", "load a dataset, check it, print its cameras and derived scene bounds", "refrax inspect <dataset> [options]",
                datasetOptions(), runInspect});

}  // namespace
}  // namespace refrax
