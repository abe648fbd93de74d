// The geometry fast paths (vertex projection, triangle setup and binning, index
// validation) against their plain definitions, over random and adversarial inputs:
//  - project_vertices() (four vertices at a time, branch-free, per instruction set)
//    against classify() and project() one vertex at a time;
//  - setup_triangle() (now culling on the area first, in 32-bit bounds) against the
//    transcription of the rules it replaced (reference_setup below);
//  - assemble_triangles() (inline setup, single-tile binning, counting while setting up)
//    against the assembly it replaced: reference_setup() for every triangle, then
//    (triangle, tile) pairs stably sorted by tile;
//  - validate_indices() (a max-reduction first) reports the first bad index.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "softpbr/raster/detail/bin.h"
#include "softpbr/raster/detail/clip.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/detail/setup.h"
#include "softpbr/simd/simd.h"
#include "softpbr/raster/detail/vertex.h"

namespace raster = softpbr::raster;
namespace simd = softpbr::simd;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// --- The plain definitions the fast paths must match. ---

std::int64_t reference_orient(std::int64_t ax, std::int64_t ay, std::int64_t bx, std::int64_t by, std::int64_t cx,
                              std::int64_t cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

// setup_triangle() as it was before the fast path: 64-bit throughout, index permutation.
bool reference_setup(const raster::ScreenVertex v[3], const std::uint32_t ids[3], raster::Viewport viewport,
                     const raster::DrawState& state, raster::Triangle& out) {
  const std::int64_t x[3] = {v[0].x, v[1].x, v[2].x};
  const std::int64_t y[3] = {v[0].y, v[1].y, v[2].y};
  const std::int64_t area = reference_orient(x[0], y[0], x[1], y[1], x[2], y[2]);
  if (area == 0) return false;
  const bool clockwise = area > 0;
  const bool front = (state.front_face == raster::FrontFace::Clockwise) == clockwise;
  if ((state.cull == raster::Cull::Back && !front) || (state.cull == raster::Cull::Front && front)) return false;
  int order[3] = {0, 1, 2};
  if (!clockwise) std::swap(order[1], order[2]);
  std::int64_t vx[3], vy[3];
  for (int i = 0; i < 3; ++i) {
    vx[i] = x[order[i]];
    vy[i] = y[order[i]];
  }
  const std::int64_t s = raster::kSubpixelScale, half = s / 2;
  const std::int64_t min_px = std::max<std::int64_t>(0, (std::min({vx[0], vx[1], vx[2]}) - half + s - 1) >> 8);
  const std::int64_t min_py = std::max<std::int64_t>(0, (std::min({vy[0], vy[1], vy[2]}) - half + s - 1) >> 8);
  const std::int64_t max_px = std::min<std::int64_t>(viewport.width - 1, (std::max({vx[0], vx[1], vx[2]}) - half) >> 8);
  const std::int64_t max_py = std::min<std::int64_t>(viewport.height - 1, (std::max({vy[0], vy[1], vy[2]}) - half) >> 8);
  if (min_px > max_px || min_py > max_py) return false;
  for (int i = 0; i < 3; ++i) {
    const int ia = (i + 1) % 3, ib = (i + 2) % 3;
    const std::int64_t xa = vx[ia], ya = vy[ia], xb = vx[ib], yb = vy[ib];
    const bool top = ya == yb && xb > xa;
    const bool left = yb < ya;
    out.a[i] = static_cast<std::int32_t>(ya - yb);
    out.b[i] = static_cast<std::int32_t>(xb - xa);
    out.bias[i] = (top || left) ? 0 : 1;
    out.c[i] = (yb - ya) * xa - (xb - xa) * ya - out.bias[i];
  }
  out.min_x = static_cast<std::int32_t>(min_px);
  out.min_y = static_cast<std::int32_t>(min_py);
  out.max_x = static_cast<std::int32_t>(max_px);
  out.max_y = static_cast<std::int32_t>(max_py);
  float z[3];
  for (int i = 0; i < 3; ++i) {
    z[i] = v[order[i]].z;
    out.inv_w[i] = v[order[i]].inv_w;
    out.vertex[i] = ids[order[i]];
  }
  out.z0 = z[0];
  out.dz1 = z[1] - z[0];
  out.dz2 = z[2] - z[0];
  out.inv_area = 1.0f / static_cast<float>(area > 0 ? area : -area);
  out.front_facing = front;
  return true;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Field by field (the struct has padding), floats by their bits.
bool same_triangle(const raster::Triangle& p, const raster::Triangle& q) {
  for (int i = 0; i < 3; ++i)
    if (p.a[i] != q.a[i] || p.b[i] != q.b[i] || p.c[i] != q.c[i] || p.bias[i] != q.bias[i] ||
        !same_bits(p.inv_w[i], q.inv_w[i]) || p.vertex[i] != q.vertex[i])
      return false;
  return p.min_x == q.min_x && p.min_y == q.min_y && p.max_x == q.max_x && p.max_y == q.max_y &&
         same_bits(p.z0, q.z0) && same_bits(p.dz1, q.dz1) && same_bits(p.dz2, q.dz2) &&
         same_bits(p.inv_area, q.inv_area) && p.front_facing == q.front_facing;
}

// --- Inputs. ---

// Clip-space positions: random ones at many scales, and the adversarial cases.
std::vector<glm::vec4> test_positions(raster::Viewport vp, std::mt19937& rng) {
  std::vector<glm::vec4> p;
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> exponent(-40.0f, 40.0f);
  auto scaled = [&] { return unit(rng) * std::exp2(exponent(rng)); };
  const float specials[] = {0.0f, -0.0f, 1.0f, -1.0f, kInf, -kInf, kNaN, raster::kMinClipW,
                            std::nextafter(raster::kMinClipW, 0.0f), 1e-30f, 1e30f, 3e38f,
                            std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::max()};
  for (int i = 0; i < 3000; ++i) {
    switch (i % 6) {
      case 0: p.push_back({unit(rng), unit(rng), unit(rng), 1.0f}); break;  // in view
      case 1: {  // in view at any depth scale
        const float w = std::exp2(exponent(rng) * 0.5f);
        p.push_back({unit(rng) * w, unit(rng) * w, unit(rng) * w, w});
        break;
      }
      case 2: p.push_back({scaled(), scaled(), scaled(), scaled()}); break;  // anything finite
      case 3: {  // pixel centres and pixel edges exactly: ties of the rounding
        const float px = static_cast<float>(static_cast<int>(rng() % (2 * vp.width)) - vp.width / 2) * 0.5f;
        const float py = static_cast<float>(static_cast<int>(rng() % (2 * vp.height)) - vp.height / 2) * 0.5f;
        const float half = std::ldexp(1.0f, -9 - static_cast<int>(rng() % 3));  // half a subpixel and less
        p.push_back({(px + half) * 2.0f / vp.width - 1.0f, 1.0f - (py + half) * 2.0f / vp.height, 0.0f, 1.0f});
        break;
      }
      case 4: {  // near the guard band: pixel ±32768 ± a little, at w = 1 and w = 2
        const float w = (rng() % 2) ? 1.0f : 2.0f;
        const float g = raster::kGuardBand * (1.0f + unit(rng) * 1e-4f) * ((rng() % 2) ? 1.0f : -1.0f);
        p.push_back({(2.0f * g / vp.width - 1.0f) * w, (1.0f - 2.0f * g / vp.height) * w, unit(rng) * w, w});
        break;
      }
      default: {  // special values in random components
        glm::vec4 v{unit(rng), unit(rng), unit(rng), 1.0f};
        v[static_cast<int>(rng() % 4)] = specials[rng() % std::size(specials)];
        if (rng() % 2) v[static_cast<int>(rng() % 4)] = specials[rng() % std::size(specials)];
        p.push_back(v);
      }
    }
  }
  return p;
}

// A screen vertex as the vertex stage makes them: anywhere in the clamp range, often near
// one spot so triangles are small, often on exact pixel centres and edges.
raster::ScreenVertex random_screen(std::mt19937& rng, raster::Viewport vp, int cx, int cy, int spread) {
  const std::int32_t limit = raster::kGuardBand * 256;
  raster::ScreenVertex v{};
  switch (rng() % 4) {
    case 0:
      v.x = static_cast<std::int32_t>(rng() % (2u * limit + 1)) - limit;
      v.y = static_cast<std::int32_t>(rng() % (2u * limit + 1)) - limit;
      break;
    case 1:  // on pixel centres or pixel edges
      v.x = cx + static_cast<std::int32_t>(rng() % 9 - 4) * 128;
      v.y = cy + static_cast<std::int32_t>(rng() % 9 - 4) * 128;
      break;
    default:
      v.x = cx + static_cast<std::int32_t>(rng() % (2u * spread + 1)) - spread;
      v.y = cy + static_cast<std::int32_t>(rng() % (2u * spread + 1)) - spread;
  }
  v.x = std::clamp(v.x, -limit, limit);
  v.y = std::clamp(v.y, -limit, limit);
  (void)vp;
  v.z = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
  v.inv_w = std::uniform_real_distribution<float>(0.01f, 100.0f)(rng);
  return v;
}

std::vector<raster::DrawState> all_cull_states() {
  std::vector<raster::DrawState> states;
  for (const auto cull : {raster::Cull::None, raster::Cull::Back, raster::Cull::Front})
    for (const auto face : {raster::FrontFace::CounterClockwise, raster::FrontFace::Clockwise}) {
      raster::DrawState s;
      s.cull = cull;
      s.front_face = face;
      states.push_back(s);
    }
  return states;
}

std::vector<simd::Isa> runnable_isas() {
  std::vector<simd::Isa> isas = {simd::Isa::Baseline};
  if (simd::cpu_isa() != simd::Isa::Baseline) isas.push_back(simd::Isa::Avx2);
  if (simd::cpu_isa() == simd::Isa::Avx512) isas.push_back(simd::Isa::Avx512);
  return isas;
}

}  // namespace

TEST_CASE("project_vertices gives classify() and project() bits for every vertex, on every instruction set") {
  const raster::Viewport viewports[] = {{1920, 1080}, {333, 217}, {1, 1}, {16384, 16384}};
  std::mt19937 rng(6);
  int differences = 0;
  for (const raster::Viewport vp : viewports) {
    const std::vector<glm::vec4> positions = test_positions(vp, rng);
    // Ranges of every length mod 4 and at every offset, so the padded tail runs too.
    const std::pair<std::size_t, std::size_t> ranges[] = {{0, positions.size()}, {1, 8}, {3, 5}, {7, 1030}, {2, 2}};
    for (const simd::Isa isa : runnable_isas()) {
      for (const auto& range : ranges) {
        const std::size_t first = range.first, last = range.second;  // (CAPTURE takes no structured binding)
        CAPTURE(vp.width);
        CAPTURE(static_cast<int>(isa));
        CAPTURE(first);
        raster::TransformedVertices v;
        v.position = positions;
        v.outcode.assign(positions.size(), 0xffff);
        v.screen.assign(positions.size(), raster::ScreenVertex{-1, -1, -1.0f, -1.0f});
        raster::project_vertices(v, first, last, vp, isa);
        for (std::size_t i = 0; i < positions.size(); ++i) {
          if (i < first || i >= last) {  // untouched outside the range
            if (v.outcode[i] != 0xffff || v.screen[i].x != -1) ++differences;
            continue;
          }
          const std::uint16_t code = raster::classify(positions[i], vp);
          const bool projectable = (code & (raster::kNeedsClipping | raster::kNotFinite)) == 0;
          const raster::ScreenVertex s = projectable ? raster::project(positions[i], vp) : raster::ScreenVertex{};
          if (v.outcode[i] != code || !same_bits(v.screen[i], s)) {
            if (++differences < 10)
              MESSAGE("vertex (", positions[i].x, ", ", positions[i].y, ", ", positions[i].z, ", ", positions[i].w,
                      "): outcode ", v.outcode[i], " vs ", code, ", x ", v.screen[i].x, " vs ", s.x, ", y ",
                      v.screen[i].y, " vs ", s.y);
          }
        }
      }
    }
  }
  CHECK(differences == 0);
}

TEST_CASE("setup_triangle equals the plain 64-bit setup for random, tiny, degenerate and edge-aligned triangles") {
  const raster::Viewport viewports[] = {{1920, 1080}, {333, 217}, {1, 1}};
  std::mt19937 rng(66);
  int differences = 0, drawn = 0, refused = 0;
  for (const raster::Viewport vp : viewports)
    for (const raster::DrawState& state : all_cull_states())
      for (int k = 0; k < 20000; ++k) {
        const int cx = static_cast<int>(rng() % (vp.width * 256u + 512)) - 256;
        const int cy = static_cast<int>(rng() % (vp.height * 256u + 512)) - 256;
        const int spread = 1 << (rng() % 14);
        raster::ScreenVertex v[3];
        for (auto& s : v) s = random_screen(rng, vp, cx, cy, spread);
        if (k % 7 == 0) v[2] = v[static_cast<int>(rng() % 2)];                 // two vertices equal
        if (k % 11 == 0) v[2].y = v[1].y;                                       // a horizontal edge
        if (k % 13 == 0) v[2].x = v[0].x;                                       // a vertical edge
        if (k % 17 == 0) v[2] = {2 * v[1].x - v[0].x, 2 * v[1].y - v[0].y, 0, 1};  // collinear
        const std::uint32_t ids[3] = {static_cast<std::uint32_t>(rng()), static_cast<std::uint32_t>(rng()),
                                      static_cast<std::uint32_t>(rng())};
        raster::Triangle fast{}, plain{};
        const bool f = raster::setup_triangle(v, ids, vp, state, fast);
        const bool p = reference_setup(v, ids, vp, state, plain);
        if (f != p || (f && !same_triangle(fast, plain))) ++differences;
        (p ? drawn : refused)++;
      }
  CHECK(differences == 0);
  CHECK(drawn > 10000);  // both outcomes well covered
  CHECK(refused > 10000);
}

namespace {

// assemble_triangles() as it was: the same chunks, reference_setup() for every triangle,
// then (triangle, tile) pairs stably sorted by tile.
std::vector<raster::TriangleChunk> reference_assembly(std::span<const std::uint32_t> indices,
                                                      const raster::TileGrid& grid,
                                                      const raster::DrawGeometry& geometry) {
  const std::size_t triangles = indices.size() / 3;
  const std::size_t chunk_count = (triangles + 1023) / 1024;  // bin.cpp's kTrianglesPerChunk
  const std::size_t per_chunk = (triangles + chunk_count - 1) / chunk_count;
  const raster::TransformedVertices& verts = geometry.vertices;
  const int nvar = verts.varyings;
  const raster::Viewport vp{grid.width, grid.height};
  std::vector<raster::TriangleChunk> chunks(chunk_count);
  for (std::size_t c = 0; c < chunk_count; ++c) {
    raster::TriangleChunk& chunk = chunks[c];
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (tile, triangle)
    auto add = [&](const raster::ScreenVertex s[3], const std::uint32_t ids[3]) {
      raster::Triangle t;
      if (!reference_setup(s, ids, vp, geometry.state, t)) return;
      const auto index = static_cast<std::uint32_t>(chunk.triangles.size());
      chunk.triangles.push_back(t);
      for (int ty = t.min_y / grid.tile_size; ty <= t.max_y / grid.tile_size; ++ty)
        for (int tx = t.min_x / grid.tile_size; tx <= t.max_x / grid.tile_size; ++tx)
          pairs.emplace_back(static_cast<std::uint32_t>(ty * grid.columns + tx), index);
    };
    for (std::size_t tri = c * per_chunk; tri < std::min(triangles, (c + 1) * per_chunk); ++tri) {
      const std::uint32_t ids[3] = {indices[3 * tri], indices[3 * tri + 1], indices[3 * tri + 2]};
      const std::uint16_t oc[3] = {verts.outcode[ids[0]], verts.outcode[ids[1]], verts.outcode[ids[2]]};
      const std::uint16_t any = oc[0] | oc[1] | oc[2];
      if ((oc[0] & oc[1] & oc[2] & raster::kOutsideFrustum) != 0 || (any & raster::kNotFinite) != 0) continue;
      if ((any & raster::kNeedsClipping) == 0) {
        const raster::ScreenVertex s[3] = {verts.screen[ids[0]], verts.screen[ids[1]], verts.screen[ids[2]]};
        add(s, ids);
        continue;
      }
      const glm::vec4 clip[3] = {verts.position[ids[0]], verts.position[ids[1]], verts.position[ids[2]]};
      const float* const var[3] = {verts.varyings_of(ids[0]), verts.varyings_of(ids[1]), verts.varyings_of(ids[2])};
      raster::ClipVertex polygon[raster::kMaxClipVertices];
      int n = 0;
      const raster::ClipResult r = raster::clip_triangle(clip, var, nvar, vp, polygon, n);
      if (r == raster::ClipResult::Inside) {
        const raster::ScreenVertex s[3] = {raster::project(clip[0], vp), raster::project(clip[1], vp),
                                           raster::project(clip[2], vp)};
        add(s, ids);
      } else if (r == raster::ClipResult::Clipped) {
        const auto base = static_cast<std::uint32_t>(verts.size() + chunk.clip_varyings.size() / std::max(nvar, 1));
        raster::ScreenVertex s[raster::kMaxClipVertices];
        for (int v = 0; v < n; ++v) {
          s[v] = raster::project(polygon[v].position, vp);
          chunk.clip_varyings.insert(chunk.clip_varyings.end(), polygon[v].varyings, polygon[v].varyings + nvar);
        }
        if (nvar == 0) chunk.clip_varyings.resize(chunk.clip_varyings.size() + n);
        for (int v = 1; v + 1 < n; ++v) {
          const std::uint32_t fan_ids[3] = {base, base + static_cast<std::uint32_t>(v),
                                            base + static_cast<std::uint32_t>(v + 1)};
          const raster::ScreenVertex fan[3] = {s[0], s[v], s[v + 1]};
          add(fan, fan_ids);
        }
      }
    }
    std::stable_sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    chunk.offsets.assign(grid.count() + 1, 0);
    for (const auto& [tile, index] : pairs) {
      ++chunk.offsets[tile + 1];
      chunk.list.push_back(index);
    }
    for (std::size_t t = 0; t < grid.count(); ++t) chunk.offsets[t + 1] += chunk.offsets[t];
  }
  return chunks;
}

}  // namespace

TEST_CASE("assemble_triangles bins the triangles of the plain assembly, each tile in submission order") {
  struct Case {
    int width, height, tile;
    int threads;
  };
  const Case cases[] = {{1920, 1080, 64, 1}, {333, 217, 24, 2}, {200, 120, 8, 2}, {64, 64, 64, 1}, {97, 61, 4096, 2}};
  std::mt19937 rng(666);
  for (const Case& c : cases) {
    CAPTURE(c.width);
    CAPTURE(c.tile);
    const raster::Viewport vp{c.width, c.height};
    raster::ThreadPool pool(static_cast<unsigned>(c.threads));
    const raster::TileGrid grid(c.width, c.height, c.tile);
    for (const raster::DrawState& state : all_cull_states()) {
      raster::DrawGeometry geometry;
      geometry.state = state;
      // Vertices: mostly in view (small triangles around a spot, as on a tessellated
      // mesh), some needing clipping, some non-finite; one varying each.
      std::vector<glm::vec4> positions = test_positions(vp, rng);
      std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
      for (int i = 0; i < 3000; ++i) {
        const float x = unit(rng), y = unit(rng), d = 0.02f * std::exp2(unit(rng) * 4.0f);
        for (int k = 0; k < 3; ++k) positions.push_back({x + unit(rng) * d, y + unit(rng) * d, unit(rng) * 0.5f, 1.0f});
      }
      raster::TransformedVertices& v = geometry.vertices;
      v.varyings = 1;
      v.position = positions;
      v.values.resize(positions.size());
      for (std::size_t i = 0; i < positions.size(); ++i) v.values[i] = static_cast<float>(i);
      v.outcode.resize(positions.size());
      v.screen.resize(positions.size());
      raster::project_vertices(v, 0, positions.size(), vp);
      // Triangles: the small ones in order, then random triples of any vertex.
      std::vector<std::uint32_t> indices;
      const auto small_start = static_cast<std::uint32_t>(positions.size() - 9000);
      for (std::uint32_t i = 0; i < 9000; ++i) indices.push_back(small_start + i);
      for (int i = 0; i < 3 * 2500; ++i) indices.push_back(static_cast<std::uint32_t>(rng() % positions.size()));
      raster::validate_indices(indices, positions.size());

      raster::assemble_triangles(pool, indices, grid, geometry);
      const std::vector<raster::TriangleChunk> expected = reference_assembly(indices, grid, geometry);
      REQUIRE(geometry.chunks.size() == expected.size());
      int differences = 0;
      std::size_t triangles = 0, entries = 0;
      for (std::size_t k = 0; k < expected.size(); ++k) {
        const raster::TriangleChunk& got = geometry.chunks[k];
        const raster::TriangleChunk& want = expected[k];
        triangles += want.triangles.size();
        entries += want.list.size();
        if (got.triangles.size() != want.triangles.size() || got.clip_varyings != want.clip_varyings) {
          ++differences;
          continue;
        }
        for (std::size_t i = 0; i < want.triangles.size(); ++i)
          differences += !same_triangle(got.triangles[i], want.triangles[i]);
        for (std::size_t t = 0; t < grid.count(); ++t) {
          const auto a = got.tile(t), b = want.tile(t);
          differences += !std::equal(a.begin(), a.end(), b.begin(), b.end());
        }
      }
      CHECK(differences == 0);
      CHECK(triangles > 1000);  // the comparison saw real work
      CHECK(entries >= triangles);
    }
  }
}

TEST_CASE("validate_indices names the first index past the vertices, whatever the larger ones after it") {
  std::vector<std::uint32_t> indices(3000, 5);
  raster::validate_indices(indices, 6);  // all good
  CHECK_THROWS_AS(raster::validate_indices(indices, 5), std::out_of_range);
  indices[1234] = 9;
  indices[2000] = 4000000000u;
  CHECK_THROWS_WITH_AS(raster::validate_indices(indices, 6),
                       "draw: index 9 at position 1234 is past the 6 vertices", std::out_of_range);
  CHECK_THROWS_WITH_AS(raster::validate_indices(std::vector<std::uint32_t>{0, 1}, 6),
                       "draw: 2 indices is not a whole number of triangles", std::invalid_argument);
  raster::validate_indices({}, 0);  // an empty draw is valid
}
