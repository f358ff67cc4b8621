#include "engine/camera/lens.h"

#include <algorithm>
#include <cmath>

#include "engine/base/error.h"
#include "engine/base/number_text.h"
#include "engine/camera/camera.h"
#include "engine/camera/lens_math.h"

namespace refrax {
namespace {

// A radial-tangential lens with all terms zero is a pinhole (and traced as one).
Lens radialTangential(double k1, double k2, double k3, double k4, double k5, double k6, double p1, double p2) {
  Lens lens;
  lens.radial = {k1, k2, k3, k4};
  lens.extra = {k5, k6, p1, p2};
  lens.kind = (lens.radial == glm::dvec4(0.0) && lens.extra == glm::dvec4(0.0)) ? LensKind::Pinhole : LensKind::RadialTangential;
  return lens;
}

Lens fisheye(double k1, double k2, double k3, double k4) {
  Lens lens;
  lens.kind = LensKind::Fisheye;
  lens.radial = {k1, k2, k3, k4};
  return lens;
}

const char* kindName(LensKind kind) {
  switch (kind) {
    case LensKind::Pinhole: return "pinhole";
    case LensKind::RadialTangential: return "radial-tangential (OpenCV)";
    case LensKind::Fisheye: return "fisheye (OpenCV equidistant)";
  }
  return "?";
}

// Whether the lens has a ray for normalised image point m: the inverse converges to within
// tolerance (normalised units) on the model's rising branch, forward for the perspective kinds.
bool lensInvertsAt(const Lens& lens, const glm::dvec2& m, double tolerance) {
  const int kind = int(lens.kind);
  const glm::dvec3 d = f64::lensUnproject(kind, lens.radial, lens.extra, m);
  if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || !lensImagesDirection(lens, d)) return false;
  const glm::dvec2 back = f64::lensProject(kind, lens.radial, lens.extra, d);
  return glm::length(back - m) <= tolerance;
}

}  // namespace

bool lensImagesDirection(const Lens& lens, const glm::dvec3& d) {
  if (lens.kind == LensKind::Fisheye) {
    // Past the lens's largest angle its polynomial may turn back into the image.
    const double theta = std::atan2(glm::length(glm::dvec2(d)), d.z);
    double slope = 0;
    const double thetaD = f64::lensFisheyeRadius(lens.radial, theta, slope);
    return glm::length(d) > 0 && slope > 0 && (theta == 0 || thetaD > 0);
  }
  if (!(d.z > 0)) return false;
  if (lens.kind == LensKind::Pinhole) return true;
  // Likewise a distortion that folds over maps points far outside the image back into it.
  const glm::dvec2 q = glm::dvec2(d) / d.z;
  glm::dvec2 dx, dy;
  const glm::dvec2 m = f64::lensRadialTangential(lens.radial, lens.extra, q, dx, dy);
  return dx.x * dy.y - dy.x * dx.y > 0 && glm::dot(m, q) >= 0;
}

LensIntrinsics intrinsicsFromColmap(const std::string& model, const std::vector<double>& params, const std::string& where) {
  struct Known {
    const char* name;
    size_t count;
  };
  static const Known known[] = {{"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4},         {"SIMPLE_RADIAL", 4},         {"RADIAL", 5},
                                {"OPENCV", 8},         {"FULL_OPENCV", 12},   {"OPENCV_FISHEYE", 8},        {"SIMPLE_RADIAL_FISHEYE", 4},
                                {"RADIAL_FISHEYE", 5}};
  const Known* k = std::find_if(std::begin(known), std::end(known), [&](const Known& e) { return model == e.name; });
  if (k == std::end(known))
    fail(where + ": COLMAP's " + model +
         " camera model has no ray in Refrax (it traces PINHOLE, SIMPLE_PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV, "
         "OPENCV_FISHEYE, SIMPLE_RADIAL_FISHEYE and RADIAL_FISHEYE): run `colmap image_undistorter` on the model, or recalibrate with one of those");
  if (params.size() != k->count)
    fail(where + ": COLMAP's " + model + " camera model has " + std::to_string(k->count) + " parameters, the file gives " + std::to_string(params.size()));
  for (double p : params)
    if (!std::isfinite(p)) fail(where + ": a " + model + " camera parameter is not a finite number");
  const std::vector<double>& p = params;
  LensIntrinsics out;
  const bool oneFocal = k->count == 3 || model == "SIMPLE_RADIAL" || model == "RADIAL" || model == "SIMPLE_RADIAL_FISHEYE" || model == "RADIAL_FISHEYE";
  if (oneFocal) {
    out.fx = out.fy = p[0], out.cx = p[1], out.cy = p[2];
  } else {
    out.fx = p[0], out.fy = p[1], out.cx = p[2], out.cy = p[3];
  }
  if (model == "SIMPLE_RADIAL") out.lens = radialTangential(p[3], 0, 0, 0, 0, 0, 0, 0);
  if (model == "RADIAL") out.lens = radialTangential(p[3], p[4], 0, 0, 0, 0, 0, 0);
  if (model == "OPENCV") out.lens = radialTangential(p[4], p[5], 0, 0, 0, 0, p[6], p[7]);
  if (model == "FULL_OPENCV") out.lens = radialTangential(p[4], p[5], p[8], p[9], p[10], p[11], p[6], p[7]);
  if (model == "OPENCV_FISHEYE") out.lens = fisheye(p[4], p[5], p[6], p[7]);
  if (model == "SIMPLE_RADIAL_FISHEYE") out.lens = fisheye(p[3], 0, 0, 0);
  if (model == "RADIAL_FISHEYE") out.lens = fisheye(p[3], p[4], 0, 0);
  return out;
}

std::string colmapModelOf(const Camera& c, std::vector<double>& params) {
  const Lens& l = c.lens;
  switch (l.kind) {
    case LensKind::Pinhole: params = {c.fx, c.fy, c.cx, c.cy}; return "PINHOLE";
    case LensKind::Fisheye: params = {c.fx, c.fy, c.cx, c.cy, l.radial[0], l.radial[1], l.radial[2], l.radial[3]}; return "OPENCV_FISHEYE";
    case LensKind::RadialTangential: break;
  }
  if (l.radial[2] == 0 && l.radial[3] == 0 && l.extra[0] == 0 && l.extra[1] == 0) {
    params = {c.fx, c.fy, c.cx, c.cy, l.radial[0], l.radial[1], l.extra[2], l.extra[3]};
    return "OPENCV";
  }
  params = {c.fx, c.fy, c.cx, c.cy, l.radial[0], l.radial[1], l.extra[2], l.extra[3], l.radial[2], l.radial[3], l.extra[0], l.extra[1]};
  return "FULL_OPENCV";
}

Lens lensFromTransformsFields(const LensFields& f, const std::string& where) {
  for (double v : {f.k1, f.k2, f.k3, f.k4, f.p1, f.p2})
    if (!std::isfinite(v)) fail(where + ": a lens coefficient (k1..k4, p1, p2) is not a finite number");
  if (f.cameraModel == "OPENCV_FISHEYE") {
    if (f.p1 != 0 || f.p2 != 0) fail(where + ": camera_model OPENCV_FISHEYE has no tangential terms, but p1 or p2 is not 0");
    return fisheye(f.k1, f.k2, f.k3, f.k4);
  }
  if (f.cameraModel.empty() || f.cameraModel == "OPENCV" || f.cameraModel == "PINHOLE" || f.cameraModel == "SIMPLE_PINHOLE") {
    if (f.k4 != 0)
      fail(where + ": k4 = " + numberText(f.k4) + " with camera_model " + (f.cameraModel.empty() ? "OPENCV" : f.cameraModel) +
           " (nerfstudio's r^8 term) is a lens Refrax does not trace; OpenCV's model takes k1, k2, k3, p1, p2");
    return radialTangential(f.k1, f.k2, f.k3, 0, 0, 0, f.p1, f.p2);
  }
  fail(where + ": camera_model " + f.cameraModel + " is not one Refrax traces (OPENCV, OPENCV_FISHEYE, PINHOLE, SIMPLE_PINHOLE)");
}

LensFields transformsFieldsOf(const Lens& lens) {
  LensFields f;
  if (lens.kind == LensKind::Pinhole) return f;
  if (lens.kind == LensKind::RadialTangential && (lens.radial[3] != 0 || lens.extra[0] != 0 || lens.extra[1] != 0))
    fail("a transforms.json cannot hold OpenCV's rational terms k4..k6 (write the dataset as COLMAP instead)");
  f.cameraModel = lens.kind == LensKind::Fisheye ? "OPENCV_FISHEYE" : "OPENCV";
  f.k1 = lens.radial[0], f.k2 = lens.radial[1], f.k3 = lens.radial[2];
  if (lens.kind == LensKind::Fisheye) f.k4 = lens.radial[3];
  else f.p1 = lens.extra[2], f.p2 = lens.extra[3];
  return f;
}

std::string lensDescription(const Lens& lens) {
  std::string s = kindName(lens.kind);
  const char* names[8] = {"k1", "k2", "k3", "k4", "k5", "k6", "p1", "p2"};
  for (int i = 0; i < 8; i++) {
    const double v = i < 4 ? lens.radial[i] : lens.extra[i - 4];
    if (v != 0) s += std::string(" ") + names[i] + " " + numberText(v);
  }
  return s;
}

void checkLensCoversImage(const Camera& c, const std::string& where) {
  if (!c.lens.distorts()) return;
  const double W = c.width, H = c.height;
  const double tolerance = 1e-6 / std::max(c.fx, c.fy);  // 1e-6 pixel
  auto check = [&](double u, double v) {
    const glm::dvec2 m((u - c.cx) / c.fx, (v - c.cy) / c.fy);
    if (!lensInvertsAt(c.lens, m, tolerance))
      fail(where + ": the " + std::string(kindName(c.lens.kind)) + " lens (k1..k4 " + numberText(c.lens.radial[0]) + " " + numberText(c.lens.radial[1]) +
           " " + numberText(c.lens.radial[2]) + " " + numberText(c.lens.radial[3]) + ", k5 k6 p1 p2 " + numberText(c.lens.extra[0]) + " " +
           numberText(c.lens.extra[1]) + " " + numberText(c.lens.extra[2]) + " " + numberText(c.lens.extra[3]) + ") has no ray for image point (" +
           numberText(u) + ", " + numberText(v) + "): its distortion folds over there or its inverse does not converge");
  };
  const int n = 64;  // points per edge and diagonal
  for (int i = 0; i <= n; i++) {
    const double s = double(i) / n;
    check(s * W, 0), check(s * W, H), check(0, s * H), check(W, s * H);
    check(s * W, s * H), check(s * W, (1 - s) * H);
  }
  for (int j = 0; j <= 16; j++)
    for (int i = 0; i <= 16; i++) check(W * i / 16.0, H * j / 16.0);
}

}  // namespace refrax
