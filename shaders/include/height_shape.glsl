// The network's shape as specialization constants (engine/height/height_field.cpp sets them), and
// the backward scratch layout shared by height_backprop.comp and height_weight_grad*.comp.
// Weight layer l = 0..HIDDEN (HIDDEN is the linear output layer), row-major [out][in].
// Scratch, for a chunk of CHUNK points (t = point in chunk), all [t][neuron]:
//   X_l (input of weight layer l: X_0 the encoding, X_l the activations of hidden layer l)
//   D_l (dLoss / d(output of weight layer l); D_HIDDEN = dLoss/dHeight, one value).
#ifndef REFRAX_HEIGHT_SHAPE_GLSL
#define REFRAX_HEIGHT_SHAPE_GLSL
layout(constant_id = 0) const uint INPUTS = 26;
layout(constant_id = 1) const uint WIDTH = 64;
layout(constant_id = 2) const uint HIDDEN = 6;
layout(constant_id = 3) const float SLOPE = 0.01;

uint layerFanIn(uint l) { return l == 0u ? INPUTS : WIDTH; }
uint layerFanOut(uint l) { return l == HIDDEN ? 1u : WIDTH; }
uint layerWeightOffset(uint l) { return l == 0u ? 0u : WIDTH * INPUTS + (l - 1u) * WIDTH * WIDTH; }
uint scratchX(uint l, uint chunk) { return chunk * (l == 0u ? 0u : INPUTS + (l - 1u) * WIDTH); }
uint scratchD(uint l, uint chunk) { return chunk * (INPUTS + HIDDEN * WIDTH + l * WIDTH); }
#endif
