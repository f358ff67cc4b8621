// Build-time generator of the straight-line height-field kernels (engine/height/height_kernel_shapes.h
// explains why and which forms). Run by CMake, one output file per call:
//   generate_height_kernels <out.comp> fused  <width> <hiddenLayers> <octaves>
//   generate_height_kernels <out.comp> backprop <width> <hiddenLayers> <octaves>
//   generate_height_kernels <out.comp> first  <width> <octaves>
//   generate_height_kernels <out.comp> hidden <width>
//   generate_height_kernels <out.comp> last   <width>
//   generate_height_kernels <out.comp> grad   <outputsPerBlock> atomic|cas
// Every generated kernel: one invocation per point, no loops, no branches except around the
// final store (lavapipe scalarises loads under control flow), weights staged cooperatively
// into shared memory as vec4 and read at constant offsets; hidden layers as vec4 dot
// products (four multiply-adds per SPIR-V instruction keeps the binaries small).
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/height/height_kernel_shapes.h"

namespace {

using refrax::kHeightKernelGroup;
using refrax::kHeightStageFloats;

const char* kLane[4] = {"x", "y", "z", "w"};

// Output rows staged at once for a layer of nin inputs.
uint32_t layerRows(uint32_t nin, uint32_t nout) { return std::max(4u, std::min(nout, kHeightStageFloats / nin) / 4 * 4); }

struct Emitter {
  std::ostringstream s;
  bool staged = false;

  void line(const std::string& l) { s << "  " << l << "\n"; }

  // Copies `floats` weights from float offset `base` (an expression, a multiple of 4) into sw4,
  // in vec4 units; the last copy clamps its source index to `lastVec4` (an expression).
  void stage(const std::string& base, uint32_t floats, const std::string& lastVec4) {
    if (staged) line("barrier();  // every invocation is done with the previous stage");
    uint32_t vec4s = (floats + 3) / 4, copies = (vec4s + kHeightKernelGroup - 1) / kHeightKernelGroup;
    for (uint32_t c = 0; c < copies; c++) {
      std::string src = "(" + base + ") / 4u + " + std::to_string(c * kHeightKernelGroup) + "u + lid";
      if (c + 1 == copies) src = "min(" + src + ", " + lastVec4 + ")";
      line("sw4[" + std::to_string(c * kHeightKernelGroup) + "u + lid] = w4[" + src + "];");
    }
    line("barrier();");
    staged = true;
  }

  // Layer with scalar inputs in[k] (k < nin), rows [j0, j1) staged at sw4 from row j0:
  // declares float s<j> accumulators.
  void denseScalar(const std::vector<std::string>& in, uint32_t j0, uint32_t j1, const std::string& acc) {
    const uint32_t nin = uint32_t(in.size()), block = 8;
    for (uint32_t b = j0; b < j1; b += block) {
      uint32_t e = std::min(j1, b + block);
      for (uint32_t k = 0; k < nin; k++)
        for (uint32_t j = b; j < e; j++) {
          uint32_t idx = (j - j0) * nin + k;
          std::string wv = "sw4[" + std::to_string(idx / 4) + "]." + kLane[idx % 4];
          if (k == 0)
            line("float " + acc + std::to_string(j) + " = " + wv + " * " + in[k] + ";");
          else
            line(acc + std::to_string(j) + " += " + wv + " * " + in[k] + ";");
        }
    }
  }

  // Layer with vec4 inputs in[q] (4 inputs each), rows [j0, j1) staged at sw4 from row j0.
  void denseVec4(const std::vector<std::string>& in, uint32_t j0, uint32_t j1, const std::string& acc) {
    const uint32_t quads = uint32_t(in.size()), block = 8;
    for (uint32_t b = j0; b < j1; b += block) {
      uint32_t e = std::min(j1, b + block);
      for (uint32_t q = 0; q < quads; q++)
        for (uint32_t j = b; j < e; j++) {
          std::string term = "dot(sw4[" + std::to_string((j - j0) * quads + q) + "], " + in[q] + ")";
          if (q == 0)
            line("float " + acc + std::to_string(j) + " = " + term + ";");
          else
            line(acc + std::to_string(j) + " += " + term + ";");
        }
    }
  }

  // vec4 activations out<q> = lrelu(acc<4q..4q+3>) for neurons [j0, j1).
  void activate(const std::string& acc, const std::string& out, uint32_t j0, uint32_t j1) {
    for (uint32_t j = j0; j < j1; j += 4)
      line("vec4 " + out + std::to_string(j / 4) + " = lrelu4(vec4(" + acc + std::to_string(j) + ", " + acc + std::to_string(j + 1) +
           ", " + acc + std::to_string(j + 2) + ", " + acc + std::to_string(j + 3) + "));");
  }

  // A whole layer of `nout` outputs from `in` (scalar or vec4 inputs of nin values), weights
  // at float offset `base` + row * nin, staged in as many chunks as the stage size needs.
  // firstStaged: the caller has staged the first chunk already (to load the inputs after the
  // barrier: lavapipe saves every value live across a barrier, per invocation).
  void layer(const std::vector<std::string>& in, bool vec4In, uint32_t nin, uint32_t nout, const std::string& base,
             const std::string& lastVec4, const std::string& acc, const std::string& out, bool firstStaged = false) {
    uint32_t rows = layerRows(nin, nout);
    for (uint32_t j0 = 0; j0 < nout; j0 += rows) {
      uint32_t j1 = std::min(nout, j0 + rows);
      if (j0 > 0 || !firstStaged) stage(base + " + " + std::to_string(j0 * nin) + "u", (j1 - j0) * nin, lastVec4);
      if (vec4In)
        denseVec4(in, j0, j1, acc);
      else
        denseScalar(in, j0, j1, acc);
      activate(acc, out, j0, j1);
    }
  }
};

uint32_t stageVec4s(uint32_t maxFloats) {
  uint32_t vec4s = (std::min(maxFloats, kHeightStageFloats) + 3) / 4;
  return (vec4s + kHeightKernelGroup - 1) / kHeightKernelGroup * kHeightKernelGroup;
}

std::string header(const std::string& what, uint32_t sharedVec4s, const std::vector<std::string>& buffers) {
  std::ostringstream h;
  h << "#version 460\n"
    << "// Generated by shaders/height/generate_height_kernels.cpp at build time: " << what << "\n"
    << "#extension GL_GOOGLE_include_directive : require\n"
    << "#include \"height_encoding.glsl\"\n"
    << "#include \"height_push.glsl\"\n"
    << "layout(local_size_x = " << kHeightKernelGroup << ") in;\n"
    << "layout(constant_id = 3) const float SLOPE = 0.01;\n";
  for (size_t b = 0; b < buffers.size(); b++) h << "layout(std430, set = 0, binding = " << b << ") " << buffers[b] << "\n";
  h << "shared vec4 sw4[" << sharedVec4s << "];\n"
    << "vec4 lrelu4(vec4 v) { return max(v, SLOPE * v); }\n"
    << "vec4 slopeAt4(vec4 a) { return mix(vec4(SLOPE), vec4(1.0), greaterThan(a, vec4(0.0))); }  // lrelu' from the output\n"
    << "void main() {\n"
    << "  uint lid = gl_LocalInvocationID.x;\n";
  return h.str();
}

std::vector<std::string> names(const std::string& prefix, uint32_t n) {
  std::vector<std::string> v;
  for (uint32_t i = 0; i < n; i++) v.push_back(prefix + std::to_string(i));
  return v;
}

// The encoding e0..e<inputs-1> of the point handled by this invocation (index clamped).
void emitEncoding(Emitter& e, uint32_t inputs) {
  e.line("uint i = pc.first + min(gl_GlobalInvocationID.x, pc.count - 1u);");
  e.line("vec2 p = points[i];");
  e.line("bool finitePoint = heightPointFinite(p);");
  e.line("vec2 u = heightDomainToUnit(finitePoint ? p : pc.domainMin, pc.domainMin, pc.domainMax);");
  for (uint32_t k = 0; k < inputs; k++) e.line("float e" + std::to_string(k) + " = heightEncodingFeature(u, " + std::to_string(k) + "u, pc.octaveWindow);");
}

void emitOutput(Emitter& e, uint32_t width, const std::string& in, const std::string& base, const std::string& lastVec4,
                bool staged = false) {
  if (!staged) e.stage(base, width, lastVec4);
  std::string r = "float r = dot(sw4[0], " + in + "0)";
  for (uint32_t q = 1; q < width / 4; q++) r += " + dot(sw4[" + std::to_string(q) + "], " + in + std::to_string(q) + ")";
  e.line(r + ";");
}

std::string fused(uint32_t width, uint32_t hidden, uint32_t octaves) {
  uint32_t inputs = 2 + 4 * octaves;
  uint64_t params = uint64_t(width) * inputs + uint64_t(hidden - 1) * width * width + width;
  std::string last = std::to_string(params / 4 - 1) + "u";
  uint32_t maxStage = std::max(width * inputs, hidden > 1 ? width * width : width);
  Emitter e;
  e.s << header("fused forward, width " + std::to_string(width) + ", " + std::to_string(hidden) + " hidden layers, " +
                    std::to_string(octaves) + " octaves",
                stageVec4s(maxStage),
                {"readonly buffer Weights { vec4 w4[]; };", "readonly buffer Points { vec2 points[]; };",
                 "writeonly buffer Heights { float heights[]; };"});
  e.stage("0u", layerRows(inputs, width) * inputs, last);
  emitEncoding(e, inputs);
  e.layer(names("e", inputs), false, inputs, width, "0u", last, "s0_", "h1_", true);
  uint64_t off = uint64_t(width) * inputs;
  for (uint32_t l = 1; l < hidden; l++) {
    std::string in = "h" + std::to_string(l) + "_", out = "h" + std::to_string(l + 1) + "_";
    e.layer(names(in, width / 4), true, width, width, std::to_string(off) + "u", last, "s" + std::to_string(l) + "_", out);
    off += uint64_t(width) * width;
  }
  emitOutput(e, width, "h" + std::to_string(hidden) + "_", std::to_string(off) + "u", last);
  e.line("if (gl_GlobalInvocationID.x < pc.count) heights[i] = finitePoint ? r + pc.initialHeight : heightNaN();");
  e.s << "}\n";
  return e.s.str();
}

// Backward pass 1 for fused widths: the fused forward, then the deltas layer by layer down
// (weights staged again, read transposed at constant offsets), every layer's input X_l and
// output delta D_l stored to the scratch ([point][neuron], height_shape.glsl). A point with
// non-finite coordinates or dLoss/dHeight is replaced by the domain corner with zero delta.
// Lanes past the chunk's count redo its last point and store the same values there.
std::string fusedBackprop(uint32_t width, uint32_t hidden, uint32_t octaves) {
  uint32_t inputs = 2 + 4 * octaves, quads = width / 4;
  uint64_t params = uint64_t(width) * inputs + uint64_t(hidden - 1) * width * width + width;
  std::string last = std::to_string(params / 4 - 1) + "u";
  uint32_t maxStage = std::max(width * inputs, hidden > 1 ? width * width : width);
  if (width * width > kHeightStageFloats) {
    std::fprintf(stderr, "generate_height_kernels: fused backprop needs width^2 <= %u\n", kHeightStageFloats);
    std::exit(2);
  }
  Emitter e;
  e.s << header("fused backward pass 1 (activations and deltas), width " + std::to_string(width) + ", " + std::to_string(hidden) +
                    " hidden layers, " + std::to_string(octaves) + " octaves",
                stageVec4s(maxStage),
                {"readonly buffer Weights { vec4 w4[]; };", "readonly buffer Points { vec2 points[]; };",
                 "readonly buffer DLossDHeight { float dLossdHeight[]; };", "writeonly buffer Scratch { float scratch[]; };"});
  e.line("uint tc = min(gl_GlobalInvocationID.x, pc.count - 1u);");
  e.line("uint i = pc.first + tc;");
  e.line("vec2 p = points[i];");
  e.line("float g = dLossdHeight[i];");
  e.line("bool usable = heightPointFinite(p) && !isnan(g) && !isinf(g);");
  e.line("g = usable ? g : 0.0;");
  e.line("vec2 u = heightDomainToUnit(usable ? p : pc.domainMin, pc.domainMin, pc.domainMax);");
  for (uint32_t k = 0; k < inputs; k++) e.line("float e" + std::to_string(k) + " = heightEncodingFeature(u, " + std::to_string(k) + "u, pc.octaveWindow);");
  // Scratch offsets: X_l at chunk * xOff(l) + tc * n_l, D_l at chunk * dOff(l) + tc * m_l.
  auto xOff = [&](uint32_t l) { return l == 0 ? 0u : inputs + (l - 1) * width; };
  auto dOff = [&](uint32_t l) { return inputs + hidden * width + l * width; };
  auto store = [&](const std::string& off, uint32_t count, uint32_t n, const std::string& value) {
    e.line("scratch[pc.chunk * " + off + "u + tc * " + std::to_string(count) + "u + " + std::to_string(n) + "u] = " + value + ";");
  };
  for (uint32_t k = 0; k < inputs; k++) store("0", inputs, k, "e" + std::to_string(k));
  e.layer(names("e", inputs), false, inputs, width, "0u", last, "s0_", "h1_");
  uint64_t off = uint64_t(width) * inputs;
  std::vector<uint64_t> layerOffset = {0};
  for (uint32_t l = 1; l < hidden; l++) {
    layerOffset.push_back(off);
    std::string in = "h" + std::to_string(l) + "_", out = "h" + std::to_string(l + 1) + "_";
    e.layer(names(in, quads), true, width, width, std::to_string(off) + "u", last, "s" + std::to_string(l) + "_", out);
    off += uint64_t(width) * width;
  }
  layerOffset.push_back(off);
  for (uint32_t l = 1; l <= hidden; l++)
    for (uint32_t j = 0; j < width; j++)
      store(std::to_string(xOff(l)), width, j, "h" + std::to_string(l) + "_" + std::to_string(j / 4) + "." + kLane[j % 4]);
  store(std::to_string(dOff(hidden)), 1, 0, "g");
  // Output layer: D_{hidden-1} = g * w_out * lrelu'(X_hidden).
  e.stage(std::to_string(off) + "u", width, last);
  std::string hl = "h" + std::to_string(hidden) + "_";
  for (uint32_t q = 0; q < quads; q++)
    e.line("vec4 d" + std::to_string(hidden - 1) + "_" + std::to_string(q) + " = g * sw4[" + std::to_string(q) + "] * slopeAt4(" + hl +
           std::to_string(q) + ");");
  // Hidden layers down: D_{l-1}[k] = sum_j W_l[j][k] D_l[j] * lrelu'(X_l[k]), W_l staged row-major.
  for (uint32_t l = hidden - 1; l >= 1; l--) {
    e.stage(std::to_string(layerOffset[l]) + "u", width * width, last);
    std::string din = "d" + std::to_string(l) + "_", dout = "d" + std::to_string(l - 1) + "_", x = "h" + std::to_string(l) + "_";
    for (uint32_t j = 0; j < width; j++)
      for (uint32_t q = 0; q < quads; q++) {
        std::string term = "sw4[" + std::to_string(j * quads + q) + "] * " + din + std::to_string(j / 4) + "." + kLane[j % 4];
        e.line(j == 0 ? "vec4 b" + std::to_string(l) + "_" + std::to_string(q) + " = " + term + ";"
                      : "b" + std::to_string(l) + "_" + std::to_string(q) + " += " + term + ";");
      }
    for (uint32_t q = 0; q < quads; q++)
      e.line("vec4 " + dout + std::to_string(q) + " = b" + std::to_string(l) + "_" + std::to_string(q) + " * slopeAt4(" + x +
             std::to_string(q) + ");");
  }
  for (uint32_t l = 0; l < hidden; l++)
    for (uint32_t j = 0; j < width; j++)
      store(std::to_string(dOff(l)), width, j, "d" + std::to_string(l) + "_" + std::to_string(j / 4) + "." + kLane[j % 4]);
  e.s << "}\n";
  return e.s.str();
}

// Layered kernels: scratch act[] holds [neuron][point] regions; t = invocation (the scratch is
// padded to whole workgroups, so t needs no clamp); push: weightBase (float offset of this
// group's first row), inOffset/outOffset (scratch offsets of neuron 0 / the group's first neuron),
// chunk (scratch stride between neurons).
std::string layerFirst(uint32_t width, uint32_t octaves) {
  uint32_t inputs = 2 + 4 * octaves, group = refrax::heightLayerGroupOutputs(width);
  Emitter e;
  e.s << header("first layer, " + std::to_string(group) + " of " + std::to_string(width) + " outputs, " + std::to_string(octaves) +
                    " octaves",
                stageVec4s(group * inputs),
                {"readonly buffer Weights { vec4 w4[]; };", "readonly buffer Points { vec2 points[]; };",
                 "writeonly buffer Act { float act[]; };"});
  e.stage("pc.weightBase + 0u", layerRows(inputs, group) * inputs, "uint(w4.length()) - 1u");
  e.line("uint t = gl_GlobalInvocationID.x;");
  emitEncoding(e, inputs);
  e.layer(names("e", inputs), false, inputs, group, "pc.weightBase", "uint(w4.length()) - 1u", "s", "h", true);
  for (uint32_t j = 0; j < group; j++)
    e.line("act[pc.outOffset + " + std::to_string(j) + "u * pc.chunk + t] = h" + std::to_string(j / 4) + "." + kLane[j % 4] + ";");
  e.s << "}\n";
  return e.s.str();
}

void emitScratchInputs(Emitter& e, uint32_t width) {
  e.line("uint t = gl_GlobalInvocationID.x;");
  for (uint32_t q = 0; q < width / 4; q++) {
    std::string v = "vec4 a" + std::to_string(q) + " = vec4(";
    for (uint32_t c = 0; c < 4; c++)
      v += std::string(c ? ", " : "") + "act[pc.inOffset + " + std::to_string(4 * q + c) + "u * pc.chunk + t]";
    e.line(v + ");");
  }
}

std::string layerHidden(uint32_t width) {
  uint32_t group = refrax::heightLayerGroupOutputs(width);
  Emitter e;
  e.s << header("hidden layer, " + std::to_string(group) + " of " + std::to_string(width) + " outputs", stageVec4s(group * width),
                {"readonly buffer Weights { vec4 w4[]; };", "buffer Act { float act[]; };"});
  e.stage("pc.weightBase + 0u", layerRows(width, group) * width, "uint(w4.length()) - 1u");
  emitScratchInputs(e, width);
  e.layer(names("a", width / 4), true, width, group, "pc.weightBase", "uint(w4.length()) - 1u", "s", "h", true);
  for (uint32_t j = 0; j < group; j++)
    e.line("act[pc.outOffset + " + std::to_string(j) + "u * pc.chunk + t] = h" + std::to_string(j / 4) + "." + kLane[j % 4] + ";");
  e.s << "}\n";
  return e.s.str();
}

std::string layerLast(uint32_t width) {
  Emitter e;
  e.s << header("output layer, width " + std::to_string(width), stageVec4s(width),
                {"readonly buffer Weights { vec4 w4[]; };", "readonly buffer Points { vec2 points[]; };",
                 "readonly buffer Act { float act[]; };", "writeonly buffer Heights { float heights[]; };"});
  e.stage("pc.weightBase", width, "uint(w4.length()) - 1u");
  emitScratchInputs(e, width);
  e.line("uint i = pc.first + min(t, pc.count - 1u);");
  e.line("bool finitePoint = heightPointFinite(points[i]);");
  emitOutput(e, width, "a", "pc.weightBase", "uint(w4.length()) - 1u", true);
  e.line("if (t < pc.count) heights[i] = finitePoint ? r + pc.initialHeight : heightNaN();");
  e.s << "}\n";
  return e.s.str();
}

// Weight gradient of one layer over a tile of points (backward pass 2 with the scratch layout of
// height_shape.glsl, [point][neuron]): workgroup (tile, k-block, j-block); lane = input k; the
// tile's deltas D[t][j0..j0+mb) are staged in shared memory (zero for points past the chunk's
// count) and read at constant offsets, the lane's inputs X[t][k] are loaded straight; after
// the tile, one float add per weight and lane. The shape (n inputs, m outputs) is pushed, so
// one kernel per block size serves every layer of every width that mb divides; so is the
// scratch's stride between points' inputs (xStride >= n: a padded first layer stores more
// encoding inputs than the network has, engine/height/height_field.h).
std::string gradTile(uint32_t mb, bool atomic) {
  const uint32_t T = refrax::kHeightGradTile, L = refrax::kHeightGradLanes;
  std::ostringstream h;
  h << "#version 460\n"
    << "// Generated by shaders/height/generate_height_kernels.cpp at build time: weight-gradient tile, " << mb << " outputs x " << T
    << " points, " << (atomic ? "float atomicAdd" : "compare-and-swap add") << "\n"
    << "#extension GL_GOOGLE_include_directive : require\n";
  if (atomic) h << "#extension GL_EXT_shader_atomic_float : require\n#define REFRAX_FLOAT_ATOMIC_ADD\n";
  h << "layout(local_size_x = " << L << ") in;\n"
    << "layout(push_constant) uniform GradPush { uint count, n, m, xBase, dBase, weightBase, xStride; } pc;\n"
    << "layout(std430, set = 0, binding = 0) readonly buffer Scratch { float scratch[]; };\n"
    << "#include \"height_grad_output.glsl\"\n"
    << "shared float sd[" << T * mb << "];\n"
    << "void main() {\n"
    << "  uint lid = gl_LocalInvocationID.x;\n"
    << "  uint t0 = gl_WorkGroupID.x * " << T << "u;\n"
    << "  uint k = gl_WorkGroupID.y * " << L << "u + lid;\n"
    << "  uint kc = min(k, pc.n - 1u);\n"
    << "  uint j0 = gl_WorkGroupID.z * " << mb << "u;\n"
    << "  uint last = uint(scratch.length()) - 1u;\n";
  Emitter e;
  for (uint32_t c = 0; c < T * mb / L; c++) {
    std::string i = "(" + std::to_string(c * L) + "u + lid)";
    std::string tt = i + " / " + std::to_string(mb) + "u", jj = i + " % " + std::to_string(mb) + "u";
    // load unconditionally, then select (a load under a condition would be scalarised)
    std::string d = "d" + std::to_string(c);
    e.line("float " + d + " = scratch[min(pc.dBase + (t0 + " + tt + ") * pc.m + j0 + " + jj + ", last)];");
    e.line("sd[" + std::to_string(c * L) + "u + lid] = t0 + " + tt + " < pc.count ? " + d + " : 0.0;");
  }
  e.line("barrier();");
  for (uint32_t t = 0; t < T; t++) {
    std::string x = "x" + std::to_string(t);
    e.line("float " + x + " = scratch[min(pc.xBase + (t0 + " + std::to_string(t) + "u) * pc.xStride + kc, last)];");
    for (uint32_t j = 0; j < mb; j++) {
      std::string term = "sd[" + std::to_string(t * mb + j) + "] * " + x;
      e.line(t == 0 ? "float acc" + std::to_string(j) + " = " + term + ";" : "acc" + std::to_string(j) + " += " + term + ";");
    }
  }
  e.line("if (k < pc.n) {");
  for (uint32_t j = 0; j < mb; j++)
    e.line("  addToGradient(pc.weightBase + (j0 + " + std::to_string(j) + "u) * pc.n + k, acc" + std::to_string(j) + ");");
  e.line("}");
  return h.str() + e.s.str() + "}\n";
}

[[noreturn]] void usage() {
  std::fprintf(stderr,
               "usage: generate_height_kernels <out.comp> fused|backprop <width> <hidden> <octaves> | first <width> <octaves> | "
               "hidden <width> | last <width> | grad <outputsPerBlock> atomic|cas\n");
  std::exit(2);
}

uint32_t number(const char* s) {
  char* end = nullptr;
  long v = std::strtol(s, &end, 10);
  if (!end || *end || v < 1 || v > 4096) usage();
  return uint32_t(v);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) usage();
  std::string kind = argv[2], text;
  uint32_t width = number(argv[3]);
  if (width % 4 && kind != "grad") {
    std::fprintf(stderr, "generate_height_kernels: width must be a multiple of 4\n");
    return 2;
  }
  if (kind == "fused" && argc == 6)
    text = fused(width, number(argv[4]), uint32_t(std::atoi(argv[5])));
  else if (kind == "backprop" && argc == 6)
    text = fusedBackprop(width, number(argv[4]), uint32_t(std::atoi(argv[5])));
  else if (kind == "first" && argc == 5)
    text = layerFirst(width, uint32_t(std::atoi(argv[4])));
  else if (kind == "hidden" && argc == 4)
    text = layerHidden(width);
  else if (kind == "last" && argc == 4)
    text = layerLast(width);
  else if (kind == "grad" && argc == 5)
    text = gradTile(width, std::string(argv[4]) == "atomic");
  else
    usage();
  std::ofstream out(argv[1], std::ios::trunc);
  out << text;
  if (!out) {
    std::fprintf(stderr, "generate_height_kernels: cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
