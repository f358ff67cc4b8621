#pragma once
// Built-in surfaces named on a command line: flat[:HEIGHT],
// sine[:HEIGHT:AMPLITUDE:WAVELENGTH:DIRECTION_DEG] or triangle[:...] (the same fields), and the
// closed-form waves (engine/height/analytic_height.h) of the flat and sine ones, which the water
// surface lifts like any height field.
#include <string>

#include "engine/height/analytic_height.h"
#include "engine/surface/builtin_surfaces.h"

namespace refrax {

// Missing fields keep BuiltinSurface's defaults, the height `defaultHeight`; refrax::Error
// naming the spec for an unknown kind, a field that is not a number or a bad wavelength.
BuiltinSurface parseBuiltinSurface(const std::string& spec, float defaultHeight);
// flat and sine only (refrax::Error otherwise): base = height, one sine wave along the direction.
AnalyticWaves builtinSurfaceWaves(const BuiltinSurface& surface);

}  // namespace refrax
