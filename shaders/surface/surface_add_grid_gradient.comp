#version 460
// gridGrad[i] += added[i]: a gradient the host computed (scaled) on the coarse grid (the water's
// priors) added to the pending dL/dheight on the device, in the push's own submission, where
// the host once read the sum back and wrote it again (two transfers per surface step; issue 48).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Added { float added[]; };
layout(std430, set = 0, binding = 1) buffer GridGrad { float gridGrad[]; };
layout(push_constant) uniform Push { uint count; } pc;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < pc.count) gridGrad[i] += added[i];
}
