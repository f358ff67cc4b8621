#pragma once
// A camera's lens: one of the models in shaders/include/lens.glsl with its coefficients, made
// from COLMAP's camera models or a transforms.json's fields (nerfstudio's and instant-ngp's),
// written back to COLMAP's, and checked to be invertible over a whole image.
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace refrax {

enum class LensKind : int { Pinhole = 0, RadialTangential = 1, Fisheye = 2 };  // LENS_* in lens.glsl

struct Lens {
  LensKind kind = LensKind::Pinhole;
  glm::dvec4 radial{0.0};  // k1 k2 k3 k4 (radial-tangential: k4 is the denominator's r^2 term)
  glm::dvec4 extra{0.0};   // k5 k6 p1 p2 (radial-tangential only)
  bool distorts() const { return kind != LensKind::Pinhole; }
};

struct Camera;

// Intrinsics of a COLMAP camera model (params in COLMAP's order; pixels as COLMAP's, centres at
// integer + 0.5, which are Refrax's). refrax::Error naming `where` for a model Refrax has no
// ray for (FOV, THIN_PRISM_FISHEYE) or a wrong parameter count.
struct LensIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Lens lens;
};
LensIntrinsics intrinsicsFromColmap(const std::string& model, const std::vector<double>& params, const std::string& where);
// The COLMAP model that holds the camera's intrinsics exactly (PINHOLE, OPENCV, FULL_OPENCV or
// OPENCV_FISHEYE) and its params in COLMAP's order.
std::string colmapModelOf(const Camera& camera, std::vector<double>& params);

// The lens of a transforms.json's camera_model and k1..k4, p1, p2 (absent: 0). "OPENCV" (or no
// camera_model) reads k1, k2, k3, p1, p2; "OPENCV_FISHEYE" reads k1..k4; nerfstudio's OPENCV
// k4 is an r^8 term no OpenCV model has, so a non-zero one is refused, as are other models.
struct LensFields {
  std::string cameraModel;  // "" when absent
  double k1 = 0, k2 = 0, k3 = 0, k4 = 0, p1 = 0, p2 = 0;
};
Lens lensFromTransformsFields(const LensFields& fields, const std::string& where);
// The same fields for a camera (the synthesiser's writer): camera_model and the non-zero terms.
LensFields transformsFieldsOf(const Lens& lens);

// Whether the lens images camera-frame direction d (OpenCV's frame: x right, y down, z
// forward) on its unfolded branch: in front of a perspective lens, where its distortion still
// rises and does not flip the point across the centre (past that a folding model would map
// far-off points back into the image).
bool lensImagesDirection(const Lens& lens, const glm::dvec3& d);

// "pinhole", or the kind and its non-zero coefficients ("fisheye (OpenCV equidistant) k1 0.01").
std::string lensDescription(const Lens& lens);

// Checks that every pixel of the camera's image has a ray through its lens: at the image's
// border, its diagonals and a grid inside, the inverse converges (the ray projects back to
// within 1e-6 pixel) on the model's unfolded branch (positive Jacobian), and a perspective
// model's ray points forward. refrax::Error naming `where` and the pixel otherwise.
void checkLensCoversImage(const Camera& camera, const std::string& where);

}  // namespace refrax
