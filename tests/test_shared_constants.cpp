// The constants and small formulas that the shaders and the double reference share
// (shaders/include/*.glsl), checked against sources of their own: the literal values of
// 3DGS and 3DGRT, the orthonormality of the SH basis integrated over the sphere, and the
// vertex-normal fan summed from its triangles' cross products. A test that compared the
// reference with the shaders could not notice a wrong constant: both read the same header.
#include <doctest/doctest.h>

#include <cmath>
#include <random>

#include "engine/gaussian/gaussian_math.h"
#include "engine/base/shared_math.h"
#include "engine/surface/surface_math.h"

// image_loss.glsl in a namespace of its own (it shares helper names with gaussian_math.glsl)
namespace refrax::loss64 {
REFRAX_SHARED_VOCABULARY(double, d)
#include "image_loss.glsl"
}

using namespace refrax;

TEST_CASE("SSIM window and constants are 3DGS's: an 11-tap Gaussian of sigma 1.5, C1 = 0.01^2, C2 = 0.03^2") {
  // 3DGS's loss_utils.gaussian(11, 1.5), the taps from the centre outwards.
  const double taps[6] = {0.26601171, 0.21300554, 0.10936069, 0.03600077, 0.00759876, 0.00102838};
  double sum = 0;
  for (int k = -5; k <= 5; k++) {
    CHECK(loss64::ssimWindowWeight(k) == doctest::Approx(taps[std::abs(k)]).epsilon(1e-6));
    sum += loss64::ssimWindowWeight(k);
  }
  CHECK(sum == doctest::Approx(1.0).epsilon(1e-12));
  CHECK(loss64::kSsimRadius == 5);
  CHECK(loss64::kSsimC1 == doctest::Approx(0.01 * 0.01).epsilon(1e-12));
  CHECK(loss64::kSsimC2 == doctest::Approx(0.03 * 0.03).epsilon(1e-12));
}

TEST_CASE("hit thresholds are 3DGRT's and 3DGS's literal values") {
  CHECK(f64::kMinKernelResponse == 0.0113);  // 3DGRT: the particle kernel's minimum response
  CHECK(f64::kMinAlpha == 1.0 / 255.0);      // 3DGS and 3DGRT: a hit below alpha 1/255 is skipped
  CHECK(f64::kMaxAlpha == 0.99);             // 3DGS: alpha = min(0.99, ...)
  CHECK(f64::kMinTransmittance == 0.001);    // 3DGRT: a ray stops below transmittance 1e-3
}

// Real spherical harmonics up to degree 3 are orthonormal over the sphere: the integral of
// Y_k Y_l is 1 for k = l and 0 otherwise. That fixes every constant's size; the signs are
// 3DGS's (sh_utils.eval_sh), checked at one direction against its formula written out here.
TEST_CASE("SH basis: orthonormal over the sphere (numerical integration), and 3DGS's signs") {
  const int nTheta = 240, nPhi = 480;
  double gram[16][16] = {};
  for (int a = 0; a < nTheta; a++) {
    double theta = (a + 0.5) * M_PI / nTheta;
    for (int b = 0; b < nPhi; b++) {
      double phi = (b + 0.5) * 2.0 * M_PI / nPhi;
      glm::dvec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      double w = std::sin(theta) * (M_PI / nTheta) * (2.0 * M_PI / nPhi);
      double y[16];
      for (uint32_t k = 0; k < 16; k++) y[k] = f64::shBasis(k, d);
      for (int k = 0; k < 16; k++)
        for (int l = 0; l < 16; l++) gram[k][l] += w * y[k] * y[l];
    }
  }
  double worst = 0;
  for (int k = 0; k < 16; k++)
    for (int l = 0; l < 16; l++) worst = std::max(worst, std::abs(gram[k][l] - (k == l ? 1.0 : 0.0)));
  CHECK(worst < 1e-4);  // the midpoint rule's error at this resolution

  const double x = 0.48, yy = -0.6, z = std::sqrt(1.0 - 0.48 * 0.48 - 0.36);
  const double C0 = 0.28209479177387814, C1 = 0.4886025119029199;
  const double C2[5] = {1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396};
  const double C3[7] = {-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154,
                        -0.4570457994644658, 1.445305721320277,  -0.5900435899266435};
  const double expected[16] = {C0,
                               -C1 * yy,
                               C1 * z,
                               -C1 * x,
                               C2[0] * x * yy,
                               C2[1] * yy * z,
                               C2[2] * (2 * z * z - x * x - yy * yy),
                               C2[3] * x * z,
                               C2[4] * (x * x - yy * yy),
                               C3[0] * yy * (3 * x * x - yy * yy),
                               C3[1] * x * yy * z,
                               C3[2] * yy * (4 * z * z - x * x - yy * yy),
                               C3[3] * z * (2 * z * z - 3 * x * x - 3 * yy * yy),
                               C3[4] * x * (4 * z * z - x * x - yy * yy),
                               C3[5] * z * (x * x - yy * yy),
                               C3[6] * x * (x * x - 3 * yy * yy)};
  for (uint32_t k = 0; k < 16; k++) {
    CAPTURE(k);
    CHECK(f64::shBasis(k, glm::dvec3(x, yy, z)) == doctest::Approx(expected[k]).epsilon(1e-12));
    // its gradient (the backward's) against central differences
    glm::dvec3 d(x, yy, z), g = f64::shBasisGradient(k, d);
    for (int a = 0; a < 3; a++) {
      glm::dvec3 p = d, m = d;
      p[a] += 1e-6;
      m[a] -= 1e-6;
      CHECK(g[a] == doctest::Approx((f64::shBasis(k, p) - f64::shBasis(k, m)) / 2e-6).epsilon(1e-6).scale(1.0));
    }
  }
}

// The unnormalised vertex normal of a lattice vertex is the sum of its six fan triangles'
// cross products (twice their area-weighted normals), over hx hy: summed here from the
// triangles themselves, for random heights and spacings.
TEST_CASE("vertex normals: the fan's cross products, summed from scratch") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0), S(0.2, 3.0);
  for (int trial = 0; trial < 50; trial++) {
    double hx = S(rng), hy = S(rng), zc = U(rng), z[6];
    for (double& v : z) v = U(rng);
    glm::dvec3 c(0, 0, zc), fan(0);
    for (int k = 0; k < 6; k++) {
      int di, dj, di2, dj2;
      f64::ringOffset(k, di, dj);
      f64::ringOffset((k + 1) % 6, di2, dj2);
      glm::dvec3 p(di * hx, dj * hy, z[k]), q(di2 * hx, dj2 * hy, z[(k + 1) % 6]);
      fan += glm::cross(p - c, q - c);
    }
    fan /= hx * hy;
    glm::dvec3 n = f64::vertexNormalRaw(z[0], z[1], z[2], z[3], z[4], z[5], hx, hy);
    CAPTURE(trial);
    for (int a = 0; a < 3; a++) CHECK(n[a] == doctest::Approx(fan[a]).epsilon(1e-12).scale(1.0));
  }
}
