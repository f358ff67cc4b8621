#version 460
// The weights laid out for generated kernels of more octaves than the network has
// (engine/height/height_field.h, "padded kernels"): the first layer's rows widened from
// `inputs` to `paddedInputs` columns with zeros, every later layer copied as it is. One
// invocation per padded weight.
layout(local_size_x = 64) in;
layout(push_constant) uniform PadPush {
  uint count;         // padded parameters
  uint width;         // rows of the first layer
  uint inputs;        // the network's encoding inputs
  uint paddedInputs;  // the kernels' encoding inputs
} pc;
layout(std430, set = 0, binding = 0) readonly buffer Weights { float w[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Padded { float padded[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= pc.count) return;
  uint firstLayer = pc.width * pc.paddedInputs;
  uint row = i / pc.paddedInputs, k = i % pc.paddedInputs;
  if (i >= firstLayer)
    padded[i] = w[i - pc.width * (pc.paddedInputs - pc.inputs)];
  else
    padded[i] = k < pc.inputs ? w[row * pc.inputs + k] : 0.0;
}
