// The median split of engine/trace/presort.h medianSplitOrder, as the device computes it
// (engine/trace/device_order.h): slots [0, n) split at (first + last) / 2, lavapipe's split.
#ifndef REFRAX_MEDIAN_SPLIT_GLSL
#define REFRAX_MEDIAN_SPLIT_GLSL
// The range [first, last] that holds slot p after `level` rounds of splits of [0, n - 1].
uvec2 medianSplitRange(uint p, uint n, uint level) {
  uint first = 0u, last = n - 1u;
  for (uint l = 0u; l < level && first < last; l++) {
    uint split = (first + last) / 2u;
    if (p <= split) last = split;
    else first = split + 1u;
  }
  return uvec2(first, last);
}
#endif
