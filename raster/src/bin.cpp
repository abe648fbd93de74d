// Primitive assembly, clipping, setup and binning (see bin.h).
#include "softpbr/raster/bin.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "softpbr/raster/clip.h"

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
  vertices.position.clear();
  vertices.values.clear();
  vertices.outcode.clear();
  vertices.screen.clear();
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

void validate_indices(std::span<const std::uint32_t> indices, std::size_t vertex_count) {
  if (indices.size() % 3 != 0)
    throw std::invalid_argument("draw: " + std::to_string(indices.size()) +
                                " indices is not a whole number of triangles");
  if (indices.size() / 3 > std::numeric_limits<std::uint32_t>::max() / 4)
    throw std::length_error("draw: more than 2^30 triangles in one draw");
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

void assemble_chunk(const DrawGeometry& geometry, std::span<const std::uint32_t> indices, std::size_t first,
                    std::size_t last, const TileGrid& grid, TriangleChunk& chunk) {
  const TransformedVertices& verts = geometry.vertices;
  const int nvar = verts.varyings;
  const Viewport viewport{grid.width, grid.height};
  // (triangle, tile) pairs, interleaved, in submission order.
  std::vector<std::uint32_t>& pairs = chunk.scratch;
  pairs.clear();

  auto add = [&](const ScreenVertex screen[3], const std::uint32_t ids[3]) {
    Triangle t;
    if (!setup_triangle(screen, ids, viewport, geometry.state, t)) return;
    const auto index = static_cast<std::uint32_t>(chunk.triangles.size());
    chunk.triangles.push_back(t);
    const int tx0 = t.min_x / grid.tile_size, tx1 = t.max_x / grid.tile_size;
    const int ty0 = t.min_y / grid.tile_size, ty1 = t.max_y / grid.tile_size;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        pairs.push_back(index);
        pairs.push_back(static_cast<std::uint32_t>(ty * grid.columns + tx));
      }
  };

  ClipVertex polygon[kMaxClipVertices];
  for (std::size_t tri = first; tri < last; ++tri) {
    const std::uint32_t ids[3] = {indices[3 * tri], indices[3 * tri + 1], indices[3 * tri + 2]};
    const std::uint16_t oc[3] = {verts.outcode[ids[0]], verts.outcode[ids[1]], verts.outcode[ids[2]]};
    const std::uint16_t any = oc[0] | oc[1] | oc[2];
    if ((oc[0] & oc[1] & oc[2] & kOutsideFrustum) != 0 || (any & kNotFinite) != 0) continue;  // culled
    if ((any & kNeedsClipping) == 0) {  // the common case: no plane to clip against
      const ScreenVertex screen[3] = {verts.screen[ids[0]], verts.screen[ids[1]], verts.screen[ids[2]]};
      add(screen, ids);
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

  // Counting sort of the pairs by tile, stable, so each tile keeps submission order.
  // offsets[t + 1] first counts tile t's pairs, then becomes its end after the prefix sum;
  // the scatter then moves each tile's start up to where the next tile starts, and a
  // final shift restores the starts.
  const std::size_t tiles = grid.count();
  chunk.offsets.assign(tiles + 1, 0);
  const std::size_t n = pairs.size() / 2;
  for (std::size_t i = 0; i < n; ++i) ++chunk.offsets[pairs[2 * i + 1] + 1];
  for (std::size_t t = 0; t < tiles; ++t) chunk.offsets[t + 1] += chunk.offsets[t];
  chunk.list.resize(n);
  for (std::size_t i = 0; i < n; ++i) chunk.list[chunk.offsets[pairs[2 * i + 1]]++] = pairs[2 * i];
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
