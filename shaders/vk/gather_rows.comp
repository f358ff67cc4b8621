#version 460
// dst row i = src row source[i], or zeros where source[i] is 0xFFFFFFFF (a new row).
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Src { float src[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Dst { float dst[]; };
layout(std430, set = 0, binding = 2) readonly buffer Source { uint source[]; };
layout(push_constant) uniform Push {
  uint rows;
  uint rowWidth;
} pc;
void main() {
  uint e = gl_GlobalInvocationID.x;
  if (e >= pc.rows * pc.rowWidth) return;
  uint row = e / pc.rowWidth;
  uint from = source[row];
  dst[e] = from == 0xFFFFFFFFu ? 0.0 : src[from * pc.rowWidth + e % pc.rowWidth];
}
