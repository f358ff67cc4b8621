#pragma once
// The viewer's frame-time readout: a running mean of the frame time (not of its inverse),
// from the first full frame. The interval before it is the setup's (pipeline compiles, the
// first upload), and averaging rates instead let one near-zero interval show "31 FPS" on
// 1.3 s frames for dozens of frames.

namespace refrax {

struct FrameClock {
  long frames = 0;       // intervals seen, the setup's included
  double meanMs = 0;     // running mean frame time; 0 until the first full frame
  double fps() const { return meanMs > 0 ? 1e3 / meanMs : 0.0; }
};

// Adds the interval since the previous frame. The first interval is skipped; the second
// starts the mean; later ones move it by `weight` (0.1: about ten frames to follow a change).
void addFrameInterval(FrameClock& clock, double intervalMs, double weight = 0.1);

}  // namespace refrax
