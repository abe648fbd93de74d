// MSAA in the rasterizer: the sample patterns, per-sample coverage (the top-left rule at
// every sample, against the independent reference of raster_helpers.h), watertightness per
// sample by additive counting, per-sample depth, the box resolve, clears and fast clears of
// multisampled targets, and shading once per pixel.
#include <atomic>
#include <cstdint>
#include <cstring>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "raster_helpers.h"
#include "softpbr/raster/detail/rast.h"
#include "softpbr/raster/raster.h"

namespace {

namespace raster = softpbr::raster;
using softpbr::test::Point;

// A flat colour per vertex (no perspective: w = 1), shaded per pixel; packets too.
struct FlatShader {
  struct Vertex {
    glm::vec4 position;
    glm::vec4 color;
  };
  struct Varyings {
    glm::vec4 color;
  };
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.color = in.color;
    return in.position;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return f.v.color; }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {p.v[0], p.v[1], p.v[2], p.v[3]};
  }
};

// A vertex at pixel coordinates (x, y) and window depth `depth`.
FlatShader::Vertex at(double x, double y, int width, int height, float depth, glm::vec4 color) {
  glm::vec4 p = softpbr::test::pixel_to_clip(x, y, width, height);
  p.z = 2.0f * depth - 1.0f;
  return {p, color};
}

// The hit count of sample s of every pixel after drawing `points` (three per triangle) with
// the counting shader (blend "over" with alpha 0 adds 1 to .r), into a width × height target
// of `samples`. Returned as counts[s][pixel].
template <class S>
std::vector<std::vector<int>> sample_counts(raster::Renderer& renderer, int width, int height, int samples,
                                            const std::vector<Point>& points) {
  std::vector<glm::vec4> positions;
  std::vector<std::uint32_t> indices;
  for (const Point& p : points) {
    indices.push_back(static_cast<std::uint32_t>(positions.size()));
    positions.push_back(softpbr::test::pixel_to_clip(p.x, p.y, width, height));
  }
  raster::Target target(width, height, samples);
  renderer.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
  renderer.draw(S{}, std::span<const glm::vec4>(positions), indices, softpbr::test::counting_state());
  renderer.end_frame();
  std::vector<std::vector<int>> counts(static_cast<std::size_t>(samples));
  for (int s = 0; s < samples; ++s)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) counts[s].push_back(static_cast<int>(target.sample_color(x, y, s).r));
  return counts;
}

// The reference's count for sample s of every pixel.
std::vector<std::vector<int>> reference_sample_counts(int width, int height, int samples,
                                                      const std::vector<Point>& points) {
  const auto offsets = raster::sample_offsets(samples);
  std::vector<std::vector<int>> counts(static_cast<std::size_t>(samples));
  for (int s = 0; s < samples; ++s)
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::int64_t cx = std::int64_t{x} * 256 + 128 + offsets[s].x * 16;
        const std::int64_t cy = std::int64_t{y} * 256 + 128 + offsets[s].y * 16;
        int n = 0;
        for (std::size_t t = 0; t + 2 < points.size(); t += 3)
          n += softpbr::test::reference_covers_point(points[t], points[t + 1], points[t + 2], cx, cy) ? 1 : 0;
        counts[s].push_back(n);
      }
  return counts;
}

// Random triangles whose vertices lie on the 1/16-pixel grid of the sample offsets, so that
// many edges pass exactly through samples (where only the top-left rule decides).
std::vector<Point> grid_triangles(std::mt19937& rng, int count, int width, int height) {
  std::uniform_int_distribution<int> gx(-16, width * 16 + 16), gy(-16, height * 16 + 16);
  std::vector<Point> points;
  for (int i = 0; i < 3 * count; ++i) points.push_back({gx(rng) / 16.0, gy(rng) / 16.0});
  return points;
}

}  // namespace

TEST_CASE("the tile kernel's sample-lane masks turn into pixel order exactly (all 65536 masks)") {
  // Sample lane k = 4·s + j (sample s of pixel j) goes to bit 4·j + s.
  for (unsigned x = 0; x < 0x10000u; ++x) {
    unsigned expected = 0, pixels = 0;
    for (int s = 0; s < 4; ++s)
      for (int j = 0; j < 4; ++j)
        if (x >> (4 * s + j) & 1u) expected |= 1u << (4 * j + s), pixels |= 1u << j;
    CAPTURE(x);
    REQUIRE(raster::detail::transpose_4x4_bits(x) == expected);
    REQUIRE(raster::detail::pixels_of_sample_lanes(x) == pixels);
  }
}

TEST_CASE("MSAA sample patterns are the standard D3D/Vulkan 4x and 8x positions, distinct and inside the pixel") {
  const auto one = raster::sample_offsets(1);
  REQUIRE(one.size() == 1);
  CHECK(one[0].x == 0);
  CHECK(one[0].y == 0);
  const std::vector<std::pair<int, int>> four = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
  const std::vector<std::pair<int, int>> eight = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
  for (const auto& entry : {std::pair{4, four}, std::pair{8, eight}}) {
    // Not a structured binding: Clang 14 cannot capture one in CAPTURE's lambda.
    const int n = entry.first;
    const auto& expected = entry.second;
    CAPTURE(n);
    const auto o = raster::sample_offsets(n);
    REQUIRE(o.size() == expected.size());
    std::set<std::pair<int, int>> distinct;
    for (std::size_t i = 0; i < o.size(); ++i) {
      CHECK(o[i].x == expected[i].first);
      CHECK(o[i].y == expected[i].second);
      CHECK(o[i].x >= -8);
      CHECK(o[i].x < 8);
      CHECK(o[i].y >= -8);
      CHECK(o[i].y < 8);
      distinct.insert({o[i].x, o[i].y});
    }
    CHECK(distinct.size() == o.size());
  }
  CHECK(raster::sample_reach(1) == 0);
  CHECK(raster::sample_reach(4) == 96);
  CHECK(raster::sample_reach(8) == 112);
  CHECK_THROWS_AS(raster::sample_offsets(2), std::invalid_argument);
  CHECK_THROWS_AS(raster::Target(4, 4, 2), std::invalid_argument);
  CHECK_THROWS_AS(raster::Target(4, 4, 16), std::invalid_argument);
  CHECK_THROWS_AS(raster::Target(4, 4, 0), std::invalid_argument);
}

TEST_CASE("a multisampled target keeps its depths by 2x2 quads, sample by sample, and a 1-sample target row-major") {
  // 1 sample: y · width + x.
  CHECK(raster::depth_index(5, 1, 3, 2, 0) == 13u);
  CHECK(raster::depth_count(5, 3, 1) == 15u);
  // 4 samples, 5 pixels a row (3 quads a row): pixel (3, 2) is pixel 1 (top-right) of quad
  // (1, 1) = quad 4; its sample 2 is at 4 · 16 + 4 · 2 + 1.
  CHECK(raster::depth_index(5, 4, 3, 2, 2) == 73u);
  CHECK(raster::depth_index(5, 4, 2, 3, 0) == 66u);  // bottom-left of quad 4, sample 0
  CHECK(raster::depth_count(5, 3, 4) == 3u * 2u * 16u);
  CHECK(raster::depth_count(6, 4, 8) == 3u * 2u * 32u);
  // Every pixel's every sample has its own index, inside the count.
  for (const int n : {4, 8})
    for (const auto& [w, h] : {std::pair{5, 3}, std::pair{6, 4}, std::pair{1, 1}, std::pair{7, 2}}) {
      std::vector<int> hits(raster::depth_count(w, h, n), 0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int s = 0; s < n; ++s) ++hits.at(raster::depth_index(w, n, x, y, s));
      for (const int k : hits) CHECK(k <= 1);
    }
  // A target's accessors read there; a frame's depths land there.
  raster::Target t(6, 4, 4);
  raster::Renderer r({.threads = 1, .tile_size = 8});
  r.begin_frame(t, raster::ClearValues{{0, 0, 0, 1}, 0.75f});
  r.end_frame();
  t.depths()[raster::depth_index(6, 4, 5, 3, 1)] = 0.25f;
  CHECK(std::as_const(t).sample_depth(5, 3, 1) == 0.25f);
  CHECK(std::as_const(t).sample_depth(5, 3, 0) == 0.75f);
  t.depths()[raster::depth_index(6, 4, 4, 2, 0)] = 0.5f;
  CHECK(std::as_const(t).depth(4, 2) == 0.5f);
}

TEST_CASE("a multisampled target holds a colour and a depth per sample, and clears and frames clear every sample") {
  for (const int n : {4, 8}) {
    CAPTURE(n);
    raster::Target t(5, 3, n);
    CHECK(t.samples() == n);
    CHECK(t.colors().size() == static_cast<std::size_t>(15 * n));
    // Depths by 2×2 quads: 5 × 3 pixels pad to 3 × 2 quads of 4 · n.
    CHECK(t.depths().size() == static_cast<std::size_t>(24 * n));
    CHECK(raster::Target::bytes(5, 3, n) == static_cast<std::uint64_t>(15 * n * 16 + 24 * n * 4));
    t.clear({0.25f, 0.5f, 0.75f, 1.0f}, 0.5f);
    for (const glm::vec4& c : t.colors()) CHECK(c == glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
    for (const float d : t.depths()) CHECK(d == 0.5f);
    // A frame that clears writes every sample of every tile (tiles of 8: partial ones too).
    raster::Target big(37, 21, n);
    big.clear({9, 9, 9, 9}, 0.0f);
    raster::Renderer r({.threads = 2, .tile_size = 8});
    r.begin_frame(big, raster::ClearValues{{0.1f, 0.2f, 0.3f, 0.4f}, 0.75f});
    r.end_frame();
    for (const glm::vec4& c : big.colors()) CHECK(c == glm::vec4(0.1f, 0.2f, 0.3f, 0.4f));
    for (const float d : big.depths()) CHECK(d == 0.75f);
    const raster::Target resolved = raster::resolve_box(big);
    CHECK(resolved.samples() == 1);
    for (const glm::vec4& c : resolved.colors()) CHECK(c == glm::vec4(0.1f, 0.2f, 0.3f, 0.4f));  // exactly
  }
}

TEST_CASE("per-sample coverage of random triangles on the sample grid is the reference top-left rule at every sample") {
  std::mt19937 rng(16);
  constexpr int kW = 21, kH = 17;
  for (const int n : {1, 4, 8}) {
    CAPTURE(n);
    const std::vector<Point> points = grid_triangles(rng, 60, kW, kH);
    const auto expected = reference_sample_counts(kW, kH, n, points);
    int covered = 0;
    for (const auto& plane : expected)
      for (const int c : plane) covered += c;
    REQUIRE(covered > 500);  // not trivially empty
    for (const int lanes : {1, 4, 8, 16})
      for (const int tile : {8, 64}) {
        CAPTURE(lanes);
        CAPTURE(tile);
        raster::Renderer r({.threads = 2, .tile_size = tile, .lanes = lanes});
        CHECK(sample_counts<softpbr::test::CountPacketShader>(r, kW, kH, n, points) == expected);
      }
    raster::Renderer scalar({.threads = 1, .tile_size = 16});
    CHECK(sample_counts<softpbr::test::CountShader>(scalar, kW, kH, n, points) == expected);
  }
}

TEST_CASE("Renderer::frame_shading counts one shader invocation per pixel and triangle, alike for threads, tiles and lanes") {
  std::mt19937 rng(19);
  constexpr int kW = 23, kH = 19;
  for (const int n : {1, 4, 8}) {
    CAPTURE(n);
    const std::vector<Point> points = grid_triangles(rng, 40, kW, kH);
    // The reference: a triangle shades each pixel where it covers some sample (the depth
    // test is off in the counting state).
    const auto offsets = raster::sample_offsets(n);
    std::uint64_t expected = 0;
    for (std::size_t t = 0; t + 2 < points.size(); t += 3)
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          bool any = false;
          for (int s = 0; s < n && !any; ++s)
            any = softpbr::test::reference_covers_point(points[t], points[t + 1], points[t + 2],
                                                        std::int64_t{x} * 256 + 128 + offsets[s].x * 16,
                                                        std::int64_t{y} * 256 + 128 + offsets[s].y * 16);
          expected += any ? 1 : 0;
        }
    REQUIRE(expected > 300);
    for (const int lanes : {1, 4, 8, 16})
      for (const int tile : {8, 64})
        for (const unsigned threads : {1u, 2u}) {
          CAPTURE(lanes);
          CAPTURE(tile);
          CAPTURE(threads);
          raster::Renderer r({.threads = threads, .tile_size = tile, .lanes = lanes});
          sample_counts<softpbr::test::CountPacketShader>(r, kW, kH, n, points);
          const raster::ShadeCounts c = r.frame_shading();
          CHECK(c.invocations == expected);
          // Packets of up to `lanes`, at least one per tile touched: never fewer calls than
          // full packets would need, never more than one a pixel.
          CHECK(c.calls * static_cast<std::uint64_t>(lanes) >= c.invocations);
          CHECK(c.calls <= c.invocations);
        }
    raster::Renderer scalar({.threads = 2, .tile_size = 16});
    sample_counts<softpbr::test::CountShader>(scalar, kW, kH, n, points);
    CHECK(scalar.frame_shading().invocations == expected);
    CHECK(scalar.frame_shading().calls == expected);  // fragment(): one call a pixel
  }
}

TEST_CASE("Renderer::frame_shading: the early depth test saves invocations, and each frame counts afresh") {
  constexpr int kW = 32, kH = 24;
  const auto layer = [&](float depth) {
    return std::vector<FlatShader::Vertex>{at(0, 0, kW, kH, depth, {1, 0, 0, 1}), at(kW, 0, kW, kH, depth, {1, 0, 0, 1}),
                                          at(0, kH, kW, kH, depth, {1, 0, 0, 1}), at(kW, kH, kW, kH, depth, {1, 0, 0, 1})};
  };
  const std::vector<std::uint32_t> quad = {0, 1, 2, 2, 1, 3};
  const auto near = layer(0.25f), far = layer(0.75f);
  for (const int n : {1, 4}) {
    CAPTURE(n);
    raster::Target target(kW, kH, n);
    raster::Renderer r({.threads = 2, .tile_size = 8});
    const auto frame = [&](const std::vector<FlatShader::Vertex>& first, const std::vector<FlatShader::Vertex>& second) {
      r.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(first), quad);
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(second), quad);
      r.end_frame();
      return r.frame_shading().invocations;
    };
    // Two triangles make each layer; at MSAA the pixels on their shared diagonal whose
    // samples the two split are shaded by both.
    const std::uint64_t one_layer = [&] {
      r.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(far), quad);
      r.end_frame();
      return r.frame_shading().invocations;
    }();
    if (n == 1) CHECK(one_layer == std::uint64_t{kW} * kH);
    else CHECK(one_layer > std::uint64_t{kW} * kH);
    CHECK(frame(far, near) == 2 * one_layer);  // back to front: both layers shaded
    CHECK(frame(near, far) == one_layer);      // front to back: the far layer fails early
    r.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
    r.end_frame();
    CHECK(r.frame_shading().invocations == 0);
    CHECK(r.frame_shading().calls == 0);
  }
}

TEST_CASE("top-left rule per sample: an edge through a column of samples gives them to exactly one of two triangles") {
  // Vertical and horizontal edges through the samples of pixel (4, 4) at each sample's
  // offset: the two triangles of a split square share the edge; every sample of the target
  // is counted once, never twice or zero times inside the square.
  for (const int n : {4, 8}) {
    CAPTURE(n);
    for (const raster::SampleOffset& o : raster::sample_offsets(n)) {
      const double ex = 4.5 + o.x / 16.0, ey = 4.5 + o.y / 16.0;
      const std::vector<Point> vertical = {{1, 1}, {ex, 1}, {ex, 8}, {1, 1}, {ex, 8}, {1, 8},
                                           {ex, 1}, {8, 1}, {8, 8}, {ex, 1}, {8, 8}, {ex, 8}};
      const std::vector<Point> horizontal = {{1, 1}, {8, 1}, {8, ey}, {1, 1}, {8, ey}, {1, ey},
                                             {1, ey}, {8, ey}, {8, 8}, {1, ey}, {8, 8}, {1, 8}};
      for (const auto* points : {&vertical, &horizontal}) {
        raster::Renderer r({.threads = 1, .tile_size = 8});
        const auto counts = sample_counts<softpbr::test::CountPacketShader>(r, 10, 10, n, *points);
        CHECK(counts == reference_sample_counts(10, 10, n, *points));
        for (const auto& plane : counts)
          for (const int c : plane) CHECK(c <= 1);
        // Pixel (4, 4) lies inside the square: each of its samples once.
        for (int s = 0; s < n; ++s) CHECK(counts[s][4 * 10 + 4] == 1);
      }
    }
  }
}

TEST_CASE("watertight per sample: a jittered grid mesh and a fan cover every sample inside once, none outside") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> jitter(-5, 5);  // 1/16 pixel
  constexpr int kW = 30, kH = 30, kCells = 7;
  const double lo = 2.5, hi = 27.5, step = (hi - lo) / kCells;
  std::vector<std::vector<Point>> grid(kCells + 1, std::vector<Point>(kCells + 1));
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const bool inner = i > 0 && i < kCells && j > 0 && j < kCells;
      grid[j][i] = {lo + i * step + (inner ? jitter(rng) / 16.0 : 0.0), lo + j * step + (inner ? jitter(rng) / 16.0 : 0.0)};
    }
  std::vector<Point> mesh;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const Point a = grid[j][i], b = grid[j][i + 1], c = grid[j + 1][i + 1], d = grid[j + 1][i];
      if ((i + j) % 2) mesh.insert(mesh.end(), {a, b, c, a, c, d});
      else mesh.insert(mesh.end(), {a, b, d, b, c, d});
    }
  // A fan of 40 thin triangles around a centre on the sample grid.
  std::vector<Point> fan;
  const Point centre{15.0 + 3 / 16.0, 14.0 - 5 / 16.0};
  std::vector<Point> rim;
  for (int k = 0; k < 10; ++k) rim.push_back({lo + k * (hi - lo) / 10, lo});
  for (int k = 0; k < 10; ++k) rim.push_back({hi, lo + k * (hi - lo) / 10});
  for (int k = 0; k < 10; ++k) rim.push_back({hi - k * (hi - lo) / 10, hi});
  for (int k = 0; k < 10; ++k) rim.push_back({lo, hi - k * (hi - lo) / 10});
  for (std::size_t k = 0; k < rim.size(); ++k) fan.insert(fan.end(), {centre, rim[k], rim[(k + 1) % rim.size()]});
  for (const auto* points : {&mesh, &fan})
    for (const int n : {4, 8}) {
      CAPTURE(n);
      raster::Renderer r({.threads = 2, .tile_size = 8, .lanes = 8});
      const auto counts = sample_counts<softpbr::test::CountPacketShader>(r, kW, kH, n, *points);
      const auto offsets = raster::sample_offsets(n);
      int inside = 0;
      for (int s = 0; s < n; ++s)
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x) {
            const double sx = x + 0.5 + offsets[s].x / 16.0, sy = y + 0.5 + offsets[s].y / 16.0;
            const bool strictly_inside = sx > lo && sx < hi && sy > lo && sy < hi;
            const bool outside = sx < lo || sx > hi || sy < lo || sy > hi;
            const int c = counts[s][static_cast<std::size_t>(y) * kW + x];
            if (strictly_inside) {
              CHECK(c == 1);
              ++inside;
            }
            if (outside) CHECK(c == 0);
            CHECK(c <= 1);
          }
      CHECK(inside > 600 * n);
    }
}

TEST_CASE("a pixel half covered by a triangle resolves to exactly half, at 4x and 8x, along x and along y") {
  for (const int n : {4, 8})
    for (const bool along_x : {true, false}) {
      CAPTURE(n);
      CAPTURE(along_x);
      constexpr int kW = 8, kH = 8;
      const glm::vec4 white(1.0f);
      // A rectangle whose edge runs through the centres of column (row) 4: half of each
      // pattern's samples lie on either side.
      const double e = 4.5;
      std::vector<FlatShader::Vertex> v;
      for (const auto& [x, y] : along_x ? std::vector<std::pair<double, double>>{{0, 0}, {e, 0}, {e, 8}, {0, 8}}
                                        : std::vector<std::pair<double, double>>{{0, 0}, {8, 0}, {8, e}, {0, e}})
        v.push_back(at(x, y, kW, kH, 0.5f, white));
      const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
      raster::Target target(kW, kH, n);
      raster::Renderer r({.threads = 1, .tile_size = 8});
      r.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(v), idx);
      r.end_frame();
      const raster::Target resolved = raster::resolve_box(target);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const int c = along_x ? x : y;
          const float expected = c < 4 ? 1.0f : c == 4 ? 0.5f : 0.0f;
          CAPTURE(x);
          CAPTURE(y);
          CHECK(resolved.color(x, y) == glm::vec4(expected));
        }
      // The 8-bit resolve: the half pixel is sRGB(0.5) = 188.
      const raster::Image8 image = raster::resolve_srgb8(target);
      const std::size_t px = along_x ? 4 * 4 : 4 * kW * 4;
      CHECK(static_cast<int>(image.rgba[px]) == 188);
    }
}

TEST_CASE("depth is tested and written per sample: two surfaces crossing inside a pixel split its samples") {
  // Surface A at depth 0.5 everywhere (red), then B (blue), whose depth grows along x and
  // crosses 0.5 at the centres of column 4: per sample, B wins exactly left of the centre.
  constexpr int kW = 8, kH = 4;
  for (const int n : {4, 8})
    for (const int lanes : {1, 8}) {
      CAPTURE(n);
      CAPTURE(lanes);
      const glm::vec4 red(1, 0, 0, 1), blue(0, 0, 1, 1);
      auto depth_b = [](double x) { return static_cast<float>(0.5 + (x - 4.5) * 0.1); };
      std::vector<FlatShader::Vertex> a, b;
      for (const auto& [x, y] : {std::pair{0.0, 0.0}, {8.0, 0.0}, {8.0, 4.0}, {0.0, 4.0}}) {
        a.push_back(at(x, y, kW, kH, 0.5f, red));
        b.push_back(at(x, y, kW, kH, depth_b(x), blue));
      }
      const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
      raster::Target target(kW, kH, n);
      raster::Renderer r({.threads = 1, .tile_size = 8, .lanes = lanes});
      r.begin_frame(target, raster::ClearValues{{0, 0, 0, 1}, 1.0f});
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(a), idx);
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(b), idx);
      r.end_frame();
      const auto offsets = raster::sample_offsets(n);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          for (int s = 0; s < n; ++s) {
            const double sx = x + 0.5 + offsets[s].x / 16.0;
            const bool b_nearer = sx < 4.5;
            CAPTURE(x);
            CAPTURE(s);
            CHECK(target.sample_color(x, y, s) == (b_nearer ? blue : red));
            if (b_nearer) CHECK(target.sample_depth(x, y, s) < 0.5f);
            else CHECK(target.sample_depth(x, y, s) == 0.5f);
          }
    }
}

TEST_CASE("a multisampled pixel is shaded once, at its centre, and its colour goes to every covered sample") {
  // A shader that returns its fragment position: a pixel covered by one triangle gets the
  // same colour in every covered sample, the pixel centre's.
  struct PosShader {
    using Vertex = glm::vec4;
    struct Varyings {};
    glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
    glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {f.pos.x, f.pos.y, 1.0f, 1.0f}; }
  };
  constexpr int kW = 16, kH = 16;
  const std::vector<glm::vec4> tri = {softpbr::test::pixel_to_clip(1.2, 0.7, kW, kH),
                                      softpbr::test::pixel_to_clip(15.1, 6.3, kW, kH),
                                      softpbr::test::pixel_to_clip(3.3, 14.9, kW, kH)};
  const std::vector<std::uint32_t> idx = {0, 1, 2};
  for (const int n : {4, 8}) {
    raster::Target target(kW, kH, n);
    raster::Renderer r({.threads = 1, .tile_size = 8});
    r.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
    r.draw(PosShader{}, std::span<const glm::vec4>(tri), idx);
    r.end_frame();
    int partial = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        int covered = 0;
        for (int s = 0; s < n; ++s) {
          const glm::vec4 c = target.sample_color(x, y, s);
          if (c.b == 0.0f) continue;
          ++covered;
          CHECK(c == glm::vec4(x + 0.5f, y + 0.5f, 1.0f, 1.0f));
        }
        partial += covered > 0 && covered < n;
      }
    CHECK(partial > 10);  // edges cross pixels: those are shaded once too
  }
}

TEST_CASE("a multisampled target's fast clear gives a fresh target's bits frame after frame") {
  constexpr int kW = 70, kH = 50;
  auto quad = [](double x0, double y0, double x1, double y1, glm::vec4 c) {
    std::vector<FlatShader::Vertex> v;
    for (const auto& [x, y] : {std::pair{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}) v.push_back(at(x, y, kW, kH, 0.3f, c));
    return v;
  };
  const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
  const raster::ClearValues clear{{0.2f, 0.1f, 0.0f, 1.0f}, 1.0f};
  for (const int n : {4, 8}) {
    CAPTURE(n);
    raster::Renderer r({.threads = 2, .tile_size = 16});
    raster::Target reused(kW, kH, n);
    const std::vector<std::vector<FlatShader::Vertex>> frames = {quad(3.3, 4.1, 40.7, 30.2, {1, 0, 0, 1}),
                                                                  quad(30.1, 20.6, 66.9, 47.3, {0, 1, 0, 1}),
                                                                  quad(0.6, 0.4, 9.5, 9.5, {0, 0, 1, 1})};
    for (const auto& v : frames) {
      r.begin_frame(reused, clear);
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(v), idx);
      r.end_frame();
      raster::Target fresh(kW, kH, n);
      r.begin_frame(fresh, clear);
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(v), idx);
      r.end_frame();
      CHECK(raster::hash_colors(reused) == raster::hash_colors(fresh));
      CHECK(raster::hash_depths(reused) == raster::hash_depths(fresh));
    }
  }
}

namespace {
// A shader whose alpha is 0 left of x = 6: those pixels are discarded (no colour, no
// depth); the rest of the quad writes depth per covered sample.
struct CutShader {
  using Vertex = glm::vec4;
  struct Varyings {};
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {1, 1, 1, f.pos.x < 6.0f ? 0.0f : 1.0f}; }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {F(1.0f), F(1.0f), F(1.0f), softpbr::simd::select(p.pos_x < F(6.0f), F(0.0f), F(1.0f))};
  }
};
}  // namespace

TEST_CASE("alpha-tested draws test and write depth per sample after shading") {
  constexpr int kW = 12, kH = 6;
  std::vector<glm::vec4> v;
  for (const auto& [x, y] : {std::pair{1.5, 0.0}, {10.5, 0.0}, {10.5, 6.0}, {1.5, 6.0}}) {
    glm::vec4 p = softpbr::test::pixel_to_clip(x, y, kW, kH);
    p.z = 0.0f;  // window depth 0.5
    v.push_back(p);
  }
  const std::vector<std::uint32_t> idx = {0, 1, 2, 0, 2, 3};
  raster::DrawState state;
  state.alpha_test = true;
  for (const int n : {4, 8})
    for (const int lanes : {1, 4, 16}) {
      CAPTURE(n);
      CAPTURE(lanes);
      raster::Target target(kW, kH, n);
      raster::Renderer r({.threads = 1, .tile_size = 8, .lanes = lanes});
      r.begin_frame(target, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
      r.draw(CutShader{}, std::span<const glm::vec4>(v), idx, state);
      r.end_frame();
      const auto offsets = raster::sample_offsets(n);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
          for (int s = 0; s < n; ++s) {
            const double sx = x + 0.5 + offsets[s].x / 16.0;
            const bool drawn = x >= 6 && sx > 1.5 && sx < 10.5;
            CAPTURE(x);
            CAPTURE(s);
            CHECK(target.sample_depth(x, y, s) == (drawn ? 0.5f : 1.0f));
            CHECK(target.sample_color(x, y, s).a == (drawn ? 1.0f : 0.0f));
          }
    }
}

TEST_CASE("alpha to coverage keeps sample s where alpha >= ref + (s + 1/2)/N - 1/2, writes depth there only and alpha 1, N = 1 is the alpha test") {
  constexpr int kW = 40, kH = 4;
  // A quad over the target at window depth `depth`, colour from `left` to `right` along x.
  const auto quad = [](float depth, glm::vec4 left, glm::vec4 right) {
    const FlatShader::Vertex a = at(0, 0, kW, kH, depth, left), b = at(kW, 0, kW, kH, depth, right),
                             c = at(kW, kH, kW, kH, depth, right), d = at(0, kH, kW, kH, depth, left);
    return std::vector<FlatShader::Vertex>{a, b, c, a, c, d};
  };
  // Red, its alpha from −0.25 to 1.25: none to all samples along the row.
  const auto red = quad(0.25f, {1, 0, 0, -0.25f}, {1, 0, 0, 1.25f});
  const auto green = quad(0.75f, {0, 1, 0, 1}, {0, 1, 0, 1});
  const auto white = quad(0.5f, {1, 1, 1, 1}, {1, 1, 1, 1});
  raster::DrawState a2c;
  a2c.alpha_to_coverage = true;  // implies the alpha test, alpha_ref 0.5
  // The alpha each pixel is shaded with: the red quad drawn plainly, its alpha read back.
  raster::Target probe(kW, kH);
  {
    raster::Renderer r({.threads = 1});
    r.begin_frame(probe, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
    r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(red));
    r.end_frame();
  }
  struct Config {
    unsigned threads;
    int tile, lanes;
    bool dispatch;
  };
  for (const int n : {1, 4, 8}) {
    CAPTURE(n);
    std::uint64_t hash = 0;
    std::set<int> counts;
    for (const Config& c : {Config{1, 8, 1, false}, Config{2, 16, 4, true}, Config{1, 32, 8, true}, Config{2, 8, 16, true}}) {
      CAPTURE(c.lanes);
      CAPTURE(c.tile);
      raster::Target t(kW, kH, n);
      raster::Renderer r({.threads = c.threads, .tile_size = c.tile, .lanes = c.lanes, .dispatch = c.dispatch});
      r.begin_frame(t, raster::ClearValues{{0, 0, 1, 0}, 1.0f});
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(green));
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(red), a2c);
      // Behind red, in front of green: it shows exactly where red kept no sample (no depth).
      r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(white));
      r.end_frame();
      const raster::Target resolved = raster::resolve_box(t);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          CAPTURE(x);
          const float alpha = probe.color(x, y).a;
          int kept = 0;
          for (int s = 0; s < n; ++s) {
            CAPTURE(s);
            const bool keep = alpha >= 0.5f + ((static_cast<float>(s) + 0.5f) / static_cast<float>(n) - 0.5f);
            // The kept samples are the first k of the pattern.
            if (keep) {
              CHECK(s == kept);
              ++kept;
            }
            CHECK(t.sample_color(x, y, s) == (keep ? glm::vec4(1, 0, 0, 1) : glm::vec4(1, 1, 1, 1)));
            CHECK(t.sample_depth(x, y, s) == (keep ? 0.25f : 0.5f));
          }
          counts.insert(kept);
          // k of n samples red, the rest white: green resolves to exactly (n − k) / n.
          CHECK(resolved.color(x, y).g == static_cast<float>(n - kept) / static_cast<float>(n));
          if (n == 1) CHECK((kept == 1) == (alpha >= 0.5f));  // the alpha test
        }
      if (hash == 0) hash = raster::hash_colors(t);
      CHECK(raster::hash_colors(t) == hash);
    }
    // Every count from none to all occurs along the ramp.
    CHECK(counts.size() == static_cast<std::size_t>(n + 1));
  }
}

TEST_CASE("tile blocks: a cleared frame gives the bits of the same draws over a target cleared beforehand, in any state") {
  // In the pass that clears the frame, a multisampled tile is rasterized in a block of the
  // thread's own and written back (renderer.cpp); drawing over a target cleared
  // beforehand uses no block. Layers of large triangles (whole pixels) and small ones
  // (partly covered pixels), replaced, blended over, alpha tested and alpha to coverage,
  // with colours of every alpha, must give the same samples, depths and resolve either
  // way — the resolve of the tile callback's pixels (the block) included.
  constexpr int kW = 70, kH = 44;
  const raster::ClearValues clear{{0.1f, 0.2f, 0.3f, 0.4f}, 1.0f};
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  struct Layer {
    std::vector<FlatShader::Vertex> v;
    raster::DrawState state;
  };
  for (const int n : {4, 8})
    for (int rep = 0; rep < 8; ++rep) {
      CAPTURE(n);
      CAPTURE(rep);
      std::vector<Layer> layers;
      for (int k = 0; k < 7; ++k) {
        Layer layer;
        const bool large = rng() % 2 == 0;
        const int triangles = 1 + static_cast<int>(rng() % 5);
        for (int t = 0; t < 3 * triangles; ++t) {
          const double spread = large ? 60.0 : 6.0;
          const double cx = unit(rng) * kW, cy = unit(rng) * kH;
          layer.v.push_back(at(cx + (unit(rng) - 0.5) * spread, cy + (unit(rng) - 0.5) * spread, kW, kH,
                               0.1f + 0.8f * unit(rng), {unit(rng), unit(rng), unit(rng), unit(rng)}));
        }
        switch (rng() % 5) {
          case 1: layer.state.blend = raster::Blend::Over; break;
          case 2: layer.state.alpha_test = true; break;
          case 3: layer.state.alpha_to_coverage = true; break;
          case 4:
            layer.state.blend = raster::Blend::Over;
            layer.state.depth_test = raster::DepthTest::LessEqual;
            layer.state.depth_write = false;
            break;
          default: break;
        }
        layers.push_back(std::move(layer));
      }
      const auto draw_all = [&](raster::Renderer& r) {
        for (const Layer& layer : layers) r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(layer.v), layer.state);
      };
      raster::Target reference(kW, kH, n);
      reference.clear(clear.color, clear.depth);
      {
        raster::Renderer r({.threads = 1, .tile_size = 16});
        r.begin_frame(reference);  // no clear: drawn in the target itself
        draw_all(r);
        r.end_frame();
      }
      std::vector<glm::vec4> want(static_cast<std::size_t>(kW) * kH);
      raster::resolve_box(reference, 0, 0, kW, kH, want.data(), kW);
      struct Config {
        unsigned threads;
        int tile, lanes;
      };
      for (const Config& c : {Config{1, 16, 16}, Config{2, 8, 4}, Config{2, 32, 1}, Config{1, 64, 8}}) {
        CAPTURE(c.tile);
        CAPTURE(c.lanes);
        raster::Target t(kW, kH, n);
        raster::Renderer r({.threads = c.threads, .tile_size = c.tile, .lanes = c.lanes});
        r.begin_frame(t, clear);
        draw_all(r);
        // The tiles' resolve from what the callback gets (the blocks).
        std::vector<glm::vec4> got(want.size());
        r.end_frame([&](const raster::TileRect& rect, bool only_clear, const raster::TargetPixels& px) {
          if (only_clear) {
            for (int y = rect.y0; y < rect.y1; ++y)
              for (int x = rect.x0; x < rect.x1; ++x) got[static_cast<std::size_t>(y) * kW + x] = clear.color;
            return;
          }
          raster::resolve_box(px, rect.x0, rect.y0, rect.x1, rect.y1, got.data() + rect.y0 * kW + rect.x0, kW);
        });
        CHECK(raster::hash_colors(t) == raster::hash_colors(reference));
        CHECK(raster::hash_depths(t) == raster::hash_depths(reference));
        CHECK(std::memcmp(got.data(), want.data(), want.size() * sizeof(glm::vec4)) == 0);
      }
      // A transient target (SampleStorage::Transient) keeps nothing: its tile callback sees
      // every sample's colour and depth exactly as the kept reference holds them, drawn in
      // blocks alone (no planes allocated), or in planes when tiles are too large for a
      // block (128 × 128 × 4 samples) or the frame runs in passes (a budget of 1 byte: a
      // transient target's first pass may hold 4 bytes).
      struct TransientConfig {
        unsigned threads;
        int tile;
        std::size_t budget;
        bool planes;  // whether the frame needs the target's planes
      };
      for (const TransientConfig& c : {TransientConfig{1, 16, 0, false}, TransientConfig{2, 8, 0, false},
                                       TransientConfig{2, 64, 0, false},
                                       TransientConfig{2, 128, 0, true}, TransientConfig{2, 16, 1, true}}) {
        CAPTURE(c.threads);
        CAPTURE(c.tile);
        CAPTURE(c.budget);
        raster::Target t(kW, kH, n, nullptr, raster::SampleStorage::Transient);
        REQUIRE(t.transient());
        raster::Renderer r({.threads = c.threads, .tile_size = c.tile, .geometry_budget = c.budget});
        const std::size_t count = static_cast<std::size_t>(kW) * kH * static_cast<std::size_t>(n);
        std::vector<glm::vec4> colors(count, glm::vec4(-1.0f));
        std::vector<float> depths(count, -1.0f);
        std::atomic<int> cleared_without_pixels{0}, cleared_with_pixels{0};  // tiles run on two threads
        for (int frame = 0; frame < 2; ++frame) {  // the second frame over the first's blocks (or planes)
          r.begin_frame(t, clear);
          draw_all(r);
          r.end_frame([&](const raster::TileRect& rect, bool only_clear, const raster::TargetPixels& px) {
            if (only_clear) ++(px.colors == nullptr ? cleared_without_pixels : cleared_with_pixels);
            for (int s = 0; s < n; ++s)
              for (int y = rect.y0; y < rect.y1; ++y)
                for (int x = rect.x0; x < rect.x1; ++x) {
                  const std::size_t at = static_cast<std::size_t>(s) * kW * kH + static_cast<std::size_t>(y) * kW + x;
                  if (only_clear && px.colors == nullptr) {
                    colors[at] = clear.color, depths[at] = clear.depth;
                  } else {
                    const std::size_t i = static_cast<std::size_t>(s) * px.plane +
                                          static_cast<std::size_t>(y) * static_cast<std::size_t>(px.width) + x - px.origin;
                    colors[at] = px.colors[i], depths[at] = px.depths[px.depth_index(x, y, s)];
                  }
                }
          });
          CHECK(std::memcmp(colors.data(), std::as_const(reference).colors().data(), count * sizeof(glm::vec4)) == 0);
          bool same_depths = true;
          for (int s = 0; s < n; ++s)
            for (int y = 0; y < kH; ++y)
              for (int x = 0; x < kW; ++x) {
                const float d = depths[static_cast<std::size_t>(s) * kW * kH + static_cast<std::size_t>(y) * kW + x];
                const float want = reference.sample_depth(x, y, s);
                same_depths = same_depths && std::memcmp(&d, &want, sizeof d) == 0;
              }
          CHECK(same_depths);
          CHECK((t.allocated_bytes() != 0) == c.planes);
        }
        // Without planes an untouched tile has no pixels to show; with them it has.
        if (c.planes) CHECK(cleared_without_pixels == 0);
        else CHECK(cleared_with_pixels == 0);
        CHECK_THROWS_AS((void)std::as_const(t).colors(), std::logic_error);
      }
    }
}

TEST_CASE("a transient target's frame over its geometry budget runs in passes over planes made for it, the same samples") {
  // 16 × 16 × 4 samples take 20 480 bytes; with a budget of 4096 a transient target's first
  // pass may hold 16 384, and four draws of 60 small triangles each hold more, so it
  // splits (and the passes after it hold 4096).
  constexpr int kW = 16, kH = 16, kN = 4;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<std::vector<FlatShader::Vertex>> draws(4);
  for (auto& d : draws)
    for (int t = 0; t < 3 * 60; ++t)
      d.push_back(at(unit(rng) * kW, unit(rng) * kH, kW, kH, unit(rng), {unit(rng), unit(rng), unit(rng), 1.0f}));
  const raster::ClearValues clear{{0.5f, 0.25f, 0.0f, 1.0f}, 1.0f};
  raster::Target reference(kW, kH, kN);
  {
    raster::Renderer r({.threads = 1, .tile_size = 8, .geometry_budget = 0});
    r.begin_frame(reference, clear);
    for (const auto& d : draws) r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(d));
    r.end_frame();
  }
  raster::Target t(kW, kH, kN, nullptr, raster::SampleStorage::Transient);
  raster::Renderer r({.threads = 2, .tile_size = 8, .geometry_budget = 4096});
  for (int frame = 0; frame < 2; ++frame) {
    r.begin_frame(t, clear);
    for (const auto& d : draws) r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(d));
    std::atomic<bool> same{true};  // tiles run on two threads
    std::atomic<int> tiles{0};
    r.end_frame([&](const raster::TileRect& rect, bool, const raster::TargetPixels& px) {
      if (px.colors == nullptr) {
        same = false;
        return;
      }
      ++tiles;
      for (int s = 0; s < kN; ++s)
        for (int y = rect.y0; y < rect.y1; ++y)
          for (int x = rect.x0; x < rect.x1; ++x) {
            const std::size_t i = static_cast<std::size_t>(s) * px.plane + static_cast<std::size_t>(y) * px.width + x - px.origin;
            const bool match =
                std::memcmp(&px.colors[i], &reference.sample_color(x, y, s), sizeof(glm::vec4)) == 0 &&
                std::memcmp(&px.depths[px.depth_index(x, y, s)],
                            &std::as_const(reference).depths()[raster::depth_index(kW, kN, x, y, s)], sizeof(float)) == 0;
            if (!match) same = false;
          }
    });
    CHECK(tiles == 4);
    CHECK(same);
    CHECK(t.allocated_bytes() == raster::Target::bytes(kW, kH, kN));
  }
  // Geometry over the budget, told to begin_frame, under 4 times it (and under a 64 × 64 × 4
  // target's 327 680 bytes of samples) is one pass on a transient target: no planes. Told
  // nothing, or more than 4 times the budget, the frame splits (planes).
  const std::size_t total = 4 * raster::draw_geometry_bytes(180, 60, 4);
  for (const std::size_t told : {total, std::size_t{0}, 3 * total}) {
    CAPTURE(told);
    raster::Target big(64, 64, kN, nullptr, raster::SampleStorage::Transient);
    raster::Renderer one_pass({.threads = 2, .tile_size = 16, .geometry_budget = total / 2});
    one_pass.begin_frame(big, clear, told);
    for (const auto& d : draws) one_pass.draw(FlatShader{}, std::span<const FlatShader::Vertex>(d));
    one_pass.end_frame([](const raster::TileRect&, bool, const raster::TargetPixels&) {});
    CHECK((big.allocated_bytes() == 0) == (told == total));
  }
  raster::Target kept_big(64, 64, kN);  // a kept target splits at the budget (nothing to see but the same bits)
  raster::Renderer one_pass_kept({.threads = 2, .tile_size = 16, .geometry_budget = 0});
  one_pass_kept.begin_frame(kept_big, clear);
  for (const auto& d : draws) one_pass_kept.draw(FlatShader{}, std::span<const FlatShader::Vertex>(d));
  one_pass_kept.end_frame();
  raster::Target split(64, 64, kN);
  raster::Renderer splitting({.threads = 2, .tile_size = 16, .geometry_budget = total / 2});
  splitting.begin_frame(split, clear);
  for (const auto& d : draws) splitting.draw(FlatShader{}, std::span<const FlatShader::Vertex>(d));
  splitting.end_frame();
  CHECK(raster::hash_colors(split) == raster::hash_colors(kept_big));
}

TEST_CASE("a transient multisampled target keeps no samples: reading, clearing or drawing over it throws") {
  raster::Target t(40, 30, 4, nullptr, raster::SampleStorage::Transient);
  CHECK(t.transient());
  CHECK(t.samples() == 4);
  CHECK(t.allocated_bytes() == 0);
  CHECK_THROWS_AS((void)std::as_const(t).colors(), std::logic_error);
  CHECK_THROWS_AS((void)std::as_const(t).depths(), std::logic_error);
  CHECK_THROWS_AS((void)t.colors(), std::logic_error);
  CHECK_THROWS_AS((void)t.color(1, 2), std::logic_error);
  CHECK_THROWS_AS((void)t.sample_depth(1, 2, 3), std::logic_error);
  CHECK_THROWS_AS(t.clear(), std::logic_error);
  CHECK_THROWS_AS((void)raster::hash_colors(t), std::logic_error);
  CHECK_THROWS_AS((void)raster::resolve_box(t), std::logic_error);
  raster::Renderer r({.threads = 1});
  CHECK_THROWS_AS(r.begin_frame(t), std::logic_error);  // nothing to draw over
  // The renderer has no frame open after refusing: a cleared frame works.
  const std::vector<FlatShader::Vertex> v = {at(2, 2, 40, 30, 0.5f, {1, 0, 0, 1}), at(38, 4, 40, 30, 0.5f, {1, 0, 0, 1}),
                                             at(5, 28, 40, 30, 0.5f, {1, 0, 0, 1})};
  r.begin_frame(t, raster::ClearValues{});
  r.draw(FlatShader{}, std::span<const FlatShader::Vertex>(v));
  std::atomic<int> touched{0};
  r.end_frame([&](const raster::TileRect&, bool only_clear, const raster::TargetPixels& px) {
    touched += !only_clear;
    if (!only_clear) CHECK(px.colors != nullptr);
  });
  CHECK(touched > 0);
  CHECK(t.allocated_bytes() == 0);
  CHECK(r.frame_shading().invocations > 0);
  // One sample a pixel: the target is the image, so it is kept whatever was asked.
  raster::Target one(40, 30, 1, nullptr, raster::SampleStorage::Transient);
  CHECK_FALSE(one.transient());
  CHECK(one.allocated_bytes() == raster::Target::bytes(40, 30));
  CHECK(std::as_const(one).colors().size() == 40u * 30u);
}
