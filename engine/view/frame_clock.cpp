#include "engine/view/frame_clock.h"

namespace refrax {

void addFrameInterval(FrameClock& clock, double intervalMs, double weight) {
  long index = clock.frames++;
  if (index == 0) return;  // the setup's interval
  clock.meanMs = index == 1 ? intervalMs : (1.0 - weight) * clock.meanMs + weight * intervalMs;
}

}  // namespace refrax
