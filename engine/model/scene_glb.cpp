#include "engine/model/scene_glb.h"

#include <cstring>
#include <sstream>

#include <tiny_gltf.h>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"

namespace refrax {
namespace {

// The bytes appended to the one buffer as a view (4-byte aligned, as accessors need).
int addView(tinygltf::Model& m, const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buf = m.buffers[0].data;
  while (buf.size() % 4) buf.push_back(0);
  tinygltf::BufferView v;
  v.buffer = 0;
  v.byteOffset = buf.size();
  v.byteLength = bytes;
  v.target = target;
  buf.resize(buf.size() + bytes);
  std::memcpy(buf.data() + v.byteOffset, data, bytes);
  m.bufferViews.push_back(v);
  return int(m.bufferViews.size() - 1);
}

// A float accessor of `components` per element (1, 3 or 4); with `bounds`, its min and max
// (glTF requires them on POSITION).
int addFloatAccessor(tinygltf::Model& m, const std::vector<float>& values, int components, bool bounds = false) {
  tinygltf::Accessor a;
  a.bufferView = addView(m, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = components == 1 ? TINYGLTF_TYPE_SCALAR : components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
  a.count = values.size() / size_t(components);
  if (bounds) {
    a.minValues.assign(size_t(components), 1e300);
    a.maxValues.assign(size_t(components), -1e300);
    for (size_t i = 0; i < values.size(); i++) {
      a.minValues[i % components] = std::min(a.minValues[i % components], double(values[i]));
      a.maxValues[i % components] = std::max(a.maxValues[i % components], double(values[i]));
    }
  }
  m.accessors.push_back(a);
  return int(m.accessors.size() - 1);
}

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
  prim.attributes["POSITION"] = addFloatAccessor(m, s.positions, 3, true);
  prim.attributes["COLOR_0"] = addFloatAccessor(m, s.colors, 4);
  prim.attributes["KHR_gaussian_splatting:ROTATION"] = addFloatAccessor(m, s.rotations, 4);
  prim.attributes["KHR_gaussian_splatting:SCALE"] = addFloatAccessor(m, s.scales, 3);
  prim.attributes["KHR_gaussian_splatting:OPACITY"] = addFloatAccessor(m, s.opacities, 1);
  for (uint32_t l = 0; l <= s.shDegree; l++)
    for (uint32_t n = 0; n < 2 * l + 1; n++)
      prim.attributes["KHR_gaussian_splatting:SH_DEGREE_" + std::to_string(l) + "_COEF_" + std::to_string(n)] =
          addFloatAccessor(m, s.sh[l * l + n], 3);
  // Refrax renders display-referred sRGB images and blends along the ray in the order of depth.
  prim.extensions["KHR_gaussian_splatting"] = object({{"kernel", tinygltf::Value(std::string("ellipse"))},
                                                      {"colorSpace", tinygltf::Value(std::string("srgb_rec709_display"))}});
  addNode(m, "gaussians", std::move(prim));
}

void addWater(tinygltf::Model& m, const GlbWater& w, const std::string& path) {
  const SurfaceMesh& mesh = w.mesh;
  if (mesh.vertexCount() == 0 || mesh.indices.empty() || mesh.indices.size() % 3 || mesh.normals.size() != mesh.positions.size())
    fail("glTF export " + path + ": the water is not a triangle mesh with normals");
  std::vector<float> positions(mesh.positions.size()), normals(mesh.normals.size());
  for (size_t i = 0; i < mesh.vertexCount(); i++) {
    toGltfAxes(&mesh.positions[3 * i], &positions[3 * i]);
    toGltfAxes(&mesh.normals[3 * i], &normals[3 * i]);
  }
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = addFloatAccessor(m, positions, 3, true);
  prim.attributes["NORMAL"] = addFloatAccessor(m, normals, 3);
  tinygltf::Accessor indices;
  indices.bufferView = addView(m, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  indices.type = TINYGLTF_TYPE_SCALAR;
  indices.count = mesh.indices.size();
  m.accessors.push_back(indices);
  prim.indices = int(m.accessors.size() - 1);

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
