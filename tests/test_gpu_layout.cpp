// The std430 records the shaders and the host share (shaders/include/layout_prelude.glsl) have
// the same layout on both sides: each record's fields' offsets and its size as glslang lays
// them out for a std430 buffer (its reflection) against offsetof and sizeof of the C++ struct
// the same header declares. No device: it runs glslangValidator, as the build does.
#include <doctest/doctest.h>

#include <cstddef>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "engine/surface/surface_record.h"
#include "engine/trace/box_bvh.h"
#include "engine/trace/rays.h"
#include "engine/gaussian/gaussian_trace.h"
#include "engine/view/fly_camera.h"
#include "tests/train_test_util.h"

namespace refrax::layout_test {

struct Field {
  std::string name;  // the GLSL name
  size_t offset, bytes;
};
struct Record {
  std::string glslName, hostName;
  size_t hostSize;
  std::vector<Field> fields;
};

// The same headers expanded a second time into a table per record: each field's GLSL name
// and its host offset and size (an XYZ_W field is one GLSL vec4 over the host's xyz and w).
using uint = uint32_t;
using refrax::SurfaceRecord;
#undef LAYOUT_STRUCT
#undef LAYOUT_END
#undef LAYOUT_UINT
#undef LAYOUT_FLOAT
#undef LAYOUT_VEC4
#undef LAYOUT_XYZ_W
#undef LAYOUT_VEC3
#undef LAYOUT_CONST
#undef LAYOUT_FN
#define LAYOUT_STRUCT(glslName, hostName) \
  inline Record record_##glslName() {     \
    using S = refrax::hostName;           \
    return {#glslName, #hostName, sizeof(S), {
#define LAYOUT_UINT(name) {#name, offsetof(S, name), 4},
#define LAYOUT_FLOAT(name) {#name, offsetof(S, name), 4},
#define LAYOUT_VEC4(name) {#name, offsetof(S, name), 16},
#define LAYOUT_XYZ_W(xyz, w, glslName) {#glslName, offsetof(S, xyz), offsetof(S, w) + 4 - offsetof(S, xyz)},
#define LAYOUT_VEC3(name) {#name, offsetof(S, name), 12},
#define LAYOUT_END(hostName, bytes) \
  }                                 \
  }                                 \
  ;                                 \
  }
#define LAYOUT_CONST(name, value)
#define LAYOUT_FN inline
#undef REFRAX_RAYS_GLSL
#undef REFRAX_SURFACE_RECORD_GLSL
#undef REFRAX_BVH_NODE_GLSL
#undef REFRAX_TRACE_RESULT_GLSL
#undef REFRAX_PINHOLE_CAMERA_GLSL
#include "rays.glsl"
#include "surface_record.glsl"
#include "bvh_node.glsl"
#include "trace_result.glsl"
#include "pinhole_camera.glsl"

std::vector<Record> sharedRecords() {
  return {record_Ray(), record_TriangleHit(), record_RayGrad(), record_SurfaceRecord(), record_BvhNode(), record_TraceResult(),
          record_PinholeCamera()};
}

// glslang's std430 layout of each record, one buffer block per record: "B_Record.r.field"
// -> offset, and "B_Record" -> the block's size.
std::map<std::string, long> glslLayout(const std::vector<Record>& records, const std::string& dir) {
  std::ofstream src(dir + "/layouts.comp");
  src << "#version 460\n#extension GL_GOOGLE_include_directive : require\n"
         "#include \"rays.glsl\"\n#include \"surface_record.glsl\"\n#include \"bvh_node.glsl\"\n"
         "#include \"trace_result.glsl\"\n#include \"pinhole_camera.glsl\"\n"
         "layout(local_size_x = 1) in;\n";
  for (size_t i = 0; i < records.size(); i++)
    src << "layout(std430, binding = " << i << ") buffer B_" << records[i].glslName << " { " << records[i].glslName << " r; } b_" << records[i].glslName << ";\n";
  src << "void main() {\n";  // a block main() does not touch is not reflected
  for (const Record& r : records) src << "  b_" << r.glslName << ".r = b_" << r.glslName << ".r;\n";
  src << "}\n";
  src.close();
  const std::string cmd = std::string(REFRAX_GLSLANG) + " -V -q --reflect-all-block-variables -I" + REFRAX_SOURCE_DIR + "/shaders/include " +
                          dir + "/layouts.comp -o " + dir + "/layouts.spv 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p);
  std::map<std::string, long> layout;
  char line[512];
  std::string all;
  while (std::fgets(line, sizeof line, p)) {
    all += line;
    char name[256];
    long offset = 0, size = 0;
    if (std::sscanf(line, "%255[^:]: offset %ld", name, &offset) == 2 && std::string(name).find('.') != std::string::npos)
      layout[name] = offset;
    else if (std::sscanf(line, "%255[^:]: offset -1, type ffffffff, size %ld", name, &size) == 2)
      layout[name] = size;
  }
  INFO(all);
  REQUIRE(pclose(p) == 0);
  return layout;
}

TEST_CASE("gpu layout: every shared std430 record has glslang's offsets and size on the host" * doctest::test_suite("one-backend")) {
  test::TrainTempDir dir;
  const std::vector<Record> records = sharedRecords();
  const std::map<std::string, long> glsl = glslLayout(records, dir.path.string());
  for (const Record& r : records) {
    const std::string block = "B_" + r.glslName;
    INFO(r.glslName << " / " << r.hostName);
    REQUIRE(glsl.count(block));
    CHECK(size_t(glsl.at(block)) == r.hostSize);
    size_t end = 0;
    for (const Field& f : r.fields) {
      INFO("field " << f.name);
      REQUIRE(glsl.count(block + ".r." + f.name));
      CHECK(size_t(glsl.at(block + ".r." + f.name)) == f.offset);
      CHECK(f.offset >= end);  // the host's fields in the GLSL order
      end = f.offset + f.bytes;
    }
  }
}

}  // namespace refrax::layout_test
