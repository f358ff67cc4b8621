#version 460
// Sums `count` vec2 partial sums in one workgroup (fixed order, so the result does not
// depend on scheduling) and writes result = (scale.x * S.x + scale.y * S.y + bias, S.x, S.y, 0).
layout(local_size_x = 256) in;
layout(std430, set = 0, binding = 0) readonly buffer Partials { vec2 partial[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Result { vec4 result; };
layout(push_constant) uniform Push {
  uint count;
  float scaleX;
  float scaleY;
  float bias;
} pc;
shared vec2 groupSum[256];
void main() {
  uint l = gl_LocalInvocationID.x;
  vec2 sum = vec2(0.0);
  for (uint i = l; i < pc.count; i += 256u) sum += partial[i];
  groupSum[l] = sum;
  barrier();
  for (uint half_ = 128u; half_ > 0u; half_ >>= 1u) {
    if (l < half_) groupSum[l] += groupSum[l + half_];
    barrier();
  }
  if (l == 0u) {
    vec2 s = groupSum[0];
    result = vec4(pc.scaleX * s.x + pc.scaleY * s.y + pc.bias, s.x, s.y, 0.0);
  }
}
