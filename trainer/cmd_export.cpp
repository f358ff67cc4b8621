// refrax export RUN --glb FILE: what a run learned as one binary glTF that other viewers open
// (engine/model/scene_glb.h): the Gaussians as KHR_gaussian_splatting and the learned water as
// a refractive mesh. Reads the run's files (config.json, point_cloud.ply, water_height.npy);
// no device. Given a 3DGS PLY instead of a run, writes its Gaussians alone.
// refrax export RUN --bottom DIR: what lies under the water as GeoTIFFs, previews and a point
// cloud (engine/survey/), traced on the device from the run's newest checkpoint.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "engine/app/cli.h"
#include "engine/base/error.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/io/staged_folder.h"
#include "engine/io/npy.h"
#include "engine/model/open_model.h"
#include "engine/survey/bottom_accuracy.h"
#include "engine/survey/bottom_files.h"
#include "engine/vk/vk_context.h"
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

// --crs EPSG:N and --origin E,N[,H]: the projected CRS the dataset's frame sits in, and where its origin lies.
BottomFrame bottomFrame(const cli::Args& a) {
  BottomFrame f;
  if (!a.has("crs") && !a.has("origin")) return f;
  if (!a.has("crs") || !a.has("origin")) fail("--crs and --origin go together: the CRS, and where the dataset's origin lies in it");
  const std::string crs = a.get("crs");
  char* end = nullptr;
  const long code = crs.rfind("EPSG:", 0) == 0 ? std::strtol(crs.c_str() + 5, &end, 10) : 0;
  if (code <= 0 || code > 65535 || *end != '\0') fail("--crs " + crs + ": give a projected CRS as EPSG:N (metres, e.g. EPSG:32633 for UTM zone 33N)");
  f.epsg = int(code);
  const std::string o = a.get("origin");
  int used = 0, n = std::sscanf(o.c_str(), "%lf,%lf%n,%lf%n", &f.origin[0], &f.origin[1], &used, &f.origin[2], &used);
  if (n < 2 || size_t(used) != o.size() || !std::isfinite(f.origin[0] + f.origin[1] + f.origin[2]))
    fail("--origin " + o + ": give the dataset origin's easting,northing[,height] in the CRS, in metres");
  f.description = "EPSG:" + std::to_string(code) + ": the dataset's frame (metres, +z up) shifted by --origin " + o;
  return f;
}

int runBottomExport(const cli::Args& a, const std::string& run) {
  const TrainConfig c = readRunConfig(run);
  const BottomFrame frame = bottomFrame(a);
  const Dataset dataset = loadRunDataset(c);
  const uint32_t truthSize = bottomTruthSize(dataset);
  const uint32_t vertices = uint32_t(a.getIntIn("grid", truthSize ? truthSize : 257, 2, 4097));
  const std::string out = a.get("bottom");
  std::error_code ec;
  if (fs::exists(out) && (!fs::is_directory(out) || !fs::is_empty(out, ec)))
    fail("--bottom " + out + ": the folder exists and is not empty (give a new or empty folder)");
  StagedFolder folder(out, "--bottom");
  auto ctx = cli::openContext(a);
  auto model = openModel(*ctx, run, dataset);
  const BottomMaps maps = mapBottom(*model, dataset.split("train"), bottomGridOver(c.domain, vertices));
  nlohmann::json report = {{"run", fs::absolute(run).string()}, {"step", model->step}, {"device", ctx->caps.name}};
  report["accuracy"] = bottomAccuracy(maps, dataset);
  const nlohmann::json j = writeBottomFiles(folder, maps, frame, report);
  std::printf("%s: the bottom on %u x %u vertices (%.4g m apart), %zu mapped\n", out.c_str(), vertices, vertices,
              (c.domain.xMax - c.domain.xMin) / (vertices - 1), j["points"].get<size_t>());
  const nlohmann::json& acc = j["accuracy"];
  if (acc.contains("bottom_rmse_m"))
    std::printf("  against the truth: RMSE %.4g m, bias %+.4g m, coverage %.1f%%, water-free orthophoto %.2f dB\n", acc["bottom_rmse_m"].get<double>(),
                acc["bottom_bias_m"].get<double>(), 100 * acc["bottom_coverage"].get<double>(), acc.value("ortho_dry_psnr", 0.0));
  else if (acc.contains("bottom_truth_missing"))
    std::printf("  no accuracy: %s\n", acc["bottom_truth_missing"].get<std::string>().c_str());
  return 0;
}

int runExport(const cli::Args& a) {
  if (a.positional.size() != 1) fail("refrax export needs one run folder or 3DGS PLY (refrax export RUN --glb FILE)");
  if (a.has("glb") == a.has("bottom")) fail("refrax export needs one of --glb FILE and --bottom DIR");
  if (a.has("bottom")) return runBottomExport(a, a.positional[0]);
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

std::vector<cli::Option> exportOptions() {
  std::vector<cli::Option> o = {
      {"glb", "FILE", "the binary glTF to write (atomically): the Gaussians, and the learned water as a refractive mesh", ""},
      {"splats-only", "", "the Gaussians alone, without the water", ""},
      {"bottom", "DIR", "what lies under the water, for a GIS: the bottom's elevation, the water's surface and depth, a confidence and "
                        "two true orthophotos (water removed, kept) as GeoTIFFs, with previews, bottom.ply and bottom.json (the "
                        "accuracy against the truth where the dataset has one)", ""},
      {"grid", "N", "--bottom: vertices per side over the water's domain (default: the truth's grid, else 257)", ""},
      {"crs", "EPSG:N", "--bottom: the projected CRS (metres) the dataset's frame sits in, written into the GeoTIFFs", ""},
      {"origin", "E,N[,H]", "--bottom with --crs: where the dataset's origin lies in that CRS", ""}};
  for (auto& d : cli::deviceOptions()) o.push_back(d);
  return o;
}

REFRAX_COMMAND({"export", "a run as one .glb other viewers open, or what lies under its water as GeoTIFFs",
                "refrax export RUN --glb FILE [--splats-only]    (or SCENE.ply: any 3DGS PLY's Gaussians)\n"
                "       refrax export RUN --bottom DIR [--grid N] [--crs EPSG:N --origin E,N[,H]]",
                exportOptions(), runExport});

}  // namespace
}  // namespace refrax
