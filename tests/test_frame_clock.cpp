// The viewer's FPS readout (engine/view/frame_clock.h): it showed "31.2 FPS (1316.4 ms)" on
// 1.3 s frames, because its average started from the setup's near-zero interval.
#include <doctest/doctest.h>

#include "engine/view/frame_clock.h"

using namespace refrax;

TEST_CASE("frame clock: the setup's interval is skipped, and slow frames read as slow from the first") {
  FrameClock clock;
  CHECK(clock.fps() == 0.0);
  addFrameInterval(clock, 0.5);  // the interval before the first frame: setup, near zero
  CHECK(clock.meanMs == 0.0);
  CHECK(clock.fps() == 0.0);
  addFrameInterval(clock, 1300.0);
  CHECK(clock.meanMs == doctest::Approx(1300.0));
  CHECK(clock.fps() == doctest::Approx(1e3 / 1300.0));
  for (int i = 0; i < 3; i++) addFrameInterval(clock, 1300.0);
  CHECK(clock.meanMs == doctest::Approx(1300.0));  // FPS and ms always agree: fps = 1000 / ms
  CHECK(clock.fps() * clock.meanMs == doctest::Approx(1e3));
}

TEST_CASE("frame clock: the mean follows a change of frame time within about ten frames") {
  FrameClock clock;
  addFrameInterval(clock, 1.0);
  for (int i = 0; i < 5; i++) addFrameInterval(clock, 10.0);
  CHECK(clock.meanMs == doctest::Approx(10.0));
  for (int i = 0; i < 30; i++) addFrameInterval(clock, 40.0);
  CHECK(clock.meanMs == doctest::Approx(40.0).epsilon(0.05));  // 0.9^30 of the old 30 ms gap: 1.3 ms
  CHECK(clock.meanMs < 40.0);
}
