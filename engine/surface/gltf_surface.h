#pragma once
// The water surface as a glTF 2.0 triangle mesh (tinygltf), for exporting a trained surface
// and for swapping in any surface mesh (`--water mesh.gltf`).
//
// Axes: files hold glTF's (+Y up), the structs here Refrax's (+Z up), turned as
// engine/io/gltf_axes.h says (a proper rotation: a surface whose normals point up in Refrax
// points up in glTF).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/surface/grid_mesh.h"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace refrax {

struct SurfaceMesh {
  std::vector<float> positions;   // xyz per vertex, Refrax axes
  std::vector<float> normals;     // xyz per vertex (unit), or empty
  std::vector<uint32_t> indices;  // 3 per triangle, counter-clockwise seen from the normal's side
  size_t vertexCount() const { return positions.size() / 3; }
  size_t triangleCount() const { return indices.size() / 3; }
};

// The grid's vertices and triangles with area-weighted vertex normals.
SurfaceMesh surfaceMeshFromGrid(const GridMesh& grid);
// Area-weighted vertex normals of the triangles (a vertex no triangle uses gets +z).
std::vector<float> vertexNormals(const std::vector<float>& positions, const std::vector<uint32_t>& indices);

// Writes one mesh (one node, one triangle primitive: POSITION, NORMAL when present, uint32
// indices) as `.gltf` with the buffer embedded as a data URI, or `.glb`, by the extension;
// atomically (engine/io/atomic_file.h). refrax::Error for another extension, an empty or
// inconsistent mesh (index out of range, non-finite value).
void writeSurfaceGltf(const std::string& path, const SurfaceMesh& mesh);

// For writers of larger scenes (engine/model/scene_glb.h): bytes appended to buffer 0 as a
// view (4-byte aligned), a float accessor of 1, 3 or 4 components (min and max with
// `withBounds`, which POSITION needs), and the mesh as a triangle primitive in glTF axes
// (checked as writeSurfaceGltf checks it; refrax::Error naming `path`). Buffer 0 must exist.
int addGltfView(tinygltf::Model& model, const void* bytes, size_t size, int target);
int addGltfFloatAccessor(tinygltf::Model& model, const std::vector<float>& values, int components, bool withBounds);
tinygltf::Primitive surfaceMeshPrimitive(tinygltf::Model& model, const SurfaceMesh& mesh, const std::string& path);

// Reads a `.gltf` (buffers embedded or in files beside it) or `.glb`: every triangle primitive
// of the nodes of the default scene (scene 0 when none is named; every mesh once, untransformed,
// when the file has no scenes), merged into one mesh, node transforms applied, converted to
// Refrax axes. Positions and indices only (normals left empty: the surface computes its own).
// One clear refrax::Error for a missing or malformed file, a primitive that is not triangles,
// one without POSITION, sparse or non-float positions, indices out of range, no triangles.
SurfaceMesh readSurfaceGltf(const std::string& path);

}  // namespace refrax
