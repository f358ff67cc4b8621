#pragma once
// Host mirror of shaders/include/surface_record.glsl: what the surface stage records per ray
// for its backward and for the caller (which triangle, where, what happened).
#include <cstdint>

namespace refrax {

struct SurfaceRecord {
  uint32_t cell;  // i | j << 16 on the lattice of `level`
  uint32_t info;  // side | level << 1 | flags << 8
  float t;        // hit distance along the normalised direction
  float u, v;     // barycentrics of corners 1 and 2
  uint32_t pad[3];

  uint32_t flags() const { return info >> 8; }
  uint32_t side() const { return info & 1u; }
  uint32_t level() const { return (info >> 1) & 0x7Fu; }
  uint32_t cellI() const { return cell & 0xFFFFu; }
  uint32_t cellJ() const { return cell >> 16; }
};
static_assert(sizeof(SurfaceRecord) == 32, "SurfaceRecord must match the std430 SurfaceRecord");

constexpr uint32_t kSurfaceHit = 1u;            // refracted at the surface
constexpr uint32_t kSurfaceMissed = 2u;         // missed the domain: continues unrefracted
constexpr uint32_t kSurfaceInvalidRay = 4u;     // NaN/inf or zero-length input: traces nothing
constexpr uint32_t kSurfaceFallback = 8u;       // some level kept the nearest child by plane distance
constexpr uint32_t kSurfaceBackFacing = 16u;    // the interpolated normal faced away and was flipped
constexpr uint32_t kSurfaceDegenerate = 32u;    // parallel to the final triangle: continues unrefracted
constexpr uint32_t kSurfaceLookupFailed = 64u;  // a needed height was never evaluated (a bug if ever set)

}  // namespace refrax
