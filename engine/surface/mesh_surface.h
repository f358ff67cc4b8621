#pragma once
// Surface swap (docs/method.md §1.4 "Surface editing"): any triangle mesh (e.g. read from glTF,
// engine/surface/gltf_surface.h) replaces the learned water surface, no retraining. Each camera
// ray is refracted at its closest hit on the mesh (interpolated vertex normals, Snell's law;
// shaders/include/mesh_refract.glsl) and handed to the Gaussian tracer like the rays of
// traceSurface. Also: baking a height source (e.g. the learned surface) into such a mesh
// once at render resolution, for fast viewing.
#include <cstdint>
#include <vector>

#include "engine/trace/box_bvh.h"
#include "engine/height/height_source.h"
#include "engine/surface/gltf_surface.h"
#include "engine/trace/rays.h"
#include "engine/surface/surface_record.h"
#include "engine/vk/vk_accel.h"
#include "engine/vk/vk_buffer.h"
#include "engine/vk/vk_pipeline.h"
#include "engine/surface/water_surface.h"

namespace refrax {

struct Context;

// A mesh that is a regular height grid as engine/surface/grid_mesh.h makes it: (cellsX+1) x (cellsY+1)
// vertices over [x0,x1]x[y0,y1], vertex (i, j) at j*(cellsX+1)+i, two triangles per cell.
struct HeightGridLayout {
  uint32_t cellsX = 0, cellsY = 0;
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

struct MeshSurface {  // a triangle mesh on the device, traced with ray queries (or walked as a grid)
  Buffer positions, normals, indices;  // packed float3 per vertex (the BLAS input), unit float3 per vertex, uint32x3
  AccelStruct blas;
  TopLevel top;
  BoxBvh bvh;  // the compute trace backend's triangle BVH (leaf k = triangle k), instead of blas/top
  bool built = false;
  uint32_t vertexCount = 0, triangleCount = 0;
  bool walkGrid = false;  // a height grid traced by walking its cells (mesh_refract.comp kGrid), not the BVH
  HeightGridLayout grid;
  float zMin = 0, zMax = 0;
  ComputePipeline refract;
};

// The unit vertex normals a MeshSurface of `mesh` uses: vertexNormals() when mesh.normals is
// empty, else mesh.normals normalised (in float, as uploaded). Validates the mesh: one clear
// refrax::Error for no triangles, a count that is not a multiple of 3, normals and positions
// differing in count, an index out of range, a non-finite position or normal, a zero normal.
std::vector<float> meshUnitNormals(const SurfaceMesh& mesh);

// Uploads the mesh (vertex normals from meshUnitNormals), builds BLAS+TLAS (submits and waits).
// refrax::Error for an empty mesh or non-finite values (see meshUnitNormals). With `grid`, the
// mesh must be that height grid (vertex count and xy positions are checked; one clear error
// otherwise) and cmdRefractThroughMesh walks its cells instead of the BVH: the same triangles,
// found without a BVH walk (on lavapipe 2.8x faster for the viewer's 256^2 baked grid at 256^2
// rays: 5 ms against 14; both match the double reference, tests/test_mesh_surface.cpp).
MeshSurface createMeshSurface(Context& ctx, const SurfaceMesh& mesh, const HeightGridLayout* grid = nullptr);

// Records: for each of `count` GpuRay in `rays`, the closest hit on the mesh; refracted[i] =
// GpuRay from the hit point (tmin 0) along the Snell-refracted unit direction (air -> water,
// eta = 1/ior; normal = barycentric interpolation of the vertex normals, normalised, flipped
// to face the ray), tmax = the rest of the ray's range; a ray that misses is copied
// unchanged; an invalid (NaN/inf, zero-length, tmin < 0 or tmax < tmin) ray gives the empty
// ray traceSurface writes (origin 0, tmin = tmax = 0). flags[i] (uint32) = kSurfaceHit /
// kSurfaceMissed / kSurfaceInvalidRay (| kSurfaceBackFacing when the normal was flipped).
// Starts with a barrier like the other cmd* stages.
void cmdRefractThroughMesh(VkCommandBuffer cb, const MeshSurface& mesh, const Buffer& rays, uint32_t count, float ior,
                           const Buffer& refracted, const Buffer& flags);

// A height source sampled on a regular (cellsX+1) x (cellsY+1) lattice over `domain` into a
// grid mesh (engine/surface/grid_mesh.h's vertices and triangles) with area-weighted vertex normals:
// how a learned surface is baked once at render resolution for fast viewing (the paper
// precomputes the surface at render resolution). Submits and waits. refrax::Error for an
// empty domain, zero cells, more than 2^26 vertices, or a non-finite height.
SurfaceMesh bakeHeightMesh(Context& ctx, const HeightSource& heights, const SurfaceDomain& domain, uint32_t cellsX, uint32_t cellsY);

}  // namespace refrax
