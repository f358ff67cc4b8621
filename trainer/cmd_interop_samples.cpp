// refrax interop-samples: writes the files scripts/interop-check.sh hands to the field's
// tools: random Gaussians through the 3DGS PLY writer, with the count and per-column
// statistics of the activated values other tools report (positions, exp scales, sigmoid
// opacity, DC colour 0.5 + C0 f_dc, raw quaternions), and a wavy water surface through the
// glTF exporter (.gltf and .glb); and both in one scene .glb as `refrax export` writes a run
// (the Gaussians as KHR_gaussian_splatting, the water as a refractive mesh).
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "engine/surface/builtin_surfaces.h"
#include "engine/base/error.h"
#include "engine/gaussian/gaussian_math.h"
#include "engine/surface/grid_mesh.h"
#include "engine/surface/gltf_surface.h"
#include "engine/io/json_io.h"
#include "engine/model/scene_glb.h"
#include "engine/gaussian/ply_gaussians.h"
#include "engine/app/cli.h"

namespace refrax {
namespace {

// The statistics splat-transform's `--stats` reports for one PLY column: it reduces the raw
// column and applies the (increasing) activation to the results, so min and max are those of
// the activated values and the mean is the activation of the raw mean.
nlohmann::json columnStats(const std::vector<double>& raw, double (*activation)(double)) {
  double lo = raw[0], hi = raw[0], sum = 0;
  for (double v : raw) lo = std::min(lo, v), hi = std::max(hi, v), sum += v;
  return {{"min", activation(lo)}, {"max", activation(hi)}, {"mean", activation(sum / double(raw.size()))}};
}

double identity(double x) { return x; }
double sigmoid(double x) { return 1.0 / (1.0 + std::exp(-x)); }
double exponential(double x) { return std::exp(x); }
double dcColour(double x) { return 0.5 + 0.28209479177387814 * x; }  // the degree-0 SH constant

// Expected statistics of the columns other tools activate: positions, exp scales, sigmoid
// opacity, DC colour; the quaternion as written (raw, not normalised, as the PLY holds it).
nlohmann::json activatedStats(const GaussianSet& set) {
  std::map<std::string, std::vector<double>> columns;
  for (size_t i = 0; i < set.count(); i++) {
    const float* g = set.at(i);
    const char* xyz[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; a++) {
      columns[xyz[a]].push_back(g[f32::kGaussMean + a]);
      columns["scale_" + std::to_string(a)].push_back(g[f32::kGaussLogScale + a]);
      columns["f_dc_" + std::to_string(a)].push_back(g[f32::kGaussSH + a]);
    }
    columns["opacity"].push_back(g[f32::kGaussLogitDensity]);
    for (int a = 0; a < 4; a++) columns["rot_" + std::to_string(a)].push_back(g[f32::kGaussRotation + a]);
  }
  nlohmann::json out = nlohmann::json::object();
  for (auto& [name, values] : columns) {
    double (*activation)(double) = identity;
    if (name.rfind("scale_", 0) == 0) activation = exponential;
    else if (name == "opacity") activation = sigmoid;
    else if (name.rfind("f_dc_", 0) == 0) activation = dcColour;
    out[name] = columnStats(values, activation);
  }
  return out;
}

int runInteropSamples(const cli::Args& args) {
  const std::string dir = args.get("output");
  if (dir.empty()) fail("interop-samples: --output DIR is required");
  const long count = args.getInt("count", 5000);
  if (count < 1 || count > 10000000) fail("interop-samples: --count must be in [1, 10000000]");
  std::mt19937 rng(uint32_t(args.getInt("seed", 1)));

  RandomGaussianOptions options;
  options.densityMin = 0.01f;
  options.densityMax = 0.99f;
  GaussianSet set = randomGaussians(rng, size_t(count), options);
  const std::string ply = dir + "/gaussians.ply";
  writeGaussiansPly(ply, set);
  writeJson(dir + "/gaussians_expected.json", {{"count", set.count()}, {"columns", activatedStats(set)}});

  BuiltinSurface wave;
  wave.kind = "sine";
  wave.amplitude = 0.03f;
  wave.wavelength = 0.4f;
  wave.directionDeg = 30.0f;
  GridMesh grid = makeGridMesh(64, 48, -1.0f, -0.75f, 1.0f, 0.75f, surfaceHeightFunction(wave));
  SurfaceMesh mesh = surfaceMeshFromGrid(grid);
  writeSurfaceGltf(dir + "/water_surface.gltf", mesh);
  writeSurfaceGltf(dir + "/water_surface.glb", mesh);
  GlbWater water;
  water.mesh = mesh;
  water.thickness = 0.5;
  writeSceneGlb(dir + "/scene.glb", gltfSplatsFrom(set, 3), water);
  std::printf("wrote %s (%zu Gaussians), gaussians_expected.json, water_surface.gltf and .glb (%zu vertices, %zu triangles) and scene.glb (both) in %s\n",
              ply.c_str(), set.count(), mesh.vertexCount(), mesh.triangleCount(), dir.c_str());
  return 0;
}

std::vector<cli::Option> interopSamplesOptions() {
  return {{"output", "DIR", "folder to write into (must exist)", ""},
          {"count", "N", "number of random Gaussians", "5000"},
          {"seed", "N", "random seed", "1"}};
}

REFRAX_COMMAND({"interop-samples", "write a random Gaussian PLY (with its expected statistics) and a water glTF for other tools to check",
                "refrax interop-samples --output DIR [--count N] [--seed N]", interopSamplesOptions(), runInteropSamples});

}  // namespace
}  // namespace refrax
