// Image loss math shared by the loss shaders and the CPU reference (see shared_prelude.glsl):
//   L = 0.8 * L1 + 0.2 * (1 - SSIM), SSIM as 3D Gaussian Splatting computes it: an 11x11
//   Gaussian window (sigma 1.5, the outer product of a normalised 1D window), per channel,
//   zero padding ("same" size output, windows at the border see zeros), K1 0.01, K2 0.03,
//   data range 1, averaged over every pixel and channel.
// The window's local moments are mu1 = G*x, mu2 = G*y, exx = G*(x^2), eyy = G*(y^2),
// exy = G*(xy); ssimTerms gives the SSIM map value at one pixel and its partial
// derivatives with respect to mu1, exx and exy (the moments that depend on the rendered
// image x), so the backward is three more blurs of those partials (the adjoint of a
// zero-padded correlation with a symmetric window is the same correlation).
#if defined(__cplusplus) || !defined(REFRAX_IMAGE_LOSS_GLSL)
#ifndef __cplusplus
#define REFRAX_IMAGE_LOSS_GLSL
#endif

const int kSsimRadius = 5;  // 11 taps
const real kSsimC1 = real(0.0001);  // (K1 * data range)^2
const real kSsimC2 = real(0.0009);  // (K2 * data range)^2
const real kLossL1Weight = real(0.8);
const real kLossSsimWeight = real(0.2);

// Normalised 1D Gaussian window, sigma 1.5, tap `offset` in [-5, 5].
SHARED_FN real ssimWindowWeight(int offset) {
  real sum = real(0);
  for (int i = -kSsimRadius; i <= kSsimRadius; i++) sum += exp(-real(i * i) / real(4.5));
  return exp(-real(offset * offset) / real(4.5)) / sum;
}

// SSIM map value at one pixel from the window moments, with dS/dmu1, dS/dexx, dS/dexy
// (total derivatives: sigma1^2 = exx - mu1^2 and sigma12 = exy - mu1 mu2 are expanded).
SHARED_FN void ssimTerms(real mu1, real mu2, real exx, real eyy, real exy, OUT(real) value, OUT(real) dMu1,
                         OUT(real) dExx, OUT(real) dExy) {
  real s11 = exx - mu1 * mu1;
  real s22 = eyy - mu2 * mu2;
  real s12 = exy - mu1 * mu2;
  real a1 = real(2) * mu1 * mu2 + kSsimC1;
  real a2 = real(2) * s12 + kSsimC2;
  real b1 = mu1 * mu1 + mu2 * mu2 + kSsimC1;
  real b2 = s11 + s22 + kSsimC2;
  real inv = real(1) / (b1 * b2);
  value = a1 * a2 * inv;
  // partials holding (mu1, s11, s12) independent
  real dSdMu1 = real(2) * mu2 * a2 * inv - value * real(2) * mu1 / b1;
  real dSdS11 = -value / b2;
  real dSdS12 = real(2) * a1 * inv;
  dMu1 = dSdMu1 - real(2) * mu1 * dSdS11 - mu2 * dSdS12;
  dExx = dSdS11;
  dExy = dSdS12;
}

// dL1/dx of |x - y| (0 where they are equal, as torch's sign).
SHARED_FN real l1Slope(real x, real y) { return x > y ? real(1) : (x < y ? real(-1) : real(0)); }

// Density regulariser term sigmoid(logit)^2 and its derivative wrt the logit.
SHARED_FN real sigmoidOf(real logit) { return real(1) / (real(1) + exp(-logit)); }
SHARED_FN real densitySquareSlope(real logit) {
  real s = sigmoidOf(logit);
  return real(2) * s * s * (real(1) - s);
}
#endif
