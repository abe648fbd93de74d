// The responsiveness policy: lower resolution while moving and slow, full when still.
#include <doctest/doctest.h>

#include <vector>

#include "resolution.h"

using namespace viewer;

TEST_CASE("the divisor follows the last frame's time while moving and is 1 when still") {
  struct Case {
    int divisor;     // before
    double frame_ms; // the last frame, at that divisor
    bool moving;
    int expected;
  };
  // Budget 40 ms, hysteresis 0.7 (a finer divisor must be predicted at ≤ 28 ms), max 4.
  const Case cases[] = {
      {1, 30.0, true, 1},    // fits
      {1, 41.0, true, 2},    // 41/4 = 10.25 fits at 2
      {1, 150.0, true, 2},   // 37.5 at 2
      {1, 170.0, true, 3},   // 42.5 at 2, 18.9 at 3
      {1, 1000.0, true, 4},  // never fits: the coarsest
      {2, 10.0, true, 2},    // 40 predicted at 1: over 28, stay
      {2, 6.0, true, 1},     // 24 predicted at 1: recover
      {4, 5.0, true, 2},     // 80 predicted at 1, 20 at 2: recover two steps
      {3, 50.0, true, 4},    // 50 · (3/4)² = 28.1 at 4: coarser
      {3, 1000.0, false, 1}, // still: full resolution at once
      {4, 1.0, false, 1},
  };
  for (const Case& c : cases) {
    CAPTURE(c.divisor);
    CAPTURE(c.frame_ms);
    ResolutionPolicy p;
    p.divisor = c.divisor;
    const int expected = c.expected;
    CHECK(p.next(c.frame_ms, c.moving) == expected);
    CHECK(p.divisor == expected);
  }
}

TEST_CASE("with frame cost proportional to pixels the divisor settles without flipping") {
  // A frame costs 0.2 µs per pixel: 1920×1080 takes 415 ms, too slow at full resolution.
  const double ms_per_pixel = 0.0002;
  for (const int width : {320, 960, 1920, 3840}) {
    CAPTURE(width);
    const int height = width * 9 / 16;
    ResolutionPolicy p;
    std::vector<int> seen;
    for (int frame = 0; frame < 20; ++frame) {
      const int d = p.divisor;
      const double ms = ms_per_pixel * scaled_size(width, d) * scaled_size(height, d);
      seen.push_back(p.next(ms, true));
    }
    // Settled: the last ten frames use one divisor, and it fits the budget unless it is
    // the coarsest.
    for (std::size_t i = 10; i < seen.size(); ++i) CHECK(seen[i] == seen[9]);
    const int d = seen.back();
    const double settled_ms = ms_per_pixel * scaled_size(width, d) * scaled_size(height, d);
    CHECK((settled_ms <= p.budget_ms || d == p.max_divisor));
    if (d > 1) {  // and a finer divisor would not fit
      const double finer = ms_per_pixel * scaled_size(width, d - 1) * scaled_size(height, d - 1);
      CHECK(finer > p.budget_ms * p.hysteresis);
    }
    CHECK(p.next(settled_ms, false) == 1);  // still again: full resolution
  }
}

TEST_CASE("scaled sizes are at least one pixel") {
  CHECK(scaled_size(960, 1) == 960);
  CHECK(scaled_size(960, 4) == 240);
  CHECK(scaled_size(3, 4) == 1);
  CHECK(scaled_size(100, 0) == 100);
}
