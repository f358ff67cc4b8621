// glTF surface I/O: round trips (.gltf and .glb) of a wavy grid, the +Z-up <-> +Y-up axis
// conversion read back through tinygltf directly, a hand-written file with a node hierarchy
// (TRS transforms, two primitives, 16-bit indices, an external buffer), and malformed files.
#include <doctest/doctest.h>

#include <tiny_gltf.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "engine/surface/grid_mesh.h"
#include "engine/io/atomic_file.h"
#include "engine/surface/gltf_surface.h"

using namespace refrax;

namespace {

std::string tempPath(const std::string& name) { return "/tmp/refrax_test_" + std::to_string(::getpid()) + "_" + name; }

GridMesh wavyGrid() {
  return makeGridMesh(7, 5, -1.0f, -0.5f, 1.0f, 0.75f, [](float x, float y) { return 0.05f * std::sin(3 * x) * std::cos(2 * y) + 0.2f; });
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// The exception's message contains `part`.
void checkFails(const std::string& path, const std::string& part) {
  INFO("expected an error containing '" << part << "'");
  try {
    readSurfaceGltf(path);
    FAIL("no error for " << path);
  } catch (const Error& e) {
    INFO("message: " << std::string(e.what()));
    CHECK(std::string(e.what()).find(part) != std::string::npos);
  }
}

// One triangle (glTF axes, horizontal, facing +Y) and indices {0, 1, 2} as uint16, in a .bin.
std::vector<unsigned char> triangleBuffer() {
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 0, -1};
  const uint16_t indices[3] = {0, 1, 2};
  std::vector<unsigned char> bytes(44, 0);
  std::memcpy(bytes.data(), positions, 36);
  std::memcpy(bytes.data() + 36, indices, 6);
  return bytes;
}

// A glTF JSON around triangleBuffer() with the given primitives and nodes.
std::string triangleGltf(const std::string& bin, const std::string& primitives, const std::string& nodes, const std::string& extraAccessor = "") {
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": )" + nodes + R"(,
  "meshes": [{"primitives": )" + primitives + R"(}],
  "buffers": [{"uri": ")" + bin + R"(", "byteLength": 44}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, -1], "max": [1, 0, 0]},
                {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"})" + extraAccessor + R"(]})";
}

}  // namespace

TEST_CASE("gltf surface: round trip of a wavy grid as .gltf and .glb") {
  GridMesh grid = wavyGrid();
  SurfaceMesh mesh = surfaceMeshFromGrid(grid);
  REQUIRE(mesh.normals.size() == mesh.positions.size());
  for (const char* ext : {".gltf", ".glb"}) {
    std::string path = tempPath(std::string("surface") + ext);
    writeSurfaceGltf(path, mesh);
    SurfaceMesh back = readSurfaceGltf(path);
    CHECK(back.positions == mesh.positions);  // the axis swap is exact (a negation and a permutation)
    CHECK(back.indices == mesh.indices);
    CHECK(back.normals.empty());

    // In the file, glTF axes: Refrax z (height) is glTF y, Refrax y is glTF -z.
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    bool ok = std::string(ext) == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path) : loader.LoadASCIIFromFile(&model, &err, &warn, path);
    REQUIRE_MESSAGE(ok, err);
    const tinygltf::Primitive& prim = model.meshes.at(0).primitives.at(0);
    const tinygltf::Accessor& pa = model.accessors.at(prim.attributes.at("POSITION"));
    const tinygltf::Accessor& na = model.accessors.at(prim.attributes.at("NORMAL"));
    const auto& data = model.buffers.at(0).data;
    const float* raw = reinterpret_cast<const float*>(data.data() + model.bufferViews.at(pa.bufferView).byteOffset);
    const float* rawN = reinterpret_cast<const float*>(data.data() + model.bufferViews.at(na.bufferView).byteOffset);
    for (size_t v = 0; v < mesh.vertexCount(); v++) {
      CHECK(raw[3 * v + 0] == mesh.positions[3 * v + 0]);
      CHECK(raw[3 * v + 1] == mesh.positions[3 * v + 2]);
      CHECK(raw[3 * v + 2] == -mesh.positions[3 * v + 1]);
      CHECK(rawN[3 * v + 1] > 0.9f);  // the surface faces up: +Y in glTF
    }
    CHECK(pa.maxValues.at(1) == doctest::Approx(0.25).epsilon(0.01));  // highest wave crest (0.2 + 0.05 at most)
    CHECK(pa.minValues.at(2) == doctest::Approx(-0.75));                // Refrax y max 0.75 -> glTF z min -0.75
    std::remove(path.c_str());
  }
}

TEST_CASE("gltf surface: grid normals are area-weighted and point up") {
  GridMesh flat = makeGridMesh(3, 3, 0, 0, 1, 1);
  SurfaceMesh mesh = surfaceMeshFromGrid(flat);
  for (size_t v = 0; v < mesh.vertexCount(); v++) {
    CHECK(mesh.normals[3 * v + 0] == doctest::Approx(0.0));
    CHECK(mesh.normals[3 * v + 1] == doctest::Approx(0.0));
    CHECK(mesh.normals[3 * v + 2] == doctest::Approx(1.0));
  }
  // A tilted plane z = 0.5 x: normal (-0.5, 0, 1) / |.|.
  GridMesh tilted = makeGridMesh(4, 2, 0, 0, 1, 1, [](float x, float) { return 0.5f * x; });
  SurfaceMesh t = surfaceMeshFromGrid(tilted);
  const double len = std::sqrt(1.25);
  for (size_t v = 0; v < t.vertexCount(); v++) {
    CHECK(t.normals[3 * v + 0] == doctest::Approx(-0.5 / len));
    CHECK(t.normals[3 * v + 2] == doctest::Approx(1.0 / len));
  }
}

TEST_CASE("gltf surface: node transforms, two primitives and 16-bit indices") {
  const std::string bin = tempPath("tri.bin"), gltf = tempPath("tri.gltf");
  writeBytes(bin, triangleBuffer());
  // Parent: 90 degrees about glTF +Y; child: translation (2, 3, 4), scale 2. Primitive 0 has no
  // indices, primitive 1 uses the uint16 indices: the merged mesh has both triangles.
  const std::string binName = bin.substr(bin.find_last_of('/') + 1);
  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 0}}, {"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}])",
                                     R"([{"rotation": [0, 0.70710678, 0, 0.70710678], "children": [1]},
                                         {"translation": [2, 3, 4], "scale": [2, 2, 2], "mesh": 0}])"));
  SurfaceMesh mesh = readSurfaceGltf(gltf);
  REQUIRE(mesh.vertexCount() == 6);
  CHECK(mesh.indices == std::vector<uint32_t>{0, 1, 2, 3, 4, 5});
  // glTF p -> R (T + 2 p), R (x, y, z) = (z, y, -x); then Refrax (x, y, z) = glTF (x, -z, y).
  const float expected[9] = {4, 2, 3, 4, 4, 3, 2, 2, 3};
  for (int i = 0; i < 9; i++) {
    CHECK(mesh.positions[i] == doctest::Approx(expected[i]).epsilon(1e-6));
    CHECK(mesh.positions[9 + i] == doctest::Approx(expected[i]).epsilon(1e-6));
  }
  // Still facing up in Refrax axes (+Z) after the transform.
  std::vector<float> n = vertexNormals(mesh.positions, mesh.indices);
  CHECK(n[2] == doctest::Approx(1.0));

  SUBCASE("a mirroring scale keeps the triangles facing the same side") {
    writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 0}}])", R"([{"scale": [-1, 1, 1], "mesh": 0}])"));
    SurfaceMesh m = readSurfaceGltf(gltf);
    std::vector<float> mn = vertexNormals(m.positions, m.indices);
    CHECK(mn[2] == doctest::Approx(1.0));
    CHECK(m.positions[3] == doctest::Approx(-1.0f));  // (1, 0, 0) mirrored
  }
  std::remove(bin.c_str());
  std::remove(gltf.c_str());
}

TEST_CASE("gltf surface: missing and malformed files are one clear error") {
  const std::string bin = tempPath("bad.bin"), gltf = tempPath("bad.gltf");
  writeBytes(bin, triangleBuffer());
  const std::string binName = bin.substr(bin.find_last_of('/') + 1);
  const std::string nodes = R"([{"mesh": 0}])";

  checkFails(tempPath("absent.gltf"), "no such file");
  writeTextAtomic(tempPath("mesh.obj"), "v 0 0 0\n");
  checkFails(tempPath("mesh.obj"), ".gltf or .glb");

  writeTextAtomic(gltf, "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
  checkFails(gltf, "malformed");

  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 0}, "indices": 1, "mode": 1}])", nodes));
  checkFails(gltf, "not a triangle list");

  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"NORMAL": 0}, "indices": 1}])", nodes));
  checkFails(gltf, "no POSITION");

  // Indices accessor 2 reads the position floats as uint16: 1.0f gives 16256, beyond 3 vertices.
  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 0}, "indices": 2}])", nodes,
                                     R"(, {"bufferView": 0, "byteOffset": 12, "componentType": 5123, "count": 3, "type": "SCALAR"})"));
  checkFails(gltf, "out of range");

  // An accessor longer than its view.
  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 2}}])", nodes,
                                     R"(, {"bufferView": 0, "componentType": 5126, "count": 30, "type": "VEC3"})"));
  checkFails(gltf, "reads past the end");

  // Positions as uint16 (quantized): not read.
  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 2}}])", nodes,
                                     R"(, {"bufferView": 1, "componentType": 5123, "count": 1, "type": "VEC3"})"));
  checkFails(gltf, "not float VEC3");

  // The external buffer is missing.
  std::remove(bin.c_str());
  writeTextAtomic(gltf, triangleGltf(binName, R"([{"attributes": {"POSITION": 0}}])", nodes));
  checkFails(gltf, "malformed");

  // A truncated .glb.
  writeBytes(bin, triangleBuffer());
  SurfaceMesh ok = surfaceMeshFromGrid(wavyGrid());
  const std::string glb = tempPath("cut.glb");
  writeSurfaceGltf(glb, ok);
  std::string bytes = readFile(glb);
  writeTextAtomic(glb, bytes.substr(0, bytes.size() / 2));
  checkFails(glb, "malformed");

  // Writing: bad extension, index out of range, non-unit normal.
  CHECK_THROWS_AS(writeSurfaceGltf(tempPath("x.obj"), ok), Error);
  SurfaceMesh bad = ok;
  bad.indices[4] = uint32_t(bad.vertexCount());
  CHECK_THROWS_AS(writeSurfaceGltf(tempPath("x.gltf"), bad), Error);
  bad = ok;
  bad.normals[0] = 3.0f;
  CHECK_THROWS_AS(writeSurfaceGltf(tempPath("x.gltf"), bad), Error);
  CHECK_FALSE(fileExists(tempPath("x.gltf")));
  for (const std::string& p : {bin, gltf, glb, tempPath("mesh.obj")}) std::remove(p.c_str());
}
