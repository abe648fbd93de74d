// Primitive assembly, clipping, setup and binning (see bin.h).
#include "softpbr/raster/detail/bin.h"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

#include "softpbr/check.h"
#include "softpbr/raster/detail/clip.h"
#include "softpbr/simd/dispatch.h"

// detail::{baseline, avx2, avx512}::largest_of().
#define SOFTPBR_TARGET_FILE "bin-inl.h"
#include "softpbr/simd/foreach_target.h"

namespace softpbr::raster {

TileGrid::TileGrid(int target_width, int target_height, int tile)
    : tile_size(tile),
      width(target_width),
      height(target_height),
      columns((target_width + tile - 1) / tile),
      rows((target_height + tile - 1) / tile) {}

TileRect TileGrid::rect(std::size_t t) const {
  const int tx = static_cast<int>(t % static_cast<std::size_t>(columns));
  const int ty = static_cast<int>(t / static_cast<std::size_t>(columns));
  return {tx * tile_size, ty * tile_size, std::min(width, (tx + 1) * tile_size),
          std::min(height, (ty + 1) * tile_size)};
}

void DrawGeometry::recycle() {
  // The vertex arrays keep their size: the next draw's vertex stage resizes them and
  // writes every element it keeps, and a resize to the same size or smaller skips the
  // value-initialisation (zeroing) that clear() then resize() paid on every draw.
  for (TriangleChunk& c : chunks) {
    c.triangles.clear();
    c.clip_varyings.clear();
    c.offsets.clear();
    c.list.clear();
  }
}

std::size_t DrawGeometry::bytes() const {
  auto held = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  std::size_t n = held(vertices.position) + held(vertices.values) + held(vertices.outcode) + held(vertices.screen) +
                  chunks.capacity() * sizeof(TriangleChunk);
  for (const TriangleChunk& c : chunks)
    n += held(c.triangles) + held(c.clip_varyings) + held(c.offsets) + held(c.list) + held(c.scratch);
  return n;
}

namespace detail {
namespace {
std::uint32_t largest_index(std::span<const std::uint32_t> indices) {
  return SOFTPBR_DISPATCH(simd::cpu_isa(), largest_of)(indices.data(), indices.size());
}
}  // namespace
}  // namespace detail

void validate_indices(std::span<const std::uint32_t> indices, std::size_t vertex_count) {
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("draw: " + std::to_string(indices.size()) +
                                " indices is not a whole number of triangles");
  if (indices.size() / 3 > std::numeric_limits<std::uint32_t>::max() / 4)
    throw std::length_error("draw: more than 2^30 triangles in one draw");
  // The largest index, without a branch per index (the loop vectorizes); only a draw
  // with a bad index looks for the first one, for the message.
  if (indices.empty() || detail::largest_index(indices) < vertex_count) return;
  for (std::size_t i = 0; i < indices.size(); ++i)
    if (indices[i] >= vertex_count)
      throw std::out_of_range("draw: index " + std::to_string(indices[i]) + " at position " + std::to_string(i) +
                              " is past the " + std::to_string(vertex_count) + " vertices");
}

namespace {

// Triangles per assembly chunk, and a cap on chunks × tiles so the per-chunk tile offsets
// stay small even for huge targets cut into tiny tiles.
constexpr std::size_t kTrianglesPerChunk = 1024;
constexpr std::size_t kMaxOffsetEntries = std::size_t{1} << 23;

// Tile column or row of a pixel coordinate (≥ 0): a shift for the usual power-of-two
// tile sizes, a division otherwise.
struct TileIndexer {
  int size;
  int shift;  // log2(size), or −1 when size is not a power of two

  explicit TileIndexer(int tile_size)
      : size(tile_size), shift(std::has_single_bit(static_cast<unsigned>(tile_size)) ? std::countr_zero(static_cast<unsigned>(tile_size)) : -1) {}
  int operator()(int pixel) const { return shift >= 0 ? pixel >> shift : pixel / size; }
};

// Marks a triangle binned to more than one tile in TriangleChunk::scratch.
constexpr std::uint32_t kSeveralTiles = 0xffffffffu;

void assemble_chunk(const DrawGeometry& geometry, std::span<const std::uint32_t> indices, std::size_t first,
                    std::size_t last, const TileGrid& grid, TriangleChunk& chunk) {
  const TransformedVertices& verts = geometry.vertices;
  const int nvar = verts.varyings;
  const Viewport viewport{grid.width, grid.height, grid.sample_reach};
  const FaceFilter faces(geometry.state);
  const TileIndexer tile_of(grid.tile_size);
  const std::size_t tiles = grid.count();
  // Binning is a counting sort by tile, stable so each tile keeps submission order:
  // offsets[t + 1] counts tile t's triangles while they are set up; scratch holds each
  // triangle's tile (the common case: its bounding box lies in one tile) or
  // kSeveralTiles, whose tiles the scatter below reads again from its bounding box.
  chunk.offsets.assign(tiles + 1, 0);
  std::uint32_t* const count = chunk.offsets.data() + 1;
  std::vector<std::uint32_t>& single_tile = chunk.scratch;
  single_tile.resize(last - first);  // grows when clipping makes more triangles
  std::size_t entries = 0;

  // Counts triangle t (the last one in `chunk`) for its tiles.
  auto bin = [&](const Triangle& t) {
    const int tx0 = tile_of(t.min_x), tx1 = tile_of(t.max_x);
    const int ty0 = tile_of(t.min_y), ty1 = tile_of(t.max_y);
    const std::size_t i = chunk.triangles.size() - 1;
    if (i >= single_tile.size()) single_tile.resize(std::max<std::size_t>(2 * single_tile.size(), 64));
    if (tx0 == tx1 && ty0 == ty1) {
      const auto tile = static_cast<std::uint32_t>(ty0 * grid.columns + tx0);
      single_tile[i] = tile;
      ++count[tile];
      ++entries;
      return;
    }
    single_tile[i] = kSeveralTiles;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) ++count[ty * grid.columns + tx];
    entries += static_cast<std::size_t>(ty1 - ty0 + 1) * static_cast<std::size_t>(tx1 - tx0 + 1);
  };
  // The general path, for vertices that were clipped or projected here.
  auto add = [&](const ScreenVertex screen[3], const std::uint32_t ids[3]) {
    Triangle t;
    if (!setup_triangle(screen, ids, viewport, geometry.state, t)) return;
    chunk.triangles.push_back(t);
    bin(t);
  };

  ClipVertex polygon[kMaxClipVertices];
  for (std::size_t tri = first; tri < last; ++tri) {
    const std::uint32_t ids[3] = {indices[3 * tri], indices[3 * tri + 1], indices[3 * tri + 2]};
    const std::uint16_t oc[3] = {verts.outcode[ids[0]], verts.outcode[ids[1]], verts.outcode[ids[2]]};
    const std::uint16_t any = oc[0] | oc[1] | oc[2];
    if ((oc[0] & oc[1] & oc[2] & kOutsideFrustum) != 0 || (any & kNotFinite) != 0) continue;  // culled
    if ((any & kNeedsClipping) == 0) {
      // The common case: no plane to clip against, the vertices projected by the vertex
      // stage. setup_triangle() inline, culling on the area first (half of a closed
      // mesh faces away).
      const ScreenVertex& v0 = verts.screen[ids[0]];
      const ScreenVertex& v1 = verts.screen[ids[1]];
      const ScreenVertex& v2 = verts.screen[ids[2]];
      const std::int64_t area = screen_area(v0, v1, v2);
      if (!faces.keeps(area)) continue;
      Triangle t;
      if (!setup_kept_triangle(v0, v1, v2, ids[0], ids[1], ids[2], area, faces.front(area), viewport,
                               t))
        continue;
      chunk.triangles.push_back(t);
      bin(t);
      continue;
    }
    const glm::vec4 clip[3] = {verts.position[ids[0]], verts.position[ids[1]], verts.position[ids[2]]};
    const float* const var[3] = {verts.varyings_of(ids[0]), verts.varyings_of(ids[1]), verts.varyings_of(ids[2])};
    int n = 0;
    switch (clip_triangle(clip, var, nvar, viewport, polygon, n)) {
      case ClipResult::Culled: break;
      case ClipResult::Inside: {  // outside the frustum on some side, but no plane to clip
        const ScreenVertex screen[3] = {project(clip[0], viewport), project(clip[1], viewport),
                                        project(clip[2], viewport)};
        add(screen, ids);
        break;
      }
      case ClipResult::Clipped: {
        // New vertices get ids past the vertex buffer; their varyings live in the chunk.
        const auto base = static_cast<std::uint32_t>(verts.size() + chunk.clip_varyings.size() / std::max(nvar, 1));
        std::uint32_t poly_ids[kMaxClipVertices];
        ScreenVertex poly_screen[kMaxClipVertices];
        for (int v = 0; v < n; ++v) {
          poly_ids[v] = base + static_cast<std::uint32_t>(v);
          poly_screen[v] = project(polygon[v].position, viewport);
          chunk.clip_varyings.insert(chunk.clip_varyings.end(), polygon[v].varyings, polygon[v].varyings + nvar);
        }
        if (nvar == 0) chunk.clip_varyings.resize(chunk.clip_varyings.size() + n);  // keep ids unique
        for (int v = 1; v + 1 < n; ++v) {  // a fan: the polygon is convex
          const std::uint32_t fan_ids[3] = {poly_ids[0], poly_ids[v], poly_ids[v + 1]};
          const ScreenVertex fan[3] = {poly_screen[0], poly_screen[v], poly_screen[v + 1]};
          add(fan, fan_ids);
        }
        break;
      }
    }
  }

  // The prefix sum makes offsets[t + 1] tile t's end; the scatter moves each tile's start
  // up to where the next tile starts, and a final shift restores the starts.
  for (std::size_t t = 0; t < tiles; ++t) chunk.offsets[t + 1] += chunk.offsets[t];
  chunk.list.resize(entries);
  std::uint32_t* const list = chunk.list.data();
  std::uint32_t* const start = chunk.offsets.data();
  const auto n = static_cast<std::uint32_t>(chunk.triangles.size());
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t tile = single_tile[i];
    if (tile != kSeveralTiles) {
      list[start[tile]++] = i;
      continue;
    }
    const Triangle& t = chunk.triangles[i];
    const int tx0 = tile_of(t.min_x), tx1 = tile_of(t.max_x);
    const int ty0 = tile_of(t.min_y), ty1 = tile_of(t.max_y);
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) list[start[ty * grid.columns + tx]++] = i;
  }
  SOFTPBR_DCHECK(chunk.offsets[tiles] == entries);  // every tile's list filled to its end
  for (std::size_t t = tiles; t > 0; --t) chunk.offsets[t] = chunk.offsets[t - 1];
  chunk.offsets[0] = 0;
}

}  // namespace

void assemble_triangles(ThreadPool& pool, std::span<const std::uint32_t> indices, const TileGrid& grid,
                        DrawGeometry& geometry) {
  const std::size_t triangles = indices.size() / 3;
  if (triangles == 0) return;
  std::size_t chunks = (triangles + kTrianglesPerChunk - 1) / kTrianglesPerChunk;
  chunks = std::max<std::size_t>(1, std::min(chunks, kMaxOffsetEntries / (grid.count() + 1)));
  const std::size_t per_chunk = (triangles + chunks - 1) / chunks;
  geometry.chunks.resize(chunks);  // recycled chunks keep their memory
  pool.parallel_for(chunks, [&](std::size_t c) {
    const std::size_t first = c * per_chunk;
    const std::size_t last = std::min(triangles, first + per_chunk);
    if (first < last) assemble_chunk(geometry, indices, first, last, grid, geometry.chunks[c]);
  });
}

}  // namespace softpbr::raster
