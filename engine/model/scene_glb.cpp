#include "engine/model/scene_glb.h"

#include <sstream>

#include <tiny_gltf.h>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {
namespace {

tinygltf::Value object(std::initializer_list<std::pair<const std::string, tinygltf::Value>> fields) {
  return tinygltf::Value(tinygltf::Value::Object(fields));
}

void addNode(tinygltf::Model& m, const std::string& name, tinygltf::Primitive prim) {
  tinygltf::Mesh mesh;
  mesh.name = name;
  mesh.primitives.push_back(std::move(prim));
  m.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = name;
  node.mesh = int(m.meshes.size() - 1);
  m.nodes.push_back(node);
  m.scenes[0].nodes.push_back(int(m.nodes.size() - 1));
}

void addSplats(tinygltf::Model& m, const GltfSplats& s) {
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_POINTS;
  prim.attributes["POSITION"] = addGltfFloatAccessor(m, s.positions, 3, true);
  prim.attributes["COLOR_0"] = addGltfFloatAccessor(m, s.colors, 4, false);
  prim.attributes["KHR_gaussian_splatting:ROTATION"] = addGltfFloatAccessor(m, s.rotations, 4, false);
  prim.attributes["KHR_gaussian_splatting:SCALE"] = addGltfFloatAccessor(m, s.scales, 3, false);
  prim.attributes["KHR_gaussian_splatting:OPACITY"] = addGltfFloatAccessor(m, s.opacities, 1, false);
  for (uint32_t l = 0; l <= s.shDegree; l++)
    for (uint32_t n = 0; n < 2 * l + 1; n++)
      prim.attributes["KHR_gaussian_splatting:SH_DEGREE_" + std::to_string(l) + "_COEF_" + std::to_string(n)] =
          addGltfFloatAccessor(m, s.sh[l * l + n], 3, false);
  // Refrax renders display-referred sRGB images and blends along the ray in the order of depth.
  prim.extensions["KHR_gaussian_splatting"] = object({{"kernel", tinygltf::Value(std::string("ellipse"))},
                                                      {"colorSpace", tinygltf::Value(std::string("srgb_rec709_display"))}});
  addNode(m, "gaussians", std::move(prim));
}

void addWater(tinygltf::Model& m, const GlbWater& w, const std::string& path) {
  if (w.mesh.normals.empty()) fail("glTF export " + path + ": the water mesh has no normals");
  tinygltf::Primitive prim = surfaceMeshPrimitive(m, w.mesh, path);

  // Clear water: white, smooth, no metal, all light transmitted and refracted at the ior, the
  // medium below as thick as the water is deep.
  tinygltf::Material mat;
  mat.name = "water";
  mat.pbrMetallicRoughness.baseColorFactor = {1, 1, 1, 1};
  mat.pbrMetallicRoughness.metallicFactor = 0;
  mat.pbrMetallicRoughness.roughnessFactor = 0;
  mat.doubleSided = false;  // the volume extension asks for a one-sided boundary: the water is seen from above
  mat.extensions["KHR_materials_transmission"] = object({{"transmissionFactor", tinygltf::Value(1.0)}});
  mat.extensions["KHR_materials_ior"] = object({{"ior", tinygltf::Value(w.ior)}});
  mat.extensions["KHR_materials_volume"] = object({{"thicknessFactor", tinygltf::Value(w.thickness)}});
  m.materials.push_back(mat);
  prim.material = int(m.materials.size() - 1);
  addNode(m, "water_surface", std::move(prim));
}

}  // namespace

void writeSceneGlb(const std::string& path, const GltfSplats& splats, const std::optional<GlbWater>& water) {
  if (path.size() < 4 || path.compare(path.size() - 4, 4, ".glb") != 0) fail("glTF export " + path + ": the file name must end in .glb");
  if (splats.count == 0) fail("glTF export " + path + ": there are no Gaussians to write");
  tinygltf::Model m;
  m.asset.version = "2.0";
  m.asset.generator = "Refrax";
  m.buffers.resize(1);
  m.scenes.resize(1);
  m.defaultScene = 0;
  m.extensionsUsed.push_back("KHR_gaussian_splatting");
  addSplats(m, splats);
  if (water) {
    addWater(m, *water, path);
    for (const char* e : {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"}) m.extensionsUsed.push_back(e);
  }
  while (m.buffers[0].data.size() % 4) m.buffers[0].data.push_back(0);
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&m, stream, /*prettyPrint=*/false, /*writeBinary=*/true))
    fail("glTF export " + path + ": tinygltf could not serialise the scene");
  writeTextAtomic(path, stream.str());
}

}  // namespace refrax
