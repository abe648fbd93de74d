// The responsiveness policy (see resolution.h).
#include "resolution.h"

#include <algorithm>

namespace viewer {

int ResolutionPolicy::next(double frame_ms, bool moving) {
  if (!moving) return divisor = 1;
  const int current = std::clamp(divisor, 1, max_divisor);
  int chosen = max_divisor;
  for (int d = 1; d <= max_divisor; ++d) {
    const double ratio = static_cast<double>(current) / static_cast<double>(d);
    const double predicted = frame_ms * ratio * ratio;
    const double limit = d < current ? budget_ms * hysteresis : budget_ms;
    if (predicted <= limit) {
      chosen = d;
      break;
    }
  }
  return divisor = chosen;
}

int scaled_size(int window_size, int divisor) { return std::max(1, window_size / std::max(1, divisor)); }

}  // namespace viewer
