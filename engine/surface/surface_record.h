#pragma once
// What the surface stage records per ray for its backward and for the caller (which
// triangle, where, what happened): SurfaceRecord, its flags and its decoders
// (surfaceRecordFlags, ...Side, ...Level, ...CellI, ...CellJ), declared once in
// shaders/include/surface_record.glsl for the shaders and the host.
#include "engine/base/gpu_layout.h"

namespace refrax {
#include "surface_record.glsl"
}  // namespace refrax
