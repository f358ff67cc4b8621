#pragma once
// Gaussians in the de-facto 3DGS PLY layout: binary little-endian, one `vertex` element with
// float properties x y z nx ny nz f_dc_0..2 f_rest_0..44 opacity scale_0..2 rot_0..3, raw
// pre-activation values, f_rest channel-major (all of red's higher-band coefficients, then
// green's, then blue's). Reading accepts lower SH degrees (0, 9 or 24 f_rest; the missing
// coefficients are zero) and extra properties of any scalar type (skipped); anything
// missing, truncated or non-finite is one clear refrax::Error.
#include <string>

#include "engine/gaussian/gaussians.h"

namespace refrax {

GaussianSet readGaussiansPly(const std::string& path);
// Written atomically (engine/io/atomic_file.h): a failed write never leaves half a file.
void writeGaussiansPly(const std::string& path, const GaussianSet& set);

}  // namespace refrax
