// Lens models of the cameras people bring (COLMAP's and OpenCV's), shared by the camera-ray
// shader and the CPU reference (shared_prelude.glsl). Directions here are in OpenCV's camera
// frame (x right, y down, looking down +z); m is the normalised image point
// ((u - cx) / fx, (v - cy) / fy), u, v in pixels.
//   LENS_PINHOLE:           m = (x, y) / z.
//   LENS_RADIAL_TANGENTIAL: OpenCV's model (COLMAP SIMPLE_RADIAL, RADIAL, OPENCV, FULL_OPENCV):
//     p = (x, y) / z, r2 = |p|^2, R = (1 + k1 r2 + k2 r2^2 + k3 r2^3) / (1 + k4 r2 + k5 r2^2 + k6 r2^3),
//     m = R p + (2 p1 px py + p2 (r2 + 2 px^2), p1 (r2 + 2 py^2) + 2 p2 px py).
//   LENS_FISHEYE: OpenCV's equidistant fisheye (COLMAP OPENCV_FISHEYE, SIMPLE_RADIAL_FISHEYE,
//     RADIAL_FISHEYE): theta = the angle from the axis, thetaD = theta (1 + k1 theta^2 + k2 theta^4
//     + k3 theta^6 + k4 theta^8), m = thetaD (x, y) / |(x, y)|. Taken through theta, not x/z, so a
//     ray at or past 90 degrees from the axis (a 180-degree lens's rim) is still defined.
// Coefficients: radial = (k1, k2, k3, k4), extra = (k5, k6, p1, p2) (the fisheye reads radial only).
// The inverse (lensUnproject) is Newton's method from m, a fixed LENS_NEWTON_STEPS steps so the
// shader and the reference run the same arithmetic; it converges where the model does not fold
// over, which the host checks for each camera over its whole image (engine/camera/lens.h).
#if defined(__cplusplus) || !defined(REFRAX_LENS_GLSL)
#ifndef __cplusplus
#define REFRAX_LENS_GLSL
#endif

#define LENS_PINHOLE 0
#define LENS_RADIAL_TANGENTIAL 1
#define LENS_FISHEYE 2
#define LENS_NEWTON_STEPS 20

// The radial-tangential map m(p) and its Jacobian's columns dm/dpx, dm/dpy.
SHARED_FN real2 lensRadialTangential(real4 radial, real4 extra, real2 p, OUT(real2) dx, OUT(real2) dy) {
  real r2 = dot(p, p);
  real num = real(1) + r2 * (radial.x + r2 * (radial.y + r2 * radial.z));
  real den = real(1) + r2 * (radial.w + r2 * (extra.x + r2 * extra.y));
  real numD = radial.x + r2 * (real(2) * radial.y + real(3) * r2 * radial.z);
  real denD = radial.w + r2 * (real(2) * extra.x + real(3) * r2 * extra.y);
  real R = num / den, dR = (numD * den - num * denD) / (den * den);  // dR / dr2
  real p1 = extra.z, p2 = extra.w;
  real2 m = R * p + real2(real(2) * p1 * p.x * p.y + p2 * (r2 + real(2) * p.x * p.x), p1 * (r2 + real(2) * p.y * p.y) + real(2) * p2 * p.x * p.y);
  real mixed = real(2) * p.x * p.y * dR + real(2) * p1 * p.x + real(2) * p2 * p.y;  // dmx/dpy = dmy/dpx
  dx = real2(R + real(2) * p.x * p.x * dR + real(2) * p1 * p.y + real(6) * p2 * p.x, mixed);
  dy = real2(mixed, R + real(2) * p.y * p.y * dR + real(6) * p1 * p.y + real(2) * p2 * p.x);
  return m;
}

// The fisheye's thetaD(theta) and its derivative.
SHARED_FN real lensFisheyeRadius(real4 radial, real theta, OUT(real) derivative) {
  real t2 = theta * theta;
  derivative = real(1) + t2 * (real(3) * radial.x + t2 * (real(5) * radial.y + t2 * (real(7) * radial.z + t2 * real(9) * radial.w)));
  return theta * (real(1) + t2 * (radial.x + t2 * (radial.y + t2 * (radial.z + t2 * radial.w))));
}

// The normalised image point of camera-frame direction d (z > 0 for the perspective kinds).
SHARED_FN real2 lensProject(int kind, real4 radial, real4 extra, real3 d) {
  if (kind == LENS_FISHEYE) {
    real rxy = length(real2(d.x, d.y));
    if (rxy == real(0)) return real2(0);
    real derivative;
    return lensFisheyeRadius(radial, atan(rxy, d.z), derivative) * real2(d.x, d.y) / rxy;
  }
  real2 p = real2(d.x, d.y) / d.z;
  if (kind == LENS_PINHOLE) return p;
  real2 dx, dy;
  return lensRadialTangential(radial, extra, p, dx, dy);
}

// The unit camera-frame direction that lensProject maps to normalised image point m.
SHARED_FN real3 lensUnproject(int kind, real4 radial, real4 extra, real2 m) {
  if (kind == LENS_FISHEYE) {
    real rd = length(m);
    if (rd == real(0)) return real3(0, 0, 1);
    real theta = rd;
    for (int i = 0; i < LENS_NEWTON_STEPS; i++) {
      real derivative;
      real f = lensFisheyeRadius(radial, theta, derivative) - rd;
      theta -= f / derivative;
    }
    return real3(sin(theta) * m / rd, cos(theta));
  }
  real2 p = m;
  if (kind == LENS_RADIAL_TANGENTIAL) {
    for (int i = 0; i < LENS_NEWTON_STEPS; i++) {
      real2 dx, dy;
      real2 f = lensRadialTangential(radial, extra, p, dx, dy) - m;
      real det = dx.x * dy.y - dy.x * dx.y;
      p -= real2(dy.y * f.x - dy.x * f.y, dx.x * f.y - dx.y * f.x) / det;
    }
  }
  return normalize(real3(p, real(1)));
}
#endif
