// refrax align-poses <colmap-dataset> <truth-dataset> [-o DIR]: how far structure from
// motion's camera poses are from the true ones (engine/dataset/pose_alignment.h), and those
// poses moved into the truth's frame as a Blender dataset that trains and evaluates against
// the truth's water.json and ground-truth surface.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "engine/base/error.h"
#include "engine/dataset/dataset.h"
#include "engine/dataset/dataset_json.h"
#include "engine/dataset/pose_alignment.h"
#include "engine/io/atomic_file.h"
#include "engine/io/json_io.h"
#include "engine/app/cli.h"

namespace fs = std::filesystem;

namespace refrax {
namespace {

// A view's name with its folder's conventions taken off, so that the same image matches in
// both datasets: no leading "./", no extension, and for a COLMAP dataset not the image folder
// the loader puts in front (COLMAP names images relative to it). "./train/000" (Blender) and
// "images/train/000.png" (COLMAP) are both "train/000".
std::string matchKey(const Dataset& d, const std::string& name) {
  fs::path p(name.rfind("./", 0) == 0 ? name.substr(2) : name);
  if (d.format == "colmap" && p.has_parent_path()) p = p.lexically_relative(*p.begin());
  return p.replace_extension().generic_string();
}

size_t imageFilesUnder(const std::string& dir) {
  size_t n = 0;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    std::string ext = e.path().extension().string();
    for (auto& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (e.is_regular_file() && (ext == ".png" || ext == ".jpg" || ext == ".jpeg")) n++;
  }
  return n;
}

nlohmann::json rows(const glm::dmat4& m) {
  nlohmann::json r = nlohmann::json::array();
  for (int i = 0; i < 4; i++) r.push_back({m[0][i], m[1][i], m[2][i], m[3][i]});
  return r;
}

struct Match {
  std::string split, key;
  const View* estimated;  // COLMAP's view (its frame, its intrinsics, its image)
  const View* truth;
  glm::dmat4 aligned{1.0};
};

// water.json and the ground-truth files it names, so the aligned poses evaluate against them.
void copyGroundTruth(const std::string& truthRoot, const std::string& out) {
  const std::string water = truthRoot + "/water.json";
  if (!fileExists(water)) return;
  fs::copy_file(water, out + "/water.json", fs::copy_options::overwrite_existing);
  nlohmann::json j = readJson(water);
  if (!j.is_object()) return;
  // {section, field}: the water's height map and mesh, and the bed's truth (refrax synth's "bottom")
  const std::pair<const char*, const char*> named[] = {{"height_map", "file"}, {"mesh", "file"}, {"bottom", "elevation"}, {"bottom", "orthophoto"}};
  for (const auto& [key, field] : named) {
    if (!j.contains(key)) continue;
    const auto& v = j[key];
    std::string file = v.is_string() ? v.get<std::string>() : v.is_object() && v.contains(field) && v[field].is_string() ? v[field].get<std::string>() : "";
    if (file.empty()) continue;
    fs::path target = fs::path(out) / file;
    fs::create_directories(target.parent_path());
    fs::copy_file(fs::path(truthRoot) / file, target, fs::copy_options::overwrite_existing);
  }
}

void writeAligned(const std::string& out, const Dataset& colmap, const Dataset& truth, const std::vector<Match>& matches) {
  std::map<std::string, nlohmann::json> frames;
  for (const Match& m : matches) {
    const Camera& c = m.estimated->camera;
    const fs::path source = fs::path(colmap.root) / m.estimated->name;
    const std::string file = m.key + source.extension().string();
    fs::create_directories((fs::path(out) / file).parent_path());
    fs::copy_file(source, fs::path(out) / file, fs::copy_options::overwrite_existing);
    nlohmann::json frame = {{"file_path", "./" + file}, {"transform_matrix", rows(m.aligned)}, {"fl_x", c.fx}, {"fl_y", c.fy},
                            {"cx", c.cx}, {"cy", c.cy}, {"w", c.width}, {"h", c.height}};
    addTransformsLens(frame, c.lens);  // COLMAP's lens, traced as it is
    frames[m.split].push_back(frame);
  }
  for (const auto& [split, f] : frames) writeJson(out + "/transforms_" + split + ".json", {{"frames", f}});
  copyGroundTruth(truth.root, out);
}

int runAlignPoses(const cli::Args& args) {
  if (args.positional.size() != 2) fail("align-poses: expected <colmap-dataset> <truth-dataset>");
  const std::string colmapDir = args.positional[0], truthDir = args.positional[1];
  std::unique_ptr<cli::OutputFolder> out;
  if (args.has("output")) {
    out = cli::createOutputFolder(args.get("output"), "-o");
    if (!fs::is_empty(out->path)) fail("align-poses: -o " + out->path + " is not empty");
  }
  auto bound = [&](const char* flag) -> std::optional<double> {
    if (!args.has(flag)) return std::nullopt;
    double v = args.getDouble(flag, 0);
    if (!(std::isfinite(v) && v >= 0)) fail(std::string("align-poses: --") + flag + " must be a number >= 0, got '" + args.get(flag) + "'");
    return v;
  };
  const auto minRegistered = bound("min-registered"), maxRotation = bound("max-rotation-error"), maxCentre = bound("max-centre-error");

  // The water height matters only for training: a known one spares the loader estimating it.
  DatasetOptions colmapOptions;
  colmapOptions.llffHold = 0;  // every registered view in one list; the truth's splits decide
  colmapOptions.waterHeight = 0;
  const Dataset colmap = loadColmapDataset(colmapDir, colmapOptions);
  const Dataset truth = loadDataset(truthDir);
  const size_t given = imageFilesUnder(imageFolder(colmapDir, 1));

  std::map<std::string, std::pair<std::string, const View*>> truthByKey;
  for (const auto& [split, views] : truth.splits)
    for (const View& v : views) truthByKey[matchKey(truth, v.name)] = {split, &v};
  std::vector<Match> matches;
  size_t registered = 0;
  std::string unmatched;
  for (const auto& [split, views] : colmap.splits)
    for (const View& v : views) {
      registered++;
      std::string key = matchKey(colmap, v.name);
      auto it = truthByKey.find(key);
      if (it == truthByKey.end()) {
        if (unmatched.size() < 200) unmatched += (unmatched.empty() ? "" : ", ") + key;
        continue;
      }
      matches.push_back({it->second.first, key, &v, it->second.second});
    }
  if (matches.size() < 3)
    fail("align-poses: " + std::to_string(matches.size()) + " of COLMAP's " + std::to_string(registered) + " registered images match a view of " +
         truthDir + " by file name (at least 3 needed; unmatched: " + (unmatched.empty() ? "none" : unmatched) + ")");

  std::vector<glm::dvec3> from, to;
  for (const Match& m : matches) {
    from.push_back(m.estimated->camera.position());
    to.push_back(m.truth->camera.position());
  }
  const Similarity sim = fitSimilarity(from, to);
  std::vector<glm::dmat4> aligned, truthPoses;
  for (Match& m : matches) {
    m.aligned = applySimilarity(sim, m.estimated->camera.cameraToWorld);
    aligned.push_back(m.aligned);
    truthPoses.push_back(m.truth->camera.cameraToWorld);
  }
  const PoseErrors e = poseErrors(aligned, truthPoses);
  const double registeredFraction = given ? double(registered) / double(given) : 0;

  std::printf("align-poses: COLMAP registered %zu of the %zu images in %s (%.0f%%); %zu match the truth's views\n", registered, given,
              imageFolder(colmapDir, 1).c_str(), 100 * registeredFraction, matches.size());
  std::printf("  similarity: scale %.6g; rotation error median %.3f deg, max %.3f deg; centre error median %.4g, max %.4g "
              "(%.2f%% and %.2f%% of the rig's extent %.4g)\n",
              sim.scale, e.rotationMedianDeg, e.rotationMaxDeg, e.centreMedian, e.centreMax, 100 * e.centreMedian / e.extent,
              100 * e.centreMax / e.extent, e.extent);

  if (out) {
    writeAligned(out->path, colmap, truth, matches);
    nlohmann::json views = nlohmann::json::array();
    for (size_t i = 0; i < matches.size(); i++)
      views.push_back({{"name", matches[i].key}, {"split", matches[i].split}, {"rotation_error_deg", e.rotationDeg[i]}, {"centre_error", e.centre[i]}});
    nlohmann::json r = {{"colmap", colmapDir}, {"truth", truthDir}, {"images_given", given}, {"registered", registered},
                        {"matched", matches.size()}, {"scale", sim.scale}, {"rotation_error_deg_median", e.rotationMedianDeg},
                        {"rotation_error_deg_max", e.rotationMaxDeg}, {"centre_error_median", e.centreMedian}, {"centre_error_max", e.centreMax},
                        {"rig_extent", e.extent}, {"views", views}};
    writeJson(out->path + "/alignment.json", r);
    out->keep();
    std::printf("  aligned poses written as a Blender dataset in %s (alignment.json: per-view errors)\n", out->path.c_str());
  }
  // The checks last, so that a failing run still leaves its numbers to look at.
  if (minRegistered && registeredFraction < *minRegistered)
    fail("align-poses: COLMAP registered " + std::to_string(registered) + " of " + std::to_string(given) + " images, under --min-registered " + args.get("min-registered"));
  if (maxRotation && !(e.rotationMaxDeg <= *maxRotation))
    fail("align-poses: a rotation error of " + std::to_string(e.rotationMaxDeg) + " deg exceeds --max-rotation-error " + args.get("max-rotation-error"));
  if (maxCentre && !(e.centreMax <= *maxCentre * e.extent))
    fail("align-poses: a centre error of " + std::to_string(e.centreMax / e.extent) + " of the rig's extent exceeds --max-centre-error " +
         args.get("max-centre-error"));
  return 0;
}

REFRAX_COMMAND({"align-poses", "compare COLMAP's camera poses with the true ones (similarity fit) and write them in the truth's frame",
                "refrax align-poses <colmap-dataset> <truth-dataset> [-o DIR] [--min-registered F] [--max-rotation-error DEG] [--max-centre-error F]\n"
                "       views are matched by image path without extension (COLMAP's images/train/000.png is the truth's train/000)",
                {{"output", "DIR", "(or -o DIR) write the COLMAP poses, aligned into the truth's frame, as a Blender dataset (its images, the "
                                   "truth's water.json and ground-truth files, alignment.json); must not exist or be empty", ""},
                 {"min-registered", "F", "fail unless COLMAP registered at least this fraction of the images in its image folder", ""},
                 {"max-rotation-error", "DEG", "fail when a camera's rotation error after the alignment exceeds DEG", ""},
                 {"max-centre-error", "F", "fail when a camera's centre error after the alignment exceeds F times the rig's extent (the "
                                           "largest distance between two true camera centres)", ""}},
                runAlignPoses});

}  // namespace
}  // namespace refrax
