// Coverage: watertight meshes (no pixel twice, none missed) across tile sizes and
// windings, the top-left fill rule pixel by pixel, and zero-area triangles.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "raster_helpers.h"

namespace {

using softpbr::test::Point;
namespace raster = softpbr::raster;
namespace test = softpbr::test;

struct Mesh2D {
  std::vector<Point> points;
  std::vector<std::uint32_t> indices;
};

struct Square {
  double x0, y0, x1, y1;  // no pixel centre (k + 0.5) lies on its border
};

// A grid over the square with the given interior lines; cells split along alternating
// diagonals. With jitter > 0, interior points move by up to jitter × the smallest cell
// and border points slide along their border (corners stay): every cell stays convex,
// so the triangles still tile the square.
Mesh2D grid_mesh(const Square& sq, std::vector<double> xs, std::vector<double> ys, double jitter,
                 std::mt19937& rng) {
  xs.insert(xs.begin(), sq.x0);
  xs.push_back(sq.x1);
  ys.insert(ys.begin(), sq.y0);
  ys.push_back(sq.y1);
  double cell = 1e300;
  for (std::size_t i = 1; i < xs.size(); ++i) cell = std::min(cell, xs[i] - xs[i - 1]);
  for (std::size_t i = 1; i < ys.size(); ++i) cell = std::min(cell, ys[i] - ys[i - 1]);
  std::uniform_real_distribution<double> d(-jitter * cell, jitter * cell);
  Mesh2D m;
  const std::size_t nx = xs.size(), ny = ys.size();
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      Point p{xs[i], ys[j]};
      const bool border_x = i == 0 || i == nx - 1, border_y = j == 0 || j == ny - 1;
      if (jitter > 0 && !border_x) p.x += d(rng);
      if (jitter > 0 && !border_y) p.y += d(rng);
      m.points.push_back(p);
    }
  for (std::size_t j = 0; j + 1 < ny; ++j)
    for (std::size_t i = 0; i + 1 < nx; ++i) {
      const auto a = static_cast<std::uint32_t>(j * nx + i), b = a + 1;
      const auto c = static_cast<std::uint32_t>(a + nx), e = c + 1;
      if ((i + j) % 2 == 0) m.indices.insert(m.indices.end(), {a, b, e, a, e, c});
      else m.indices.insert(m.indices.end(), {a, b, c, b, e, c});
    }
  return m;
}

// The square's border walked clockwise (on screen) from its top-left corner, with the
// given extra points along each side (as fractions in (0, 1) of the side).
std::vector<Point> perimeter(const Square& sq, const std::vector<double>& fractions) {
  const Point corners[4] = {{sq.x0, sq.y0}, {sq.x1, sq.y0}, {sq.x1, sq.y1}, {sq.x0, sq.y1}};
  std::vector<Point> out;
  for (int s = 0; s < 4; ++s) {
    const Point a = corners[s], b = corners[(s + 1) % 4];
    out.push_back(a);
    std::vector<double> f = fractions;
    std::sort(f.begin(), f.end());
    for (double t : f) out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
  return out;
}

// A fan from an interior point to every border point.
Mesh2D centre_fan(const Square& sq, Point centre, const std::vector<double>& fractions) {
  Mesh2D m;
  m.points = perimeter(sq, fractions);
  const auto n = static_cast<std::uint32_t>(m.points.size());
  m.points.push_back(centre);
  for (std::uint32_t i = 0; i < n; ++i) m.indices.insert(m.indices.end(), {n, i, (i + 1) % n});
  return m;
}

// The border polygon (convex) fanned from its first vertex: long thin triangles, and
// zero-area ones where three fan points share a side.
Mesh2D corner_fan(const Square& sq, const std::vector<double>& fractions) {
  Mesh2D m;
  m.points = perimeter(sq, fractions);
  const auto n = static_cast<std::uint32_t>(m.points.size());
  for (std::uint32_t i = 1; i + 1 < n; ++i) m.indices.insert(m.indices.end(), {0u, i, i + 1});
  return m;
}

// Multiples of `step` strictly inside (lo, hi), shifted by `offset`.
std::vector<double> lines(double lo, double hi, double step, double offset) {
  std::vector<double> v;
  for (double x = std::ceil((lo - offset) / step) * step + offset; x < hi; x += step)
    if (x > lo) v.push_back(x);
  return v;
}

// Sorted random positions in (lo, hi), at least `gap` apart; on the 1/256 grid if `snap`.
std::vector<double> random_lines(double lo, double hi, int count, double gap, bool snap, std::mt19937& rng) {
  std::uniform_real_distribution<double> d(lo + gap, hi - gap);
  std::vector<double> v;
  for (int i = 0; i < count; ++i) {
    double x = d(rng);
    if (snap) x = std::round(x * 256.0) / 256.0;
    v.push_back(x);
  }
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (double x : v)
    if ((out.empty() ? x - lo : x - out.back()) >= gap && hi - x >= gap) out.push_back(x);
  return out;
}

enum class Winding { AsBuilt, Reversed, Mixed };

std::vector<glm::vec4> to_clip(const std::vector<Point>& pts, int w, int h) {
  std::vector<glm::vec4> out;
  for (const Point& p : pts) out.push_back(test::pixel_to_clip(p.x, p.y, w, h));
  return out;
}

std::vector<std::uint32_t> rewind(std::vector<std::uint32_t> idx, Winding winding) {
  for (std::size_t t = 0; t < idx.size() / 3; ++t)
    if (winding == Winding::Reversed || (winding == Winding::Mixed && t % 2 == 1))
      std::swap(idx[3 * t + 1], idx[3 * t + 2]);
  return idx;
}

struct NamedMesh {
  std::string name;
  Mesh2D mesh;
};

std::vector<NamedMesh> meshes_for(const Square& sq, std::mt19937& rng) {
  const double mx = 0.5 * (sq.x0 + sq.x1), my = 0.5 * (sq.y0 + sq.y1);
  std::vector<NamedMesh> out;
  // Grid lines through pixel centres (k + 0.5): horizontal, vertical and 45° diagonal
  // edges all run through centres.
  out.push_back({"grid on pixel centres",
                 grid_mesh(sq, lines(sq.x0, sq.x1, 4, 0.5), lines(sq.y0, sq.y1, 4, 0.5), 0, rng)});
  // Grid lines on every 8-pixel tile border (so on 16- and 64-pixel borders too).
  out.push_back({"grid on tile borders", grid_mesh(sq, lines(sq.x0, sq.x1, 8, 0), lines(sq.y0, sq.y1, 8, 0), 0, rng)});
  // Sub-pixel cells: most triangles cover no centre or one.
  out.push_back({"grid of 0.37-pixel cells",
                 grid_mesh(sq, lines(sq.x0, sq.x1, 0.37, 0.1), lines(sq.y0, sq.y1, 0.37, 0.2), 0, rng)});
  out.push_back({"grid at random 1/256 positions",
                 grid_mesh(sq, random_lines(sq.x0, sq.x1, 14, 1.0 / 64, true, rng),
                           random_lines(sq.y0, sq.y1, 14, 1.0 / 64, true, rng), 0, rng)});
  out.push_back({"jittered grid (random triangulation)",
                 grid_mesh(sq, lines(sq.x0, sq.x1, 5, 0.5), lines(sq.y0, sq.y1, 5, 0.5), 0.2, rng)});
  out.push_back({"jittered fine grid (random triangulation)",
                 grid_mesh(sq, lines(sq.x0, sq.x1, 1.5, 0.25), lines(sq.y0, sq.y1, 1.5, 0.25), 0.2, rng)});
  const std::vector<double> fractions = {0.125, 0.25, 0.3, 0.5, 0.61, 0.75, 0.875, 0.9};
  std::vector<double> random_fractions;
  std::uniform_real_distribution<double> f(0.01, 0.99);
  for (int i = 0; i < 11; ++i) random_fractions.push_back(f(rng));
  out.push_back({"fan around a pixel centre", centre_fan(sq, {std::floor(mx) + 0.5, std::floor(my) + 0.5}, fractions)});
  out.push_back({"fan around a tile corner", centre_fan(sq, {32.0, 32.0}, fractions)});
  out.push_back({"fan around a random point", centre_fan(sq, {mx + 3.1234567, my - 2.71828}, random_fractions)});
  out.push_back({"fan from a corner of the border polygon", corner_fan(sq, random_fractions)});
  return out;
}

}  // namespace

TEST_CASE("watertight meshes hit every pixel centre inside the square exactly once and nothing outside") {
  constexpr int kW = 100, kH = 84;
  // Borders at integers, tile multiples and sub-pixel offsets, never at k + 0.5.
  const Square squares[] = {{0, 0, 64, 64}, {16, 8, 80, 72}, {3.25, 5.125, 90.75, 77.0}, {1.75, 0.0625, 99.0, 84.0}};
  const int tiles[] = {8, 16, 64};
  const Winding windings[] = {Winding::AsBuilt, Winding::Reversed, Winding::Mixed};
  std::mt19937 rng(12345);
  int renders = 0;
  for (const Square& sq : squares) {
    std::vector<int> expected(kW * kH, 0);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        expected[y * kW + x] = (x + 0.5 > sq.x0 && x + 0.5 < sq.x1 && y + 0.5 > sq.y0 && y + 0.5 < sq.y1) ? 1 : 0;
    for (const NamedMesh& nm : meshes_for(sq, rng)) {
      const std::vector<glm::vec4> positions = to_clip(nm.mesh.points, kW, kH);
      for (const int tile : tiles)
        for (const Winding winding : windings) {
          // Shaded one pixel at a time, then in packets of 4 and 16 pixels.
          const int lanes = winding == Winding::AsBuilt ? 1 : winding == Winding::Reversed ? 4 : 16;
          raster::Renderer renderer({.threads = 2, .tile_size = tile, .lanes = lanes});
          const auto indices = rewind(nm.mesh.indices, winding);
          const std::vector<int> counts =
              winding == Winding::AsBuilt
                  ? test::render_counts(renderer, kW, kH, positions, indices)
                  : test::render_counts<test::CountPacketShader>(renderer, kW, kH, positions, indices);
          int wrong = 0, first = -1;
          for (int i = 0; i < kW * kH; ++i)
            if (counts[i] != expected[i]) {
              if (first < 0) first = i;
              ++wrong;
            }
          CAPTURE(nm.name);
          CAPTURE(tile);
          CAPTURE(static_cast<int>(winding));
          CAPTURE(sq.x0);
          CAPTURE(sq.y0);
          INFO("first wrong pixel (" << first % kW << ", " << first / kW << ") count "
                                     << (first >= 0 ? counts[first] : 0));
          CHECK(wrong == 0);
          ++renders;
        }
    }
  }
  CHECK(renders == 4 * 10 * 3 * 3);
}

// Pixel masks of 9×9 targets: 'X' drawn once, '.' not drawn.
struct FillCase {
  const char* name;
  Point v[3];
  const char* mask[9];
};

// Every edge below lies on pixel centres (vertices at k + 0.5). Top and left edges keep
// their centres, right and bottom edges lose them (D3D10 top-left rule, y down).
const FillCase kFillCases[] = {
    {"square (0.5,0.5)-(4.5,4.5), first half",  // with the second half below, the square
     {{0.5, 0.5}, {4.5, 0.5}, {4.5, 4.5}},     // covers x, y in [0, 3]
     {"XXXX.....", ".XXX.....", "..XX.....", "...X.....", ".........", ".........", ".........", ".........",
      "........."}},
    {"square (0.5,0.5)-(4.5,4.5), second half: the diagonal's centres go to the first half",
     {{0.5, 0.5}, {4.5, 4.5}, {0.5, 4.5}},
     {".........", "X........", "XX.......", "XXX......", ".........", ".........", ".........", ".........",
      "........."}},
    {"flat top, left edge vertical: top row and left column in, hypotenuse out",
     {{0.5, 0.5}, {8.5, 0.5}, {0.5, 8.5}},
     {"XXXXXXXX.", "XXXXXXX..", "XXXXXX...", "XXXXX....", "XXXX.....", "XXX......", "XX.......", "X........",
      "........."}},
    {"flat bottom, right edge vertical: bottom row and right column out, hypotenuse (a left edge) in",
     {{0.5, 8.5}, {8.5, 8.5}, {8.5, 0.5}},
     {".........", ".......X.", "......XX.", ".....XXX.", "....XXXX.", "...XXXXX.", "..XXXXXX.", ".XXXXXXX.",
      "........."}},
    {"pointing left: both slanted edges are left edges, the vertical right edge is out",
     {{0.5, 4.5}, {8.5, 0.5}, {8.5, 8.5}},
     {".........", "......XX.", "....XXXX.", "..XXXXXX.", "XXXXXXXX.", "..XXXXXX.", "....XXXX.", "......XX.",
      "........."}},
    {"pointing right: both slanted edges are right edges, the vertical left edge is in",
     {{8.5, 4.5}, {0.5, 8.5}, {0.5, 0.5}},
     {".........", "XX.......", "XXXX.....", "XXXXXX...", "XXXXXXXX.", "XXXXXX...", "XXXX.....", "XX.......",
      "........."}},
    {"pointing up: the flat bottom is out, the slanted edges split left in / right out",
     {{4.5, 0.5}, {8.5, 8.5}, {0.5, 8.5}},
     {".........", "....X....", "...XX....", "...XXX...", "..XXXX...", "..XXXXX..", ".XXXXXX..", ".XXXXXXX.",
      "........."}},
    {"pointing down: the flat top is in",
     {{0.5, 0.5}, {8.5, 0.5}, {4.5, 8.5}},
     {"XXXXXXXX.", ".XXXXXXX.", ".XXXXXX..", "..XXXXX..", "..XXXX...", "...XXX...", "...XX....", "....X....",
      "........."}},
};

TEST_CASE("top-left rule: centres on top and left edges are drawn, on right and bottom edges not, in both windings") {
  const int offsets[][2] = {{0, 0}, {4, 4}, {3, 5}, {7, 1}};  // straddling 8-pixel tile corners
  for (const FillCase& fc : kFillCases)
    for (const auto& off : offsets)
      for (const bool reversed : {false, true}) {
        CAPTURE(fc.name);
        CAPTURE(off[0]);
        CAPTURE(off[1]);
        CAPTURE(reversed);
        constexpr int kW = 20, kH = 20;
        std::vector<Point> pts;
        for (const Point& p : fc.v) pts.push_back({p.x + off[0], p.y + off[1]});
        if (reversed) std::swap(pts[1], pts[2]);
        raster::Renderer renderer({.threads = 1, .tile_size = 8});
        const std::vector<int> counts = test::render_pixel_triangles(renderer, kW, kH, pts);
        int wrong = 0, reference_wrong = 0;
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x) {
            const int mx = x - off[0], my = y - off[1];
            const bool in_mask = mx >= 0 && my >= 0 && mx < 9 && my < 9 && fc.mask[my][mx] == 'X';
            if (counts[y * kW + x] != (in_mask ? 1 : 0)) ++wrong;
            // The reference implementation agrees with the hand-drawn mask.
            if (test::reference_covers(pts[0], pts[1], pts[2], x, y) != in_mask) ++reference_wrong;
          }
        CHECK(wrong == 0);
        CHECK(reference_wrong == 0);
      }
}

TEST_CASE("two triangles of the square (0.5,0.5)-(4.5,4.5) cover exactly x, y in [0, 3] for both diagonals and windings") {
  const Point a{0.5, 0.5}, b{4.5, 0.5}, c{4.5, 4.5}, d{0.5, 4.5};
  const std::vector<std::vector<Point>> splits = {{a, b, c, a, c, d}, {a, b, d, b, c, d}};
  for (const auto& split : splits)
    for (const bool reversed : {false, true})
      for (const int tile : {8, 16}) {
        std::vector<Point> pts = split;
        if (reversed) {
          std::swap(pts[1], pts[2]);
          std::swap(pts[4], pts[5]);
        }
        raster::Renderer renderer({.threads = 1, .tile_size = tile});
        const std::vector<int> counts = test::render_pixel_triangles(renderer, 8, 8, pts);
        int wrong = 0;
        for (int y = 0; y < 8; ++y)
          for (int x = 0; x < 8; ++x) wrong += counts[y * 8 + x] != ((x <= 3 && y <= 3) ? 1 : 0);
        CAPTURE(reversed);
        CAPTURE(tile);
        CHECK(wrong == 0);
      }
}

TEST_CASE("random triangles cover exactly the pixel centres the reference top-left rule assigns them") {
  std::mt19937 rng(777);
  constexpr int kW = 24, kH = 20;
  // Half of the vertices on the half-pixel grid, so edges often run through centres and
  // edges are often horizontal or vertical; the rest anywhere on the 1/256 grid.
  std::uniform_int_distribution<int> half_x(-4, 2 * kW + 4), half_y(-4, 2 * kH + 4);
  std::uniform_int_distribution<int> fine_x(-256 * 2, 256 * (kW + 2)), fine_y(-256 * 2, 256 * (kH + 2));
  raster::Renderer renderer({.threads = 1, .tile_size = 8});
  int mismatched = 0, drawn = 0;
  for (int i = 0; i < 1500; ++i) {
    std::vector<Point> pts;
    for (int k = 0; k < 3; ++k) {
      if ((i + k) % 2 == 0) pts.push_back({half_x(rng) * 0.5, half_y(rng) * 0.5});
      else pts.push_back({fine_x(rng) / 256.0, fine_y(rng) / 256.0});
    }
    const std::vector<int> counts = test::render_pixel_triangles(renderer, kW, kH, pts);
    const std::vector<int> expected = test::reference_counts(kW, kH, pts);
    for (std::size_t p = 0; p < counts.size(); ++p) {
      mismatched += counts[p] != expected[p];
      drawn += counts[p];
    }
  }
  CHECK(mismatched == 0);
  CHECK(drawn > 1500 * 20);  // the triangles are not trivially empty
}

TEST_CASE("wide triangles in big tiles (rows walked only where the triangle may be) cover exactly the reference") {
  // raster_triangle narrows each row of quads to where every edge can be ≥ 0 once a
  // triangle spans a few quads of a tile; thin slivers, nearly horizontal and nearly
  // vertical edges, and vertices far outside the target (the guard band) probe its margin.
  std::mt19937 rng(4242);
  constexpr int kW = 150, kH = 110;
  std::uniform_real_distribution<double> in_x(-4.0, kW + 4.0), in_y(-4.0, kH + 4.0);
  std::uniform_real_distribution<double> far(-3000.0, 3000.0), near(-0.6, 0.6), unit(0.0, 1.0);
  std::vector<Point> pts;
  for (int i = 0; i < 240; ++i) {
    const Point a{in_x(rng), in_y(rng)};
    Point b{in_x(rng), in_y(rng)};
    Point c{in_x(rng), in_y(rng)};
    switch (i % 4) {
      case 0: break;  // anywhere
      case 1: {       // a sliver: c near the segment ab
        const double f = unit(rng);
        c = {a.x + f * (b.x - a.x) + near(rng), a.y + f * (b.y - a.y) + near(rng)};
        break;
      }
      case 2:  // nearly horizontal (or vertical) long edges
        if (i % 8 == 2) b = {a.x + far(rng), a.y + near(rng)};
        else b = {a.x + near(rng), a.y + far(rng)};
        break;
      case 3:  // two vertices far outside the target
        b = {far(rng), far(rng)};
        c = {far(rng), far(rng)};
        break;
    }
    pts.insert(pts.end(), {a, b, c});
  }
  // On the 1/256 grid, so that the float clip coordinates snap back to the reference's.
  for (Point& p : pts) p = {std::round(p.x * 256.0) / 256.0, std::round(p.y * 256.0) / 256.0};
  const std::vector<int> expected = test::reference_counts(kW, kH, pts);
  int drawn = 0;
  for (const int c : expected) drawn += c;
  REQUIRE(drawn > 240 * 200);  // most triangles span many quads
  for (const int tile : {16, 64}) {
    CAPTURE(tile);
    raster::Renderer renderer({.threads = 2, .tile_size = tile});
    const auto mismatched = [&](const std::vector<int>& counts) {
      int n = 0;
      for (std::size_t p = 0; p < counts.size(); ++p) n += counts[p] != expected[p];
      return n;
    };
    CHECK(mismatched(test::render_pixel_triangles(renderer, kW, kH, pts)) == 0);
    CHECK(mismatched(test::render_pixel_triangles<test::CountPacketShader>(renderer, kW, kH, pts)) == 0);
  }
}

TEST_CASE("zero-area triangles draw nothing") {
  const std::vector<std::vector<Point>> cases = {
      {{3, 3}, {3, 3}, {3, 3}},                      // one point
      {{0.5, 0.5}, {8.5, 0.5}, {0.5, 0.5}},          // two coincident, along a row of centres
      {{0.5, 0.5}, {4.5, 0.5}, {8.5, 0.5}},          // horizontal through centres
      {{2.5, 0.5}, {2.5, 9.5}, {2.5, 4.5}},          // vertical through centres
      {{0.5, 0.5}, {8.5, 8.5}, {4.5, 4.5}},          // diagonal through centres
      {{1, 1}, {9, 5}, {5, 3}},                      // collinear, between centres
      {{1.25, 1.25}, {9.25, 9.25}, {5.25, 5.2501}},  // collinear once snapped to 1/256
      {{-20, 4.5}, {40, 4.5}, {10, 4.5}},            // horizontal across the whole target
  };
  raster::Renderer renderer({.threads = 1, .tile_size = 8});
  for (std::size_t i = 0; i < cases.size(); ++i)
    for (const bool reversed : {false, true}) {
      std::vector<Point> pts = cases[i];
      if (reversed) std::swap(pts[1], pts[2]);
      const std::vector<int> counts = test::render_pixel_triangles(renderer, 16, 16, pts);
      CAPTURE(i);
      CAPTURE(reversed);
      CHECK(std::count(counts.begin(), counts.end(), 0) == 16 * 16);
    }
}
