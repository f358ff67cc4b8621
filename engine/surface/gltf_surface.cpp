#include "engine/surface/gltf_surface.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <sstream>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "engine/base/error.h"
#include "engine/io/atomic_file.h"
#include "engine/io/gltf_axes.h"

namespace refrax {
namespace {

std::string lowerExtension(const std::string& path) {
  size_t dot = path.find_last_of('.');
  size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

void checkMesh(const SurfaceMesh& mesh, const std::string& path) {
  const std::string what = "glTF export " + path + ": ";
  if (mesh.positions.empty() || mesh.positions.size() % 3 != 0) fail(what + "the mesh has no vertices (or a position count not a multiple of 3)");
  if (mesh.indices.empty() || mesh.indices.size() % 3 != 0) fail(what + "the mesh has no triangles (or an index count not a multiple of 3)");
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) fail(what + "normals and positions differ in count");
  for (float v : mesh.positions)
    if (!std::isfinite(v)) fail(what + "a vertex position is not finite");
  for (size_t i = 0; i < mesh.normals.size(); i += 3) {
    double len = std::sqrt(double(mesh.normals[i]) * mesh.normals[i] + double(mesh.normals[i + 1]) * mesh.normals[i + 1] +
                           double(mesh.normals[i + 2]) * mesh.normals[i + 2]);
    if (!(std::abs(len - 1.0) < 1e-3)) fail(what + "normal " + std::to_string(i / 3) + " is not a unit vector");
  }
  for (uint32_t index : mesh.indices)
    if (index >= mesh.vertexCount()) fail(what + "index " + std::to_string(index) + " is out of range (" + std::to_string(mesh.vertexCount()) + " vertices)");
}

std::vector<float> convertedToGltf(const std::vector<float>& xyz) {
  std::vector<float> out(xyz.size());
  for (size_t i = 0; i < xyz.size(); i += 3) {
    glm::dvec3 g = toGltfAxes({xyz[i], xyz[i + 1], xyz[i + 2]});
    out[i] = float(g.x), out[i + 1] = float(g.y), out[i + 2] = float(g.z);
  }
  return out;
}

}  // namespace

int addGltfView(tinygltf::Model& model, const void* bytes, size_t size, int target) {
  auto& data = model.buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = size;
  view.target = target;
  const auto* b = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), b, b + size);
  model.bufferViews.push_back(view);
  return int(model.bufferViews.size() - 1);
}

int addGltfFloatAccessor(tinygltf::Model& model, const std::vector<float>& values, int components, bool withBounds) {
  tinygltf::Accessor a;
  a.bufferView = addGltfView(model, values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.type = components == 1 ? TINYGLTF_TYPE_SCALAR : components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
  a.count = values.size() / size_t(components);
  if (withBounds) {
    a.minValues.assign(size_t(components), std::numeric_limits<double>::infinity());
    a.maxValues.assign(size_t(components), -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < values.size(); i++) {
      a.minValues[i % components] = std::min(a.minValues[i % components], double(values[i]));
      a.maxValues[i % components] = std::max(a.maxValues[i % components], double(values[i]));
    }
  }
  model.accessors.push_back(a);
  return int(model.accessors.size() - 1);
}

tinygltf::Primitive surfaceMeshPrimitive(tinygltf::Model& model, const SurfaceMesh& mesh, const std::string& path) {
  checkMesh(mesh, path);
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = addGltfFloatAccessor(model, convertedToGltf(mesh.positions), 3, true);
  if (!mesh.normals.empty()) prim.attributes["NORMAL"] = addGltfFloatAccessor(model, convertedToGltf(mesh.normals), 3, false);
  tinygltf::Accessor indices;
  indices.bufferView = addGltfView(model, mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  indices.type = TINYGLTF_TYPE_SCALAR;
  indices.count = mesh.indices.size();
  model.accessors.push_back(indices);
  prim.indices = int(model.accessors.size() - 1);
  return prim;
}

namespace {

// ---- reading

struct AccessorView {
  const unsigned char* data = nullptr;
  size_t count = 0, stride = 0;
};

// The accessor's elements inside its buffer, bounds-checked.
AccessorView viewOf(const tinygltf::Model& model, int accessorIndex, const std::string& what) {
  if (accessorIndex < 0 || size_t(accessorIndex) >= model.accessors.size()) fail(what + " refers to a missing accessor");
  const tinygltf::Accessor& a = model.accessors[accessorIndex];
  if (a.sparse.isSparse) fail(what + " uses a sparse accessor (not supported)");
  if (a.bufferView < 0 || size_t(a.bufferView) >= model.bufferViews.size()) fail(what + " has no buffer view");
  const tinygltf::BufferView& v = model.bufferViews[a.bufferView];
  if (v.buffer < 0 || size_t(v.buffer) >= model.buffers.size()) fail(what + " refers to a missing buffer");
  const auto& buffer = model.buffers[v.buffer].data;
  int elementSize = tinygltf::GetComponentSizeInBytes(a.componentType) * tinygltf::GetNumComponentsInType(a.type);
  if (elementSize <= 0) fail(what + " has an unknown component type");
  AccessorView out;
  out.count = a.count;
  out.stride = v.byteStride ? v.byteStride : size_t(elementSize);
  size_t begin = v.byteOffset + a.byteOffset;
  size_t need = a.count == 0 ? 0 : out.stride * (a.count - 1) + size_t(elementSize);
  if (v.byteOffset + v.byteLength > buffer.size() || a.byteOffset + need > v.byteLength)
    fail(what + " reads past the end of its buffer");
  out.data = buffer.data() + begin;
  return out;
}

glm::dmat4 localTransform(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major, as glTF
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3) m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
  if (node.rotation.size() == 4) {  // glTF quaternions are (x, y, z, w)
    glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
    m = m * glm::dmat4(glm::mat3_cast(glm::normalize(q)));
  }
  if (node.scale.size() == 3) m = m * glm::dmat4(glm::dmat3(glm::dvec3(node.scale[0], 0, 0), glm::dvec3(0, node.scale[1], 0), glm::dvec3(0, 0, node.scale[2])));
  return m;
}

void appendMesh(const tinygltf::Model& model, int meshIndex, const glm::dmat4& transform, SurfaceMesh& out, const std::string& path) {
  if (meshIndex < 0 || size_t(meshIndex) >= model.meshes.size()) fail("glTF " + path + ": a node refers to a missing mesh");
  const tinygltf::Mesh& mesh = model.meshes[meshIndex];
  // A mirroring transform flips the winding; swap two corners to keep counter-clockwise.
  const bool mirrored = glm::determinant(glm::dmat3(transform)) < 0;
  for (size_t p = 0; p < mesh.primitives.size(); p++) {
    const tinygltf::Primitive& prim = mesh.primitives[p];
    const std::string what = "glTF " + path + ": mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
      fail(what + " is not a triangle list (mode " + std::to_string(prim.mode) + "; only mode 4, triangles, is read)");
    auto pos = prim.attributes.find("POSITION");
    if (pos == prim.attributes.end()) fail(what + " has no POSITION attribute");
    AccessorView positions = viewOf(model, pos->second, what + " POSITION");  // checks the index
    const tinygltf::Accessor& pa = model.accessors[pos->second];
    if (pa.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || pa.type != TINYGLTF_TYPE_VEC3)
      fail(what + " POSITION is not float VEC3 (quantized positions are not supported)");
    const size_t base = out.vertexCount();
    if (base + positions.count > std::numeric_limits<uint32_t>::max()) fail(what + ": too many vertices");
    for (size_t i = 0; i < positions.count; i++) {
      float v[3];
      std::memcpy(v, positions.data + i * positions.stride, sizeof v);
      glm::dvec3 world = fromGltfAxes(glm::dvec3(transform * glm::dvec4(v[0], v[1], v[2], 1.0)));
      for (int a = 0; a < 3; a++) {
        if (!std::isfinite(world[a])) fail(what + " has a non-finite vertex position");
        out.positions.push_back(float(world[a]));
      }
    }
    std::vector<uint32_t> local;
    if (prim.indices >= 0) {
      AccessorView idx = viewOf(model, prim.indices, what + " indices");
      const tinygltf::Accessor& ia = model.accessors[prim.indices];
      if (ia.type != TINYGLTF_TYPE_SCALAR) fail(what + " indices are not scalars");
      for (size_t i = 0; i < idx.count; i++) {
        const unsigned char* e = idx.data + i * idx.stride;
        uint32_t value;
        if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) value = e[0];
        else if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
          uint16_t s;
          std::memcpy(&s, e, 2);
          value = s;
        } else if (ia.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) std::memcpy(&value, e, 4);
        else fail(what + " indices are not unsigned byte, short or int");
        local.push_back(value);
      }
    } else {
      for (size_t i = 0; i < positions.count; i++) local.push_back(uint32_t(i));
    }
    if (local.size() % 3 != 0) fail(what + " has " + std::to_string(local.size()) + " indices, not a multiple of 3");
    for (size_t t = 0; t < local.size(); t += 3)
      for (int c = 0; c < 3; c++) {
        uint32_t v = local[t + (mirrored && c > 0 ? 3 - c : c)];
        if (v >= positions.count) fail(what + " has index " + std::to_string(v) + " out of range (" + std::to_string(positions.count) + " vertices)");
        out.indices.push_back(uint32_t(base + v));
      }
  }
}

}  // namespace

std::vector<float> vertexNormals(const std::vector<float>& positions, const std::vector<uint32_t>& indices) {
  std::vector<glm::dvec3> sum(positions.size() / 3, glm::dvec3(0));
  auto at = [&](uint32_t i) { return glm::dvec3(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]); };
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    uint32_t a = indices[t], b = indices[t + 1], c = indices[t + 2];
    glm::dvec3 n = glm::cross(at(b) - at(a), at(c) - at(a));  // length = 2 * area: area weighting
    sum[a] += n, sum[b] += n, sum[c] += n;
  }
  std::vector<float> normals(positions.size());
  for (size_t i = 0; i < sum.size(); i++) {
    double len = glm::length(sum[i]);
    glm::dvec3 n = len > 0 ? sum[i] / len : glm::dvec3(0, 0, 1);
    normals[3 * i] = float(n.x), normals[3 * i + 1] = float(n.y), normals[3 * i + 2] = float(n.z);
  }
  return normals;
}

SurfaceMesh surfaceMeshFromGrid(const GridMesh& grid) {
  SurfaceMesh mesh;
  mesh.positions = grid.vertices;
  mesh.indices = grid.indices;
  mesh.normals = vertexNormals(mesh.positions, mesh.indices);
  return mesh;
}

void writeSurfaceGltf(const std::string& path, const SurfaceMesh& mesh) {
  const std::string ext = lowerExtension(path);
  if (ext != ".gltf" && ext != ".glb") fail("glTF export " + path + ": the file name must end in .gltf or .glb");
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "Refrax";
  model.buffers.resize(1);
  tinygltf::Primitive prim = surfaceMeshPrimitive(model, mesh, path);
  while (model.buffers[0].data.size() % 4) model.buffers[0].data.push_back(0);
  tinygltf::Mesh m;
  m.name = "water_surface";
  m.primitives.push_back(prim);
  model.meshes.push_back(m);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "water_surface";
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/ext == ".gltf", /*writeBinary=*/ext == ".glb"))
    fail("glTF export " + path + ": tinygltf could not serialise the mesh");
  writeTextAtomic(path, stream.str());
}

SurfaceMesh readSurfaceGltf(const std::string& path) {
  if (!fileExists(path)) fail("glTF " + path + ": no such file");
  const std::string ext = lowerExtension(path);
  if (ext != ".gltf" && ext != ".glb") fail("glTF " + path + ": the file name must end in .gltf or .glb");
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) {
    std::string message = err.empty() ? warn : err;
    while (!message.empty() && (message.back() == '\n' || message.back() == '\r')) message.pop_back();
    std::replace(message.begin(), message.end(), '\n', ' ');
    // tinygltf quotes what it failed on, a whole data: URI of base64 at times: keep one line short.
    constexpr size_t kMaxMessage = 240;
    if (message.size() > kMaxMessage) message = message.substr(0, kMaxMessage) + "... (" + std::to_string(message.size()) + " characters)";
    fail("glTF " + path + " is malformed: " + (message.empty() ? "tinygltf could not parse it" : message));
  }

  SurfaceMesh out;
  if (model.scenes.empty()) {
    for (size_t m = 0; m < model.meshes.size(); m++) appendMesh(model, int(m), glm::dmat4(1.0), out, path);
  } else {
    int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : 0;
    if (size_t(sceneIndex) >= model.scenes.size()) fail("glTF " + path + ": the default scene does not exist");
    std::vector<int> depthOf(model.nodes.size(), -1);
    std::function<void(int, const glm::dmat4&, int)> visit = [&](int n, const glm::dmat4& parent, int depth) {
      if (n < 0 || size_t(n) >= model.nodes.size()) fail("glTF " + path + ": a scene refers to a missing node");
      if (depthOf[n] >= 0) fail("glTF " + path + ": node " + std::to_string(n) + " appears twice in the scene (a cycle or shared child)");
      depthOf[n] = depth;
      const tinygltf::Node& node = model.nodes[n];
      glm::dmat4 world = parent * localTransform(node);
      if (node.mesh >= 0) appendMesh(model, node.mesh, world, out, path);
      for (int child : node.children) visit(child, world, depth + 1);
    };
    for (int root : model.scenes[sceneIndex].nodes) visit(root, glm::dmat4(1.0), 0);
  }
  if (out.indices.empty()) fail("glTF " + path + ": no triangles in the scene");
  return out;
}

}  // namespace refrax
