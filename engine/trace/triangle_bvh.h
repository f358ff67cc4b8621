#pragma once
// Box BVHs over triangle meshes (engine/trace/box_bvh.h) for the compute trace backend: the mesh
// swap (engine/surface/mesh_surface.h) and the surface preview trace triangles through these where
// the ray-query backend builds a BLAS.
#include <cstdint>
#include <vector>

#include "engine/trace/box_bvh.h"
#include "engine/trace/presort.h"

namespace refrax {

// Boxes of the triangles (3 vertex indices each) of packed xyz positions, and the triangles
// reordered by the median split of those boxes (what a BVH over them in index order wants).
std::vector<Box> triangleBoxes(const std::vector<float>& positions, const std::vector<uint32_t>& triangles);
std::vector<uint32_t> trianglesInSplitOrder(const std::vector<float>& positions, const std::vector<uint32_t>& triangles);
// A triangle mesh's BVH for the compute backend: its boxes refitted into the tree once.
BoxBvh createTriangleBvh(Context& ctx, const std::vector<float>& positions, const std::vector<uint32_t>& trianglesInOrder);

}  // namespace refrax
