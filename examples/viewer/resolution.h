// viewer/resolution.h — the responsiveness policy: render at a fraction of the window's
// resolution while the view is changing and frames are slow, at full resolution when still.
//
// The render size is the window size divided by an integer divisor d in 1…max_divisor
// (the image is scaled up to the window, nearest pixel). A frame's cost is taken as
// proportional to its pixel count, so a frame that took t ms at divisor d is predicted to
// take t · (d / d')² ms at divisor d'. After each frame:
// - still (camera not moving, lights not rotating): d = 1, full resolution at once;
// - moving: d becomes the smallest divisor whose predicted time fits the budget; a finer
//   divisor than the current one must fit `hysteresis` × budget, so the resolution does
//   not flip back and forth around the budget.
// Script mode does not use the policy: it always renders at full resolution, so its
// screenshots do not depend on how fast the machine is.
#pragma once

namespace viewer {

struct ResolutionPolicy {
  double budget_ms = 40.0;    // 25 frames per second while moving
  double hysteresis = 0.7;    // a finer divisor must fit in 70% of the budget
  int max_divisor = 4;        // at most a quarter of the window's width and height
  int divisor = 1;            // current divisor

  // Updates and returns the divisor for the next frame from the last frame's time (at the
  // current divisor) and whether the view is changing.
  int next(double frame_ms, bool moving);
};

// Render size along one axis for a window size and divisor: at least 1 pixel.
int scaled_size(int window_size, int divisor);

}  // namespace viewer
