#pragma once
// Posed image datasets: the NeRF/Blender format (transforms_<split>.json), LLFF
// (poses_bounds.npy, as NeRFrac's dataset) and COLMAP sparse models (what users of Gaussian
// splatting make of their own photographs), plus the water metadata (water.json).
//
// World frame: Z up, out of the water; cameras in the Blender/NeRF convention (engine/camera/camera.h:
// camera-to-world columns right, up, back; the camera looks down its -Z).
//
// Blender: transforms_train.json (required), transforms_test.json and any other
//   transforms_<name>.json (extra splits). Intrinsics: camera_angle_x (fx = w / (2 tan(angle/2)),
//   fy from camera_angle_y when given, else fx), or fl_x / fl_y / cx / cy / w / h (instant-ngp);
//   a frame may override any of them. Principal point defaults to the image centre. Lens (as
//   nerfstudio writes it): camera_model (OPENCV, OPENCV_FISHEYE; absent: OPENCV) with k1..k4,
//   p1, p2 (absent: 0), traced as given, no undistortion (engine/camera/lens.h). frames[i]:
//   file_path (relative to the dataset folder, with or without extension: .png .jpg .jpeg are
//   tried) and transform_matrix (4x4 camera-to-world). RGBA images are composited on the
//   background colour; grey images become RGB. Poses are used as given.
//
// LLFF (poses_bounds.npy, N x 17, with images/ or images_<factor>/): each row is a 3x5 matrix
//   [R | t | hwf] row-major, then the near and far bounds. Conventions, following NeRF's
//   load_llff.py that NeRFrac uses (recenter=True, bd_factor=0.75, spherify=False):
//   1. R's columns are the camera's [down, right, back] axes; they become [right, up, back]
//      = [col1, -col0, col2] (Blender/NeRF convention).
//   2. hwf = (height, width, focal) at the full resolution; focal / factor for images_<factor>,
//      principal point at the image centre; the images' size must match height / factor and
//      width / factor (rounded either way).
//   3. Scale: translations and bounds are multiplied by s = 1 / (0.75 * min near bound).
//   4. Recentring: the average pose A (centre = mean position, back = normalised sum of back
//      axes, right = normalise(sum of up axes x back), up = back x right) is mapped to the
//      identity: every camera-to-world becomes inverse(A) * C. So the mean camera sits at the
//      origin looking down -Z: for cameras looking down at water, Z is up.
//   Dataset::normalization holds the whole map, world_loaded = normalization * world_original.
//   Images are sorted by file name and paired with the rows in order. Test views: those named
//   by testViews, else every llffHold-th image from the first (0, 8, 16, ... for the default
//   8); the others train.
//
// COLMAP (a sparse model in sparse/0/, sparse/ or the folder itself: cameras, images and
//   points3D as .bin or .txt, engine/dataset/colmap_model.h; images in images/ or images_<N>/
//   with --llff-factor N, intrinsics divided by N). Every COLMAP camera model but FOV and
//   THIN_PRISM_FISHEYE, the distorted ones traced through their lens as they are (no
//   undistortion; engine/camera/lens.h); those two are refused with the fix (`colmap image_undistorter`). Images registered but
//   not on disk, or on disk but not registered, are left out and counted in Dataset::notes.
//   The model's frame is arbitrary, so the loaded frame is derived for the water:
//   1. Up (toward the cameras): --up X,Y,Z in the model's frame; else, when the cameras look
//      the same way (their unit viewing directions' mean has length > 0.5: a rig looking down),
//      the opposite of their mean viewing direction; else (a ring around the scene) the normal
//      of the plane through their centres (least-squares), on the cameras' side. Up becomes +Z.
//   2. The mean camera centre becomes the origin.
//   3. Scale: the median depth of the sparse points below the cameras becomes 1 (COLMAP's
//      units when the model has fewer than 10 points).
//   4. The water height: --water-height or water.json (in this loaded frame), else the 95th
//      percentile of the sparse points' heights, taken as the dry rim around the water
//      (points seen through the water appear lower); an error when there are no points.
//   Test views: as LLFF (testViews, else every llffHold-th image in name order).
//   `refrax inspect` prints the derived frame (Dataset::notes).
//
// nerfstudio (transforms.json, as ns-process-data writes it; no transforms_train.json): frames
//   as a Blender split's (intrinsics and lens per frame or for the file), each frame's mask_path
//   its mask. Test views: test_filenames (else val_filenames), train_filenames the training
//   views (else the rest); without those lists, or with --test-views, as LLFF. The frame is
//   the source's (COLMAP's, turned by applied_transform, which the poses already carry), so
//   the water's is derived as for COLMAP (steps 1-4, --up in the file's frame) from the poses
//   and the sparse points of ply_file_path (sparse_pc.ply; the file's units without them),
//   unless water.json says "frame": "dataset" (then the poses are used as written).
//
// Masks (every format; engine/dataset/view_image.h): masks/<image's path>.png, the masks/
//   folder mirroring the image folder (images_<N>/ -> masks_<N>/; Blender: masks/train/000.png
//   for ./train/000), else <image>_mask.png beside the image (RefracGS's convention). Zero
//   where a pixel must not count (a tank's rim, reflections, people); a view without either
//   file counts every pixel. Dataset::notes counts the views with masks.
//
// water.json (optional, in the dataset folder; values in the loaded world frame): {"ior": 1.33,
//   "height": -1.0, "depth": 2.0, "domain": [xmin, ymin, xmax, ymax]}; every field optional,
//   DatasetOptions override each one.
//
// Every problem is one refrax::Error naming the file: missing or undecodable image, image of
// the wrong size, malformed JSON, missing field, non-finite pose, non-orthonormal rotation,
// empty split, images and poses not matching in number.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "engine/camera/camera.h"
#include "engine/io/image_io.h"

namespace refrax {

struct View {
  std::string name;       // file name (relative to the dataset folder)
  Camera camera;
  Image image;            // RGB, composited
  Image mask;             // 1 where the pixel counts in the loss, the metrics and densification, 0 where not; empty: all count
  double nearBound = 0;   // LLFF bounds along the view axis in the loaded frame; 0 when unknown
  double farBound = 0;
};

struct Rect {
  double xMin = 0, yMin = 0, xMax = 0, yMax = 0;
};

// The water's index of refraction: 1.33 unless water.json or --ior says otherwise, and
// accepted wherever it is read (water.json, --ior, a run's config.json) when finite and in
// [kIorMin, kIorMax): below 1 the water would be thinner than air.
constexpr double kWaterIor = 1.33;
constexpr double kIorMin = 1.0, kIorMax = 4.0;
inline bool validIor(double ior) { return ior >= kIorMin && ior < kIorMax; }  // false for NaN
const char* const kIorRange = "a finite number in [1, 4)";

struct WaterMetadata {
  // water.json "frame": "loaded" (the default: its values are in the frame the loader makes, for
  // LLFF the recentred and scaled one) or "dataset" (in the frame of the dataset's own poses: an
  // LLFF dataset's poses are then used as they are, neither recentred nor scaled; `refrax synth`
  // writes this, so its LLFF files load with its water.json).
  bool datasetFrame = false;
  double ior = kWaterIor;
  std::optional<double> height;  // initial (mean) water height, world z
  std::optional<double> depth;   // how far under the water the scene reaches
  std::optional<Rect> domain;    // the height field's domain in x, y
};

struct DatasetOptions {
  glm::dvec3 background{0.0, 0.0, 0.0};  // for RGBA images
  int llffFactor = 1;                    // images_<factor>/ (1: images/)
  int llffHold = 8;                      // every llffHold-th LLFF image is a test view
  // LLFF and COLMAP: the test views by index in name order (from 0) or by file name, in
  // place of llffHold (NeRFrac's protocol: {"4"}, the centre of its nine views).
  std::vector<std::string> testViews;
  // Overrides of water.json (command-line options).
  std::optional<double> ior, waterHeight, waterDepth;
  std::optional<Rect> domain;
  std::optional<glm::dvec3> up;          // COLMAP: the water's up in the model's frame (else derived)
};

// A sparse 3D point the poses were computed with (COLMAP's points3D), in the loaded frame.
struct SparsePoint {
  glm::dvec3 position{0};
  glm::dvec3 colour{0};  // 0..1
};

struct Dataset {
  std::string root;
  std::string format;                             // "blender", "llff", "colmap" or "nerfstudio"
  std::map<std::string, std::vector<View>> splits;  // "train", "test", ...
  WaterMetadata water;
  glm::dmat4 normalization{1.0};                  // original world -> loaded world (LLFF, COLMAP)
  std::vector<std::string> notes;                 // what the loader derived or left out, for `refrax inspect` and `train`
  std::vector<SparsePoint> points;                // COLMAP's or nerfstudio's sparse points (--init-points); empty for other formats

  const std::vector<View>& split(const std::string& name) const;  // refrax::Error when absent
};

// Detects the format (transforms_train.json: Blender; poses_bounds.npy: LLFF; a COLMAP model).
Dataset loadDataset(const std::string& folder, const DatasetOptions& options = {});
Dataset loadBlenderDataset(const std::string& folder, const DatasetOptions& options = {});
Dataset loadLlffDataset(const std::string& folder, const DatasetOptions& options = {});
Dataset loadColmapDataset(const std::string& folder, const DatasetOptions& options = {});
Dataset loadNerfstudioDataset(const std::string& folder, const DatasetOptions& options = {});

// Counts the views with masks into d.notes ("masks: N of M views").
void noteMasks(Dataset& d);

// Which of an LLFF or COLMAP dataset's images (file names in name order) are test views:
// options.testViews when given (each an index from 0 or a file name; refrax::Error naming
// --test-views for one that matches no image, and when no training view would remain), else
// every llffHold-th from the first (none for 0; refrax::Error below 0).
std::vector<bool> testViewFlags(const std::vector<std::string>& files, const DatasetOptions& options, const std::string& where);

// The image folder of an LLFF or COLMAP dataset: images/, or images_<factor>/ (--llff-factor).
std::string imageFolder(const std::string& folder, int factor);
// Its masks' folder: masks/, or masks_<factor>/.
std::string maskFolder(const std::string& folder, int factor);

// water.json of the folder (defaults when absent) with the options' overrides applied.
WaterMetadata loadWaterMetadata(const std::string& folder, const DatasetOptions& options = {});

// Checks a camera-to-world matrix: finite, rotation orthonormal (within 1e-3, either
// handedness is refused if not a proper rotation: det > 0), last row (0 0 0 1).
void validateCameraToWorld(const glm::dmat4& cameraToWorld, const std::string& where);

// The LLFF conventions above as a pure function: rows of poses_bounds.npy (17 values each)
// to cameras (focal divided by `factor`, size from width/height given) and bounds, scaled and
// recentred (unless `keepFrame`: water.json's "frame": "dataset"); `normalization` receives
// the map from the original frame.
struct LlffCameras {
  std::vector<Camera> cameras;
  std::vector<double> nearBounds, farBounds;
  glm::dmat4 normalization{1.0};
};
LlffCameras llffCameras(const std::vector<double>& posesBounds, size_t count, int factor, int imageWidth, int imageHeight,
                        const std::string& where, bool keepFrame = false);

}  // namespace refrax
