#include "engine/synth/synth_dataset.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <filesystem>
#include <sstream>
#include <system_error>
#include <tiny_gltf.h>
#include <unistd.h>

#include "engine/base/error.h"
#include "engine/dataset/dataset_json.h"
#include "engine/io/atomic_file.h"
#include "engine/io/staged_folder.h"
#include "engine/io/image_io.h"
#include "engine/io/json_io.h"
#include "engine/io/npy.h"
#include "engine/synth/bottom_truth.h"
#include "engine/synth/render_view.h"
#include "engine/synth/synth_rng.h"

namespace fs = std::filesystem;

namespace refrax::synth {

namespace {

std::string indexName(size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%03zu", i);
  return buf;
}

nlohmann::json matrixRows(const glm::dmat4& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; r++) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
  return rows;
}

void addIntrinsics(nlohmann::json& j, const SynthCamera& c) {
  if (!c.lens.distorts()) j["camera_angle_x"] = 2 * std::atan(0.5 * c.width / c.fx);
  j["fl_x"] = c.fx;
  j["fl_y"] = c.fy;
  j["cx"] = c.cx;
  j["cy"] = c.cy;
  j["w"] = c.width;
  j["h"] = c.height;
  addTransformsLens(j, c.lens);
}

Image toImage(int width, int height, int channels, const std::vector<float>& pixels) {
  Image img;
  img.width = width;
  img.height = height;
  img.channels = channels;
  img.pixels = pixels;
  return img;
}

nlohmann::json surfaceJson(const WaveSurface& w) {
  nlohmann::json waves = nlohmann::json::array(), ripples = nlohmann::json::array();
  for (const auto& d : w.waves) {
    double k = std::hypot(d.kx, d.ky);
    waves.push_back({{"amplitude", d.amplitude}, {"kx", d.kx}, {"ky", d.ky}, {"phase", d.phase}, {"wavelength", 2 * M_PI / k},
                     {"direction_deg", std::atan2(d.ky, d.kx) * 180 / M_PI}});
  }
  for (const auto& r : w.ripples)
    ripples.push_back({{"amplitude", r.amplitude}, {"cx", r.cx}, {"cy", r.cy}, {"k", r.k}, {"sigma", r.sigma}, {"wavelength", 2 * M_PI / r.k}});
  return {{"type", "wave_sum"},
          {"formula", "z = mean_height + sum_i amplitude_i * sin(kx_i * x + ky_i * y + phase_i) + sum_j amplitude_j * cos(k_j * r_j) * "
                      "exp(-r_j^2 / (2 sigma_j^2)), r_j = |(x, y) - (cx_j, cy_j)|"},
          {"mean_height", w.meanHeight},
          {"directional_waves", waves},
          {"radial_ripples", ripples},
          {"height_bound", waveHeightBound(w)},
          {"slope_bound", waveSlopeBound(w)}};
}

// Height map with samples at both domain edges: value [j][i] at x = xmin + i (xmax - xmin) / (n - 1),
// y = ymin + j (ymax - ymin) / (n - 1).
NpyArray heightMap(const WaveSurface& w, int n) {
  NpyArray a;
  a.shape = {size_t(n), size_t(n)};
  a.data.resize(size_t(n) * n);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double x = w.domain[0] + (w.domain[2] - w.domain[0]) * i / (n - 1), y = w.domain[1] + (w.domain[3] - w.domain[1]) * j / (n - 1);
      a.data[size_t(j) * n + i] = float(waveHeight(w, x, y));
    }
  return a;
}

template <typename T>
void appendBytes(std::vector<unsigned char>& out, const std::vector<T>& v) {
  const unsigned char* p = reinterpret_cast<const unsigned char*>(v.data());
  out.insert(out.end(), p, p + v.size() * sizeof(T));
}

// The surface as an n x n vertex grid with analytic normals, in world coordinates (+Z up,
// no node transform), one embedded buffer.
void writeSurfaceGltf(const std::string& path, const WaveSurface& w, int n) {
  std::vector<float> positions, normals;
  std::vector<uint32_t> indices;
  float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double x = w.domain[0] + (w.domain[2] - w.domain[0]) * i / (n - 1), y = w.domain[1] + (w.domain[3] - w.domain[1]) * j / (n - 1);
      float p[3] = {float(x), float(y), float(waveHeight(w, x, y))};
      glm::dvec3 nn = waveNormal(w, x, y);
      for (int c = 0; c < 3; c++) {
        positions.push_back(p[c]);
        normals.push_back(float(nn[c]));
        lo[c] = std::min(lo[c], p[c]);
        hi[c] = std::max(hi[c], p[c]);
      }
    }
  for (int j = 0; j + 1 < n; j++)
    for (int i = 0; i + 1 < n; i++) {
      uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      indices.insert(indices.end(), {a, b, d, a, d, c});  // counter-clockwise seen from +Z
    }
  tinygltf::Model model;
  tinygltf::Buffer buffer;
  appendBytes(buffer.data, positions);
  appendBytes(buffer.data, normals);
  appendBytes(buffer.data, indices);
  model.buffers.push_back(buffer);
  size_t posBytes = positions.size() * 4, nrmBytes = normals.size() * 4, idxBytes = indices.size() * 4;
  auto view = [&](size_t offset, size_t length, int target) {
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = offset;
    v.byteLength = length;
    v.target = target;
    model.bufferViews.push_back(v);
  };
  view(0, posBytes, TINYGLTF_TARGET_ARRAY_BUFFER);
  view(posBytes, nrmBytes, TINYGLTF_TARGET_ARRAY_BUFFER);
  view(posBytes + nrmBytes, idxBytes, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  auto accessor = [&](int bufferView, int componentType, size_t count, int type) {
    tinygltf::Accessor a;
    a.bufferView = bufferView;
    a.componentType = componentType;
    a.count = count;
    a.type = type;
    model.accessors.push_back(a);
  };
  accessor(0, TINYGLTF_COMPONENT_TYPE_FLOAT, size_t(n) * n, TINYGLTF_TYPE_VEC3);
  model.accessors.back().minValues = {lo[0], lo[1], lo[2]};
  model.accessors.back().maxValues = {hi[0], hi[1], hi[2]};
  accessor(1, TINYGLTF_COMPONENT_TYPE_FLOAT, size_t(n) * n, TINYGLTF_TYPE_VEC3);
  accessor(2, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, indices.size(), TINYGLTF_TYPE_SCALAR);
  tinygltf::Primitive prim;
  prim.attributes["POSITION"] = 0;
  prim.attributes["NORMAL"] = 1;
  prim.indices = 2;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh mesh;
  mesh.name = "water_gt";
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "water_gt";
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.asset.version = "2.0";
  model.asset.generator = "refrax synth";
  std::ostringstream out;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, out, false, false)) fail("cannot encode glTF " + path);
  writeTextAtomic(path, out.str());
}

struct RenderJob {
  std::string split;     // train, test, test_air, air, between
  const SynthCamera* camera;
  size_t index;
  bool water;
};

}  // namespace

std::vector<double> llffPoseRow(const SynthCamera& cam, double nearDepth, double farDepth) {
  const glm::dmat4& m = cam.cameraToWorld;
  glm::dvec3 right(m[0]), up(m[1]), back(m[2]), centre(m[3]);
  glm::dvec3 cols[5] = {-up, right, back, centre, glm::dvec3(cam.height, cam.width, cam.fx)};
  std::vector<double> row;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 5; c++) row.push_back(cols[c][r]);
  row.push_back(nearDepth);
  row.push_back(farDepth);
  return row;
}

namespace {

// What rendering the views measured, per split: the depth range each view saw and the share of
// its samples that missed the water's domain.
struct RenderedSplits {
  std::map<std::string, std::vector<double>> nearDepth, farDepth, missFraction;
};

// Renders every view of every split (through the water, or dry) into DIR/<split>/ and the masks.
RenderedSplits renderSplits(const SynthPreset& p, const std::string& dir, const SynthWriteOptions& o) {
  std::vector<RenderJob> jobs;
  for (size_t i = 0; i < p.train.size(); i++) jobs.push_back({"train", &p.train[i], i, !o.dry});
  for (size_t i = 0; i < p.test.size(); i++) jobs.push_back({"test", &p.test[i], i, !o.dry});
  for (size_t i = 0; i < p.test.size(); i++) jobs.push_back({"test_air", &p.test[i], i, false});
  for (size_t i = 0; i < p.air.size(); i++) jobs.push_back({"air", &p.air[i], i, false});
  // last, so every view before them keeps the sample jitter it had before this split existed
  for (size_t i = 0; i < p.between.size(); i++) jobs.push_back({"between", &p.between[i], i, !o.dry});

  RenderSettings settings;
  settings.samplesPerAxis = p.samplesPerAxis;
  settings.seed = o.seed;
  settings.threads = o.threads;
  RenderedSplits out;
  auto start = std::chrono::steady_clock::now();
  for (size_t k = 0; k < jobs.size(); k++) {
    if (o.cancel && o.cancel->load()) fail("synth: interrupted; nothing was written to the output folder");
    const RenderJob& job = jobs[k];
    const bool wetSplit = job.split == "train" || job.split == "test" || job.split == "between";
    uint64_t key = mixKeys(k, wetSplit ? 1 : 2);  // the dry control's views jitter as the wet ones
    RenderedView v = renderView(p.scene, job.water ? &p.water : nullptr, p.ior, *job.camera, settings, key);
    std::string stem = indexName(job.index);
    writePng((fs::path(dir) / job.split / (stem + ".png")).string(), toImage(v.width, v.height, 3, v.rgb));
    if (job.water) {
      writePng((fs::path(dir) / "masks" / (job.split + "_" + stem + ".png")).string(), toImage(v.width, v.height, 1, v.mask));
      out.missFraction[job.split].push_back(double(v.samplesMissingWater) / (double(v.width) * v.height * p.samplesPerAxis * p.samplesPerAxis));
    }
    out.nearDepth[job.split].push_back(v.nearDepth);
    out.farDepth[job.split].push_back(v.farDepth);
    if (o.progress) {
      double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      double eta = elapsed / double(k + 1) * double(jobs.size() - k - 1);
      std::printf("  %-8s %2zu/%zu  view %zu of %zu  elapsed %6.1f s  ETA %6.1f s\n", job.split.c_str(), job.index + 1,
                  job.split == "air" ? p.air.size() : job.split == "train" ? p.train.size() : job.split == "between" ? p.between.size() : p.test.size(),
                  k + 1, jobs.size(), elapsed,
                  eta);
      std::fflush(stdout);
    }
  }

  return out;
}

// The Blender-format splits, transforms_{train,test,air}.json, and transforms_between.json where
// the preset has views between its training cameras.
void writeBlenderSplits(const SynthPreset& p, const std::string& dir, const SynthWriteOptions& o) {
  auto writeSplit = [&](const std::string& file, const std::string& split, const std::vector<SynthCamera>& cams, bool masks,
                        const std::string& airSplit) {
    nlohmann::json j;
    addIntrinsics(j, cams.front());
    j["image_extension"] = ".png";
    nlohmann::json frames = nlohmann::json::array();
    for (size_t i = 0; i < cams.size(); i++) {
      nlohmann::json f;
      f["file_path"] = "./" + split + "/" + indexName(i);
      f["transform_matrix"] = matrixRows(cams[i].cameraToWorld);
      addIntrinsics(f, cams[i]);
      if (masks) f["mask_path"] = "./masks/" + split + "_" + indexName(i);
      if (!airSplit.empty()) f["air_file_path"] = "./" + airSplit + "/" + indexName(i);
      frames.push_back(f);
    }
    j["frames"] = frames;
    writeJson((fs::path(dir) / file).string(), j);
  };
  writeSplit("transforms_train.json", "train", p.train, !o.dry, "");
  writeSplit("transforms_test.json", "test", p.test, !o.dry, "test_air");
  writeSplit("transforms_air.json", "air", p.air, false, "");
  if (!p.between.empty()) writeSplit("transforms_between.json", "between", p.between, !o.dry, "");

}

// The true surface (height map, glTF) and water.json, which describes the dataset.
void writeWaterTruth(const SynthPreset& p, const std::string& dir, const SynthWriteOptions& o, const RenderedSplits& r) {
  NpyArray hm = heightMap(p.water, p.heightMapSize);
  writeNpy((fs::path(dir) / "water_gt_height.npy").string(), hm);
  writeSurfaceGltf((fs::path(dir) / "water_gt.gltf").string(), p.water, p.meshGridSize);
  double hmMean = 0;
  for (double v : hm.data) hmMean += v;
  hmMean /= double(hm.data.size());

  const WaveSurface& w = p.water;
  nlohmann::json domain = {w.domain[0], w.domain[1], w.domain[2], w.domain[3]};
  nlohmann::json water;
  water["preset"] = p.name;
  water["description"] = p.description;
  water["size"] = o.sizeName;
  water["seed"] = o.seed;
  // The values are in the poses' own frame: poses_bounds.npy is then loaded as written (not
  // recentred), so the LLFF layout alone loads with this file as the Blender one does.
  water["frame"] = "dataset";
  water["ior"] = p.ior;
  water["mean_height"] = w.meanHeight;
  water["domain"] = domain;
  water["coordinates"] = "world +Z up (out of the water); the surface is z = H(x, y) over domain [xmin, ymin, xmax, ymax]; metres";
  water["surface"] = surfaceJson(w);
  water["surface"]["made_by"] = p.surfaceDescription;
  water["height_map"] = {{"file", "water_gt_height.npy"},
                         {"domain", domain},
                         {"shape", {p.heightMapSize, p.heightMapSize}},
                         {"dtype", "float32"},
                         {"mean", hmMean},
                         {"layout", "value [j][i] is H at x = xmin + i (xmax - xmin) / (nx - 1), y = ymin + j (ymax - ymin) / (ny - 1)"}};
  water["bottom"] = {{"elevation", "bottom_gt_height.npy"},
                     {"orthophoto", "bottom_gt_ortho.png"},
                     {"shape", {p.heightMapSize, p.heightMapSize}},
                     {"dtype", "float32"},
                     {"what", "the first scene surface a vertical ray meets over the water's domain with the water removed: its z (NaN: "
                              "nothing met) and its colour seen straight down"},
                     {"layout", "the height map's: value [j][i] at x = xmin + i (xmax - xmin) / (nx - 1), y = ymin + j (ymax - ymin) / (ny - 1); "
                                "the orthophoto's rows north up: PNG row r is j = ny - 1 - r"}};
  water["mesh"] = {{"file", "water_gt.gltf"},
                   {"grid", {p.meshGridSize, p.meshGridSize}},
                   {"up", "+Z: vertex positions are world coordinates, no node transform"}};
  water["masks"] = "masks/<split>_<index>.png: 1 where every sample of the pixel met the water surface inside its domain; rays that "
                   "miss the domain go on unrefracted";
  water["images"] = "train/, test/ (and between/: more test views, between the training cameras): through the water; test_air/ and air/: "
                    "the same scene with the water removed (test_air: the test cameras, air: the water-removal cameras); file paths in "
                    "transforms_*.json omit the .png extension (Blender convention)";
  if (o.dry) {
    water["dry"] = true;
    water["images"] = "the dry control (refrax synth --dry): train/, test/ and between/ rendered with the water removed, the same cameras and scene "
                      "as the dataset without --dry; test_air/ and air/ as there; file paths in transforms_*.json omit the .png extension";
    water.erase("masks");
  }
  if (!p.parametersJson.empty()) {
    nlohmann::json drawn = nlohmann::json::parse(p.parametersJson);
    water["scene_parameters"] = drawn;
    writeJson((fs::path(dir) / "scene.json").string(), drawn);
  }
  water["samples_per_pixel"] = p.samplesPerAxis * p.samplesPerAxis;
  nlohmann::json miss;
  for (const auto& [split, v] : r.missFraction) miss[split] = v;
  water["fraction_of_samples_missing_water"] = miss;
  writeJson((fs::path(dir) / "water.json").string(), water);

}

// NeRFrac's LLFF layout: images/000.png is the held-out centre view, then the training views.
void writeLlffLayout(const SynthPreset& p, const std::string& dir, const RenderedSplits& r) {
  std::vector<const SynthCamera*> cams;
  std::vector<std::pair<std::string, size_t>> sources;
  for (size_t i = 0; i < p.test.size(); i++) {
    cams.push_back(&p.test[i]);
    sources.push_back({"test", i});
  }
  for (size_t i = 0; i < p.train.size(); i++) {
    cams.push_back(&p.train[i]);
    sources.push_back({"train", i});
  }
  NpyArray poses;
  poses.shape = {cams.size(), 17};
  for (size_t i = 0; i < cams.size(); i++) {
    const auto& [split, idx] = sources[i];
    double nearD = r.nearDepth.at(split)[idx] * 0.9, farD = r.farDepth.at(split)[idx] * 1.1;
    auto row = llffPoseRow(*cams[i], nearD, farD);
    poses.data.insert(poses.data.end(), row.begin(), row.end());
    std::string bytes = readFile((fs::path(dir) / split / (indexName(idx) + ".png")).string());
    writeFileAtomic((fs::path(dir) / "images" / (indexName(i) + ".png")).string(), bytes.data(), bytes.size());
  }
  writeNpy((fs::path(dir) / "poses_bounds.npy").string(), poses, true);
}

// The bed's truth (engine/synth/bottom_truth.h): its elevation grid and its orthophoto, north up.
void writeBottomTruth(const SynthPreset& p, const std::string& dir) {
  const BottomTruth b = renderBottomTruth(p);
  const size_t n = size_t(b.size);
  NpyArray a;
  a.shape = {n, n};
  a.data.assign(b.elevation.begin(), b.elevation.end());
  writeNpy((fs::path(dir) / "bottom_gt_height.npy").string(), a);
  std::vector<float> northUp(b.rgb.size());
  for (size_t r = 0; r < n; r++) std::copy_n(&b.rgb[(n - 1 - r) * n * 3], n * 3, &northUp[r * n * 3]);
  writePng((fs::path(dir) / "bottom_gt_ortho.png").string(), toImage(int(n), int(n), 3, northUp));
}

}  // namespace

void writeSynthDataset(const SynthPreset& p, const std::string& dir, const SynthWriteOptions& o) {
  for (const char* sub : {"train", "test", "test_air", "air", "masks"}) fs::create_directories(fs::path(dir) / sub);
  if (!p.between.empty()) fs::create_directories(fs::path(dir) / "between");
  if (p.writeLlff) fs::create_directories(fs::path(dir) / "images");
  const RenderedSplits rendered = renderSplits(p, dir, o);
  writeBlenderSplits(p, dir, o);
  writeWaterTruth(p, dir, o, rendered);
  writeBottomTruth(p, dir);
  if (p.writeLlff) writeLlffLayout(p, dir, rendered);
}

void checkSynthOutputDir(const std::string& outDir) {
  std::error_code ec;
  fs::path out(outDir);
  if (outDir.empty()) fail("synth: -o DIR is required");
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) fail("synth: output " + outDir + " exists and is not a folder");
    if (!fs::is_empty(out, ec)) fail("synth: output folder " + outDir + " already exists and is not empty");
  }
  fs::path parent = fs::absolute(out, ec).parent_path();
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent)) fail("synth: cannot create output folder " + outDir + (ec ? ": " + ec.message() : ""));
  // Permission bits do not tell (root, read-only or special file systems): try it.
  fs::path probe = fs::absolute(out).string() + ".probe-" + std::to_string(getpid());
  if (!fs::create_directory(probe, ec) || ec) fail("synth: cannot create output folder " + outDir + (ec ? ": " + ec.message() : ""));
  fs::remove(probe, ec);
}

void generateSynthDataset(const SynthPreset& preset, const std::string& outDir, const SynthWriteOptions& options) {
  checkSynthOutputDir(outDir);
  StagedFolder staged(outDir, "synth: -o");  // the dataset appears whole or not at all
  try {
    writeSynthDataset(preset, staged.path, options);
  } catch (const fs::filesystem_error& e) {
    fail("synth: writing " + outDir + " failed: " + e.what());
  }
  staged.commit();
}

}  // namespace refrax::synth
