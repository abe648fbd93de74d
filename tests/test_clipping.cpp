// Clipping and culling: the near plane and w ≤ 0 (clipped, never mirrored), the guard band
// (huge triangles stay watertight), needles, sub-pixel and non-finite triangles, and
// back-face culling for both front-face conventions.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "raster_helpers.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/mesh.h"

namespace {

using softpbr::test::Point;
namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;
namespace test = softpbr::test;

int total(const std::vector<int>& counts) { return std::accumulate(counts.begin(), counts.end(), 0); }
int most(const std::vector<int>& counts) { return *std::max_element(counts.begin(), counts.end()); }

std::vector<std::uint32_t> iota_indices(std::size_t n) {
  std::vector<std::uint32_t> v(n);
  std::iota(v.begin(), v.end(), 0u);
  return v;
}

// Transforms world positions by a matrix: the vertex stage of a plain camera.
std::vector<glm::vec4> transform(const glm::mat4& m, const std::vector<glm::vec3>& world) {
  std::vector<glm::vec4> out;
  for (const glm::vec3& p : world) out.push_back(m * glm::vec4(p, 1.0f));
  return out;
}

// A grid of n × n quads on the ground plane y = 0 over [x0, x1] × [z0, z1].
void ground_grid(float x0, float x1, float z0, float z1, int n, std::vector<glm::vec3>& pos,
                 std::vector<std::uint32_t>& idx) {
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) pos.push_back({x0 + (x1 - x0) * i / n, 0.0f, z0 + (z1 - z0) * j / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const auto a = static_cast<std::uint32_t>(j * (n + 1) + i), b = a + 1;
      const auto c = a + static_cast<std::uint32_t>(n + 1), d = c + 1;
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
}

}  // namespace

TEST_CASE("a ground plane crossing the near plane covers exactly the pixels whose rays hit it, once each") {
  constexpr int kW = 160, kH = 120;
  const float fovy = static_cast<float>(softpbr::dmath::radians(60.0));
  const float aspect = static_cast<float>(kW) / kH;
  const double tan_half = std::tan(0.5 * fovy);
  // The plane spans [−half_width, half_width] × [−ahead, behind] around the eye, which is 1
  // above it looking horizontally down −z. Huge planes put clip coordinates near ±1e7,
  // where float rounding alone exceeds the near distance.
  const struct {
    float half_width, ahead, behind, far;
    int n;
  } planes[] = {{20, 40, 5, 100, 1}, {20, 40, 5, 100, 7}, {1e5f, 1e5f, 1e5f, 1e6f, 1}, {1e7f, 1e7f, 1e7f, 1e8f, 1},
                {1e7f, 1e7f, 1e7f, 1e8f, 4}};
  for (const auto& plane : planes) {
    const glm::mat4 vp =
        pbr::perspective(fovy, aspect, 0.1f, plane.far) * pbr::look_at({0, 1, 0}, {0, 1, -1}, {0, 1, 0});
    std::vector<glm::vec3> world;
    std::vector<std::uint32_t> idx;
    ground_grid(-plane.half_width, plane.half_width, -plane.ahead, plane.behind, plane.n, world, idx);
    const std::vector<glm::vec4> clip = transform(vp, world);
    for (const int tile : {8, 64}) {
      raster::Renderer renderer({.threads = 2, .tile_size = tile});
      const std::vector<int> counts = test::render_counts(renderer, kW, kH, clip, idx);
      int wrong = 0, unsure = 0, hits = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          // The ray through the pixel centre in view space: (dx, dy, −1).
          const double dx = (2.0 * (x + 0.5) / kW - 1.0) * tan_half * aspect;
          const double dy = (1.0 - 2.0 * (y + 0.5) / kH) * tan_half;
          int expected = 0;
          bool sure = true;
          if (dy < 0) {
            const double t = 1.0 / -dy;  // the ray meets y = 0 at depth t (always ≥ near)
            const double hx = dx * t;
            expected = (std::fabs(hx) < plane.half_width && t < plane.ahead) ? 1 : 0;
            sure = std::fabs(std::fabs(hx) - plane.half_width) > 0.02 * plane.half_width &&
                   std::fabs(t - plane.ahead) > 0.02 * plane.ahead;
          }
          const int c = counts[y * kW + x];
          hits += c == 1;
          if (!sure) {
            ++unsure;
            if (c > 1) ++wrong;
          } else if (c != expected) {
            ++wrong;
          }
        }
      CAPTURE(plane.half_width);
      CAPTURE(plane.n);
      CAPTURE(tile);
      CHECK(wrong == 0);
      CHECK(unsure < kW * kH / 20);
      CHECK(hits > kW * kH / 3);  // the lower half, less the far corners
    }
  }
}

TEST_CASE("a triangle partly behind the eye is clipped, never mirrored to the other side") {
  constexpr int kW = 64, kH = 48;
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  SUBCASE("hand-built clip coordinates: w goes from 1 to −1") {
    // A and B project to x = −0.5; C (w = −1) would project to x = +1 if divided naively.
    // On the segment towards C, x/w = (−0.5 − 0.5t)/(1 − 2t) ≤ −0.5 wherever w > 0.
    for (const float cy : {0.0f, 0.9f, -0.9f}) {
      const std::vector<glm::vec4> clip = {{-0.5f, -0.5f, 0, 1}, {-0.5f, 0.5f, 0, 1}, {-1.0f, cy, 0, -1}};
      for (const bool reversed : {false, true}) {
        std::vector<std::uint32_t> idx = {0, 1, 2};
        if (reversed) std::swap(idx[1], idx[2]);
        const std::vector<int> counts = test::render_counts(renderer, kW, kH, clip, idx);
        int wrong_side = 0;
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x)
            if (counts[y * kW + x] != 0 && 2.0 * (x + 0.5) / kW - 1.0 > -0.5) ++wrong_side;
        CAPTURE(cy);
        CHECK(wrong_side == 0);
        CHECK(total(counts) > 0);
        CHECK(most(counts) == 1);
      }
    }
  }
  SUBCASE("a real camera: a wall at x = −1 reaching behind the eye stays on the left half") {
    const glm::mat4 vp =
        pbr::perspective(static_cast<float>(softpbr::dmath::radians(70.0)), static_cast<float>(kW) / kH, 0.1f, 50.0f) *
        pbr::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
    const std::vector<glm::vec3> world = {{-1, -0.5f, -2}, {-1, 0.5f, -2}, {-1, 0, 3}};  // the last is behind
    const std::vector<int> counts = test::render_counts(renderer, kW, kH, transform(vp, world), iota_indices(3));
    int right_half = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = kW / 2; x < kW; ++x) right_half += counts[y * kW + x];
    CHECK(right_half == 0);
    CHECK(total(counts) > 0);
  }
}

TEST_CASE("triangles entirely behind the eye or with w <= 0 at every vertex draw nothing") {
  constexpr int kW = 32, kH = 32;
  raster::Renderer renderer({.threads = 1, .tile_size = 8});
  const float ws[][3] = {{0, 0, 0}, {-1, -1, -1}, {0, -1, -2}, {-1e-6f, 0, -3}, {-1e6f, -1, 0},
                         {1e-6f, 1e-6f, 1e-6f} /* below kMinClipW: at the eye */};
  for (const auto& w : ws) {
    // x, y inside the frustum for w = ±1, so only w decides.
    const std::vector<glm::vec4> clip = {{-0.5f * w[0], -0.5f * w[0], 0, w[0]}, {0.9f, -0.7f, 0.1f, w[1]},
                                         {0.2f, 0.8f, -0.1f, w[2]}, {-0.5f, -0.5f, 0, w[0]}};
    CAPTURE(w[0]);
    CAPTURE(w[1]);
    CAPTURE(w[2]);
    CHECK(total(test::render_counts(renderer, kW, kH, clip, std::vector<std::uint32_t>{0, 1, 2, 3, 2, 1})) == 0);
  }
  // A vertex at the clip-space origin (the eye, w = 0): the triangle projects onto its
  // opposite edge, a line, so nothing is drawn.
  const std::vector<glm::vec4> at_eye = {{0, 0, 0, 0}, {0.5f, -0.5f, 0, 1}, {0.5f, 0.5f, 0, 1}};
  CHECK(total(test::render_counts(renderer, kW, kH, at_eye, iota_indices(3))) == 0);
  // A camera looking down −z; the triangle at z = +1..+5 is behind it.
  const glm::mat4 vp = pbr::perspective(1.0f, 1.0f, 0.1f, 100.0f) * pbr::look_at({0, 0, 0}, {0, 0, -1}, {0, 1, 0});
  const std::vector<glm::vec3> behind = {{-1, -1, 1}, {1, -1, 5}, {0, 1, 3}};
  CHECK(total(test::render_counts(renderer, kW, kH, transform(vp, behind), iota_indices(3))) == 0);
  // The same triangle mirrored in front of the eye is drawn: the test can fail.
  const std::vector<glm::vec3> front = {{-1, -1, -1}, {1, -1, -5}, {0, 1, -3}};
  CHECK(total(test::render_counts(renderer, kW, kH, transform(vp, front), iota_indices(3))) > 0);
}

TEST_CASE("a quad spanning ±1e6 covers every pixel exactly once (guard-band clipping is watertight)") {
  const int sizes[][2] = {{64, 64}, {100, 37}, {333, 200}};
  for (const auto& size : sizes)
    for (const int tile : {8, 16, 64})
      for (const float w : {1.0f, 3.5f})
        for (const int diagonal : {0, 1}) {
          const float e = 1e6f * w;
          const std::vector<glm::vec4> clip = {{-e, -e, 0, w}, {e, -e, 0, w}, {e, e, 0, w}, {-e, e, 0, w}};
          const std::vector<std::uint32_t> idx = diagonal == 0 ? std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}
                                                               : std::vector<std::uint32_t>{0, 1, 3, 1, 2, 3};
          raster::Renderer renderer({.threads = 2, .tile_size = tile});
          const std::vector<int> counts = test::render_counts(renderer, size[0], size[1], clip, idx);
          CAPTURE(size[0]);
          CAPTURE(size[1]);
          CAPTURE(tile);
          CAPTURE(w);
          CAPTURE(diagonal);
          CHECK(std::count(counts.begin(), counts.end(), 1) == size[0] * size[1]);
        }
}

TEST_CASE("an edge of a huge triangle crosses the screen exactly along its line (guard-band clipping moves nothing)") {
  constexpr int kW = 200, kH = 150;
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  for (const float slope : {0.0f, 0.375f, -2.5f, 7.0f, -0.01f})
    for (const float offset : {0.1037f, -0.3111f})  // rows of centres are at 1 − (k + 0.5)/75
      for (const float reach : {1e4f, 1e6f}) {
        // Edge a–b runs from x = −reach to +reach through (0, offset); c is far below, so on
        // screen the triangle is the half-plane under the line a–b.
        const glm::vec4 a{-reach, offset - reach * slope, 0, 1}, b{reach, offset + reach * slope, 0, 1};
        const std::vector<glm::vec4> clip = {a, b, {0, -1e7f, 0, 1}};
        const std::vector<int> counts = test::render_counts(renderer, kW, kH, clip, iota_indices(3));
        int wrong = 0, near_line = 0;
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x) {
            // The line through the float end points, in double, at this pixel centre.
            const double nx = 2.0 * (x + 0.5) / kW - 1.0, ny = 1.0 - 2.0 * (y + 0.5) / kH;
            const double line_y = double{a.y} + (nx - a.x) * ((double{b.y} - a.y) / (double{b.x} - a.x));
            if (std::fabs(ny - line_y) * kH / 2 < 0.01) {  // within 1/100 pixel: either is fine
              ++near_line;
              continue;
            }
            wrong += counts[y * kW + x] != (ny < line_y ? 1 : 0);
          }
        CAPTURE(slope);
        CAPTURE(offset);
        CAPTURE(reach);
        CHECK(wrong == 0);
        CHECK(near_line < kW);
      }
}

TEST_CASE("a fan of huge triangles around any centre covers every pixel exactly once") {
  constexpr int kW = 120, kH = 90;
  const glm::vec2 centres[] = {{0, 0}, {0.3f, -0.2f}, {1.7f, 0.4f} /* off screen */, {-0.25f, 0.5f}};
  for (const glm::vec2 c : centres)
    for (const int spokes : {3, 7, 16}) {
      std::vector<glm::vec4> clip = {{c.x, c.y, 0, 1}};
      std::vector<std::uint32_t> idx;
      for (int i = 0; i < spokes; ++i) {
        const double a = 0.1 + 2.0 * softpbr::dmath::kPi * i / spokes;
        clip.push_back({static_cast<float>(1e6 * std::cos(a)), static_cast<float>(1e6 * std::sin(a)), 0, 1});
        idx.insert(idx.end(), {0u, static_cast<std::uint32_t>(1 + i), static_cast<std::uint32_t>(1 + (i + 1) % spokes)});
      }
      raster::Renderer renderer({.threads = 2, .tile_size = 16});
      const std::vector<int> counts = test::render_counts(renderer, kW, kH, clip, idx);
      CAPTURE(c.x);
      CAPTURE(c.y);
      CAPTURE(spokes);
      CHECK(std::count(counts.begin(), counts.end(), 1) == kW * kH);
    }
}

TEST_CASE("needles: long thin triangles match the reference coverage, never hit a pixel twice, and pairs fill their strip") {
  constexpr int kW = 256, kH = 192;
  std::mt19937 rng(4242);
  std::uniform_real_distribution<double> pos_x(-20, kW + 20), pos_y(-20, kH + 20), angle(0, 2 * softpbr::dmath::kPi);
  std::uniform_real_distribution<double> length(100, 400), width_log(-4, -0.3);
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  auto snap = [](double v) { return std::round(v * 256.0) / 256.0; };
  int mismatched = 0, drawn = 0;
  for (int i = 0; i < 300; ++i) {
    const Point a{snap(pos_x(rng)), snap(pos_y(rng))};
    const double t = angle(rng), len = length(rng), width = std::pow(10.0, width_log(rng));
    const Point b{snap(a.x + len * std::cos(t)), snap(a.y + len * std::sin(t))};
    // Two needles sharing the long edge a–b: a strip `width` wide either side of it.
    const Point c{snap(a.x - width * std::sin(t)), snap(a.y + width * std::cos(t))};
    const Point d{snap(b.x + width * std::sin(t)), snap(b.y - width * std::cos(t))};
    const std::vector<Point> pts = {a, b, c, b, a, d};
    const std::vector<int> counts = test::render_pixel_triangles(renderer, kW, kH, pts);
    mismatched += counts != test::reference_counts(kW, kH, pts);
    CHECK(most(counts) <= 1);
    drawn += total(counts);
  }
  CHECK(mismatched == 0);
  CHECK(drawn > 0);
  // An axis-aligned strip through one row of centres: exactly that row segment, once.
  const std::vector<Point> strip = {{0.2, 10.3}, {200.2, 10.3}, {200.2, 10.6}, {0.2, 10.3}, {200.2, 10.6}, {0.2, 10.6}};
  const std::vector<int> counts = test::render_pixel_triangles(renderer, kW, kH, strip);
  int wrong = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) wrong += counts[y * kW + x] != ((y == 10 && x < 200) ? 1 : 0);
  CHECK(wrong == 0);
}

TEST_CASE("needles crossing the guard band never hit a pixel twice nor more pixels than their length allows") {
  constexpr int kW = 200, kH = 150;
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  for (const float thickness : {1e-7f, 1e-5f, 1e-3f})
    for (const float slope : {0.0f, 0.375f, -2.5f}) {
      // From x = −1e6 to +1e6 in NDC along y = slope·x (exact in float), `thickness` NDC
      // units thick at x = 0.
      const std::vector<glm::vec4> clip = {{-1e6f, -1e6f * slope, 0, 1}, {1e6f, 1e6f * slope, 0, 1},
                                           {0.0f, thickness, 0, 1}};
      const std::vector<int> counts = test::render_counts(renderer, kW, kH, clip, iota_indices(3));
      CAPTURE(thickness);
      CAPTURE(slope);
      CHECK(most(counts) <= 1);
      CHECK(total(counts) <= kW + kH);
    }
}

TEST_CASE("sub-pixel triangles draw 0 or 1 pixel, exactly as the reference rule says") {
  constexpr int kW = 16, kH = 16;
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> origin(256 * 2, 256 * 13), offset(0, 255);
  raster::Renderer renderer({.threads = 1, .tile_size = 8});
  int ones = 0, mismatched = 0;
  for (int i = 0; i < 1000; ++i) {
    // Bounding box under one pixel: at most one centre fits.
    const int ox = origin(rng), oy = origin(rng);
    const Point a{ox / 256.0, oy / 256.0}, b{(ox + offset(rng)) / 256.0, (oy + offset(rng)) / 256.0},
        c{(ox + offset(rng)) / 256.0, (oy + offset(rng)) / 256.0};
    const std::vector<int> counts = test::render_pixel_triangles(renderer, kW, kH, std::vector<Point>{a, b, c});
    const int n = total(counts);
    CHECK(n <= 1);
    ones += n == 1;
    mismatched += counts != test::reference_counts(kW, kH, std::vector<Point>{a, b, c});
  }
  CHECK(mismatched == 0);
  CHECK(ones > 0);
  // Around a centre: one pixel; between centres: none.
  CHECK(total(test::render_pixel_triangles(renderer, kW, kH, std::vector<Point>{{5.3, 5.3}, {5.8, 5.4}, {5.4, 5.9}})) == 1);
  CHECK(total(test::render_pixel_triangles(renderer, kW, kH, std::vector<Point>{{5.6, 5.6}, {6.4, 5.6}, {6.0, 6.4}})) == 0);
}

TEST_CASE("triangles with NaN or infinite positions are skipped without disturbing the others") {
  constexpr int kW = 48, kH = 40;
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  const std::vector<glm::vec4> good = {{-0.8f, -0.8f, 0, 1}, {0.8f, -0.6f, 0, 1}, {0.1f, 0.9f, 0, 1}};
  const std::vector<int> alone = test::render_counts(renderer, kW, kH, good, iota_indices(3));
  REQUIRE(total(alone) > 100);
  for (const float bad : {nan, inf, -inf})
    for (int component = 0; component < 4; ++component)
      for (int vertex = 0; vertex < 3; ++vertex) {
        // Vertices 3..5: a copy of the good triangle with one broken component, shared by
        // two triangles; then the good triangle.
        std::vector<glm::vec4> clip = good;
        for (int k = 0; k < 3; ++k) clip.push_back(good[k]);
        clip[3 + vertex][component] = bad;
        const std::vector<std::uint32_t> idx = {3, 4, 5, 5, 4, 3, 0, 1, 2};
        const std::vector<int> counts = test::render_counts(renderer, kW, kH, clip, idx);
        CAPTURE(bad);
        CAPTURE(component);
        CAPTURE(vertex);
        CHECK(counts == alone);
      }
}

TEST_CASE("scaling every clip coordinate of a triangle by a power of two changes nothing, up to the float range") {
  // Homogeneous coordinates: (x, y, z, w) and (s·x, s·y, s·z, s·w) are the same point, and
  // for s = 2^k every product and quotient scales exactly, so the clipped, snapped
  // triangle must be the same at any k whose coordinates stay finite floats.
  constexpr int kW = 64, kH = 48;
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> xy(-3e5f, 3e5f), z(-2.0f, 2.0f), w(0.5f, 2.0f);
  raster::Renderer renderer({.threads = 1, .tile_size = 16});
  int wrong = 0, drawn = 0;
  for (int i = 0; i < 300; ++i) {
    // Vertices far outside the guard band (so it clips), some beyond near or far.
    std::vector<glm::vec4> clip;
    for (int k = 0; k < 3; ++k) {
      const float wk = w(rng);
      const float spread = k == 0 ? 2.5e-6f : 1.0f;  // vertex 0 within the target
      clip.push_back({spread * xy(rng) * wk, spread * xy(rng) * wk, z(rng) * wk, wk});
    }
    const std::vector<int> reference = test::render_counts(renderer, kW, kH, clip, iota_indices(3));
    drawn += total(reference) > 0;
    for (const int k : {1, 20, 60, 100}) {  // 3e5 · 2 · 2^100 ≈ 7.6e35 < 3.4e38 (w stays ≥ kMinClipW)
      std::vector<glm::vec4> scaled = clip;
      for (glm::vec4& p : scaled) p = glm::vec4(std::ldexp(p.x, k), std::ldexp(p.y, k), std::ldexp(p.z, k), std::ldexp(p.w, k));
      const std::vector<int> counts = test::render_counts(renderer, kW, kH, scaled, iota_indices(3));
      CAPTURE(i);
      CAPTURE(k);
      wrong += counts != reference;
    }
  }
  CHECK(wrong == 0);
  CHECK(drawn > 100);
}

TEST_CASE("clip coordinates up to ±1e15 never make a triangle, whole or split in two, hit a pixel twice") {
  // Random triangles mixing magnitudes 1 to 1e15 in every coordinate, w of both signs: the
  // clipper cuts edges whose ends are 1e15 apart at w = kMinClipW = 1e-5 and still must
  // not leave a vertex at w <= 0 (mirrored) or a non-convex polygon (overlapping fan).
  // (Beyond ~1e15 the w = 1e-5 cut is below double's resolution of such an edge.)
  constexpr int kW = 32, kH = 24;
  std::mt19937 rng(5);
  const float magnitudes[] = {1.0f, 1.0f, 1e3f, 1e6f, 1e10f, 1e15f};
  std::uniform_int_distribution<int> pick(0, 5);
  std::uniform_real_distribution<float> sign(-1.0f, 1.0f);
  raster::Renderer renderer({.threads = 1, .tile_size = 16});
  int doubled = 0, drawn = 0;
  for (int i = 0; i < 5000; ++i) {
    // One triangle, and the same triangle split at its edge midpoint: the two halves meet
    // along a shared edge.
    std::vector<glm::vec4> v(4);
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 4; ++c) v[k][c] = sign(rng) * magnitudes[pick(rng)];
    v[3] = v[1] * 0.5f + v[2] * 0.5f;
    const std::vector<int> whole = test::render_counts(renderer, kW, kH, v, std::vector<std::uint32_t>{0, 1, 2});
    const std::vector<int> halves =
        test::render_counts(renderer, kW, kH, v, std::vector<std::uint32_t>{0, 1, 3, 0, 3, 2});
    doubled += most(whole) > 1 || most(halves) > 1;
    drawn += total(whole) > 0;
  }
  CHECK(doubled == 0);
  CHECK(drawn > 500);
}

// A triangle that runs counter-clockwise on screen in NDC (y up).
const std::vector<glm::vec4> kCcwTriangle = {{-0.6f, -0.6f, 0, 1}, {0.7f, -0.5f, 0, 1}, {0.0f, 0.7f, 0, 1}};

// Counts hits in .r and front-facing hits in .g.
struct FacingShader {
  using Vertex = glm::vec4;
  struct Varyings {};
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {1.0f, f.front_facing ? 1.0f : 0.0f, 0, 0}; }
};

TEST_CASE("back-face culling keeps exactly the faces the front-face convention and cull mode select") {
  constexpr int kW = 32, kH = 32;
  struct Case {
    bool ccw_on_screen;
    raster::FrontFace front_face;
    raster::Cull cull;
    bool drawn;
    bool front;
  };
  using FF = raster::FrontFace;
  using C = raster::Cull;
  const Case cases[] = {
      {true, FF::CounterClockwise, C::None, true, true},   {false, FF::CounterClockwise, C::None, true, false},
      {true, FF::CounterClockwise, C::Back, true, true},   {false, FF::CounterClockwise, C::Back, false, false},
      {true, FF::CounterClockwise, C::Front, false, true}, {false, FF::CounterClockwise, C::Front, true, false},
      {true, FF::Clockwise, C::None, true, false},         {false, FF::Clockwise, C::None, true, true},
      {true, FF::Clockwise, C::Back, false, false},        {false, FF::Clockwise, C::Back, true, true},
      {true, FF::Clockwise, C::Front, true, false},        {false, FF::Clockwise, C::Front, false, true},
  };
  raster::Renderer renderer({.threads = 1, .tile_size = 16});
  for (const Case& c : cases) {
    const std::vector<std::uint32_t> idx = c.ccw_on_screen ? std::vector<std::uint32_t>{0, 1, 2}
                                                           : std::vector<std::uint32_t>{0, 2, 1};
    raster::DrawState state = test::counting_state();
    state.front_face = c.front_face;
    state.cull = c.cull;
    raster::Target target(kW, kH);
    target.clear({0, 0, 0, 0});
    renderer.begin_frame(target);
    renderer.draw(FacingShader{}, std::span<const glm::vec4>(kCcwTriangle), idx, state);
    renderer.end_frame();
    int hits = 0, front_hits = 0;
    for (const glm::vec4& px : target.colors()) {
      hits += static_cast<int>(px.r);
      front_hits += static_cast<int>(px.g);
    }
    CAPTURE(c.ccw_on_screen);
    CAPTURE(static_cast<int>(c.front_face));
    CAPTURE(static_cast<int>(c.cull));
    CHECK((hits > 0) == c.drawn);
    CHECK(front_hits == (c.front ? hits : 0));
  }
}

TEST_CASE("a closed sphere: back-culled plus front-culled coverage equals unculled coverage, and each is at most 1") {
  constexpr int kW = 96, kH = 80;
  const pbr::Mesh sphere = pbr::uv_sphere(1.0f, 24, 12);
  std::vector<glm::vec3> world;
  for (const auto& v : sphere.vertices) world.push_back(v.position);
  // Eyes outside the sphere, and one so close that the near plane cuts away all the
  // sphere it faces: it looks through the hole at the inside (back faces).
  const struct {
    glm::vec3 eye;
    bool sees_outside;
  } views[] = {{{0, 0, 4}, true}, {{2.5f, 1.5f, 2}, true}, {{0.02f, 0.03f, 1.05f}, false}};
  for (const auto& [eye, sees_outside] : views) {
    const glm::mat4 vp = pbr::perspective(1.0f, static_cast<float>(kW) / kH, 0.1f, 20.0f) *
                         pbr::look_at(eye, {0, 0, 0}, {0, 1, 0});
    const std::vector<glm::vec4> clip = transform(vp, world);
    raster::Renderer renderer({.threads = 2, .tile_size = 16});
    auto render = [&](raster::Cull cull, raster::FrontFace ff) {
      raster::DrawState state = test::counting_state();
      state.cull = cull;
      state.front_face = ff;
      return test::render_counts(renderer, kW, kH, clip, sphere.indices, state);
    };
    const auto none = render(raster::Cull::None, raster::FrontFace::CounterClockwise);
    const auto back = render(raster::Cull::Back, raster::FrontFace::CounterClockwise);
    const auto front = render(raster::Cull::Front, raster::FrontFace::CounterClockwise);
    const auto back_cw = render(raster::Cull::Back, raster::FrontFace::Clockwise);
    int sum_wrong = 0;
    for (std::size_t i = 0; i < none.size(); ++i) sum_wrong += back[i] + front[i] != none[i];
    const float eye_z = eye.z;  // a copy: Clang 14 cannot capture a structured binding
    CAPTURE(eye_z);
    CHECK(sum_wrong == 0);
    CHECK(most(back) <= 1);
    CHECK(most(front) <= 1);
    CHECK(back_cw == front);  // clockwise-front with back culling keeps what CCW front culling keeps
    CHECK(total(sees_outside ? back : front) > 0);
  }
}
