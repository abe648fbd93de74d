// Shared helpers for the rasterizer suites: a hit-counting shader, pixel → clip-space
// positions, and a reference top-left coverage test written from the D3D10 definition.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "softpbr/raster/raster.h"

namespace softpbr::test {

namespace raster = softpbr::raster;

// Counts hits in .r: the fragment returns (1, 0, 0, 0) and premultiplied "over" adds it,
// since dst + src · ... = src + dst · (1 − 0). Depth never rejects nor changes anything.
struct CountShader {
  using Vertex = glm::vec4;  // clip-space position
  struct Varyings {};
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
  glm::vec4 fragment(const raster::Fragment<Varyings>&) const { return {1.0f, 0.0f, 0.0f, 0.0f}; }
};

// The same, shaded in packets of RendererOptions::lanes pixels.
struct CountPacketShader : CountShader {
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>&) const {
    return {F(1.0f), F(0.0f), F(0.0f), F(0.0f)};
  }
};

inline raster::DrawState counting_state() {
  raster::DrawState s;
  s.depth_test = raster::DepthTest::Always;
  s.depth_write = false;
  s.blend = raster::Blend::Over;
  return s;
}

// Clip-space position of pixel coordinates (px, py) (row 0 at the top, pixel centres at
// +0.5), w = 1. Computed in double: positions on a 1/256 grid snap back exactly.
inline glm::vec4 pixel_to_clip(double px, double py, int width, int height, double w = 1.0) {
  const double x = 2.0 * px / width - 1.0;
  const double y = 1.0 - 2.0 * py / height;
  return {static_cast<float>(x * w), static_cast<float>(y * w), 0.0f, static_cast<float>(w)};
}

struct Point {
  double x, y;
};

// Renders `indices` over `positions` (clip space) with a counting shader into a fresh
// width × height target and returns the hit count of every pixel (row-major).
template <class S = CountShader>
std::vector<int> render_counts(raster::Renderer& renderer, int width, int height,
                                      std::span<const glm::vec4> positions, std::span<const std::uint32_t> indices,
                                      raster::DrawState state = counting_state()) {
  raster::Target target(width, height);
  target.clear({0, 0, 0, 0});
  renderer.begin_frame(target);
  renderer.draw(S{}, positions, indices, state);
  renderer.end_frame();
  std::vector<int> counts(target.colors().size());
  for (std::size_t i = 0; i < counts.size(); ++i) counts[i] = static_cast<int>(target.colors()[i].r);
  return counts;
}

// The same for triangles given in pixel coordinates, three points each.
template <class S = CountShader>
std::vector<int> render_pixel_triangles(raster::Renderer& renderer, int width, int height,
                                        std::span<const Point> points,
                                        raster::DrawState state = counting_state()) {
  std::vector<glm::vec4> positions;
  std::vector<std::uint32_t> indices;
  for (const Point& p : points) {
    indices.push_back(static_cast<std::uint32_t>(positions.size()));
    positions.push_back(pixel_to_clip(p.x, p.y, width, height));
  }
  return render_counts<S>(renderer, width, height, positions, indices, state);
}

// Reference coverage, independent of setup.cpp: is the centre of pixel (px, py) covered by
// the triangle (a, b, c) in pixel coordinates (y down)? Positions are snapped to 1/256
// pixel as the rasterizer does. A centre on an edge counts when the edge is a top edge
// (exactly horizontal, the third vertex below it) or a left edge (not horizontal, the
// third vertex on its right) — the D3D10 rule, whatever the winding.
// reference_covers_point() takes the point (cx, cy) in 1/256 pixel instead: a pixel's
// sample (MSAA) at its centre plus the sample's offset.
inline bool reference_covers_point(Point a, Point b, Point c, std::int64_t cx, std::int64_t cy) {
  auto snap = [](double v) { return static_cast<std::int64_t>(std::floor(v * 256.0 + 0.5)); };
  const std::int64_t x[3] = {snap(a.x), snap(b.x), snap(c.x)};
  const std::int64_t y[3] = {snap(a.y), snap(b.y), snap(c.y)};
  auto side = [](std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t qx,
                 std::int64_t qy) {
    const std::int64_t d = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax);
    return (d > 0) - (d < 0);
  };
  if (side(x[0], y[0], x[1], y[1], x[2], y[2]) == 0) return false;  // zero area
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;  // edge (i, j), third vertex k
    const int third = side(x[i], y[i], x[j], y[j], x[k], y[k]);
    const int here = side(x[i], y[i], x[j], y[j], cx, cy);
    if (here == third) continue;
    if (here != 0) return false;
    bool top_or_left;
    if (y[i] == y[j]) {
      top_or_left = y[k] > y[i];  // horizontal: top when the triangle lies below it
    } else {
      // Not horizontal: left when the third vertex lies right of the edge's line at its
      // height, i.e. x_k > x_i + (y_k − y_i)(x_j − x_i)/(y_j − y_i), cross-multiplied.
      const std::int64_t dy = y[j] - y[i];
      const std::int64_t lhs = (x[k] - x[i]) * dy, rhs = (y[k] - y[i]) * (x[j] - x[i]);
      top_or_left = dy > 0 ? lhs > rhs : lhs < rhs;
    }
    if (!top_or_left) return false;
  }
  return true;
}

inline bool reference_covers(Point a, Point b, Point c, int px, int py) {
  return reference_covers_point(a, b, c, std::int64_t{px} * 256 + 128, std::int64_t{py} * 256 + 128);
}

// Reference hit counts of triangles given as three points each, row-major.
inline std::vector<int> reference_counts(int width, int height, std::span<const Point> points) {
  std::vector<int> counts(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), 0);
  for (std::size_t t = 0; t + 2 < points.size(); t += 3) {
    const Point a = points[t], b = points[t + 1], c = points[t + 2];
    // Only centres inside the bounding box can be covered.
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))) - 1);
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))) - 1);
    const int x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))) + 1);
    const int y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))) + 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        counts[static_cast<std::size_t>(y) * width + x] += reference_covers(a, b, c, x, y) ? 1 : 0;
  }
  return counts;
}

}  // namespace softpbr::test
