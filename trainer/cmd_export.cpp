// refrax export RUN --glb FILE: what a run learned as one binary glTF that other viewers open
// (engine/model/scene_glb.h): the Gaussians as KHR_gaussian_splatting and the learned water as
// a refractive mesh. Reads the run's files (config.json, point_cloud.ply, water_height.npy);
// no device. Given a 3DGS PLY instead of a run, writes its Gaussians alone.
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "engine/app/cli.h"
#include "engine/base/error.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/io/npy.h"
#include "engine/model/open_model.h"
#include "engine/model/scene_glb.h"
#include "engine/surface/grid_mesh.h"

namespace refrax {
namespace {

namespace fs = std::filesystem;

// The water the run learned: water_height.npy's grid (rows along y over the domain, corners
// included) as a mesh, the run's IOR, and the depth from the water height to the box's floor.
GlbWater learnedWater(const std::string& run, const TrainConfig& c) {
  const std::string path = (fs::path(run) / "water_height.npy").string();
  if (!fs::exists(path)) fail(run + " has no water_height.npy (a run writes it when training ends): nothing to export the water from");
  const NpyArray a = readNpy(path);
  if (a.shape.size() != 2 || a.shape[0] < 2 || a.shape[1] < 2) fail(path + ": the water's heights are not a grid of at least 2 x 2");
  const size_t ny = a.shape[0], nx = a.shape[1];
  for (double h : a.data)
    if (!std::isfinite(h)) fail(path + ": a water height is not finite");
  const Rect& d = c.domain;
  auto height = [&](float x, float y) {
    const size_t i = size_t(std::lround((x - d.xMin) / (d.xMax - d.xMin) * double(nx - 1)));
    const size_t j = size_t(std::lround((y - d.yMin) / (d.yMax - d.yMin) * double(ny - 1)));
    return float(a.data[std::min(j, ny - 1) * nx + std::min(i, nx - 1)]);
  };
  GlbWater w;
  w.mesh = surfaceMeshFromGrid(makeGridMesh(uint32_t(nx - 1), uint32_t(ny - 1), float(d.xMin), float(d.yMin), float(d.xMax), float(d.yMax), height));
  w.ior = c.ior;
  w.thickness = std::max(0.0, c.waterHeight - c.boxMin[2]);
  return w;
}

int runExport(const cli::Args& a) {
  if (a.positional.size() != 1) fail("refrax export needs one run folder or 3DGS PLY (refrax export RUN --glb FILE)");
  if (!a.has("glb")) fail("refrax export needs --glb FILE (the only format it writes)");
  const std::string run = a.positional[0], out = a.get("glb");
  if (fs::path(run).extension() == ".ply") {  // any 3DGS PLY: its Gaussians alone, every SH degree it holds
    const GltfSplats splats = gltfSplatsFrom(readGaussiansPly(run), 3);
    writeSceneGlb(out, splats, std::nullopt);
    std::printf("%s: %zu Gaussians (SH degree 3)\n", out.c_str(), splats.count);
    return 0;
  }
  const TrainConfig c = readRunConfig(run);
  const std::string ply = (fs::path(run) / "point_cloud.ply").string();
  if (!fs::exists(ply)) fail(run + " has no point_cloud.ply (a run writes it when training ends)");
  const GltfSplats splats = gltfSplatsFrom(readGaussiansPly(ply), std::min<uint32_t>(c.maxShDegree, 3));
  std::optional<GlbWater> water;
  const bool hasWater = c.model != WaterModel::NoRefraction;
  if (hasWater && !a.has("splats-only")) water = learnedWater(run, c);
  writeSceneGlb(out, splats, water);
  std::printf("%s: %zu Gaussians (SH degree %u)%s\n", out.c_str(), splats.count, splats.shDegree,
              water ? (", the water (" + std::to_string(water->mesh.triangleCount()) + " triangles, IOR " + std::to_string(water->ior).substr(0, 4) + ")").c_str()
                    : hasWater ? ", no water (--splats-only)" : ", no water (the run traced straight rays)");
  return 0;
}

REFRAX_COMMAND({"export", "a run as one .glb other viewers open: KHR_gaussian_splatting and the water",
                "refrax export RUN --glb FILE [--splats-only]    (or SCENE.ply: any 3DGS PLY's Gaussians)",
                {{"glb", "FILE", "the binary glTF to write (atomically): the Gaussians, and the learned water as a refractive mesh", ""},
                 {"splats-only", "", "the Gaussians alone, without the water", ""}},
                runExport});

}  // namespace
}  // namespace refrax
