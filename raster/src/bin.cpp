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
constexpr std::size_t kTrianglesPerChunk = 2048;
constexpr std::size_t kMaxOffsetEntries = std::size_t{1} << 23;

void assemble_chunk(const DrawGeometry& geometry, std::span<const std::uint32_t> indices, std::size_t first,
                    std::size_t last, const TileGrid& grid, TriangleChunk& chunk) {
  const TransformedVertices& verts = geometry.vertices;
  const int nvar = verts.varyings;
  const Viewport viewport{grid.width, grid.height};
  std::vector<std::uint32_t> tile_of;  // (tile, triangle) pairs as two parallel lists
  std::vector<std::uint32_t> tri_of;

  auto add = [&](const glm::vec4 clip[3], const std::uint32_t ids[3]) {
    Triangle t;
    if (!setup_triangle(clip, ids, viewport, geometry.state, t)) return;
    const auto index = static_cast<std::uint32_t>(chunk.triangles.size());
    chunk.triangles.push_back(t);
    const int tx0 = t.min_x / grid.tile_size, tx1 = t.max_x / grid.tile_size;
    const int ty0 = t.min_y / grid.tile_size, ty1 = t.max_y / grid.tile_size;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        tile_of.push_back(static_cast<std::uint32_t>(ty * grid.columns + tx));
        tri_of.push_back(index);
      }
  };

  ClipVertex polygon[kMaxClipVertices];
  for (std::size_t tri = first; tri < last; ++tri) {
    const std::uint32_t ids[3] = {indices[3 * tri], indices[3 * tri + 1], indices[3 * tri + 2]};
    const glm::vec4 clip[3] = {verts.position[ids[0]], verts.position[ids[1]], verts.position[ids[2]]};
    const float* const var[3] = {verts.varyings_of(ids[0]), verts.varyings_of(ids[1]), verts.varyings_of(ids[2])};
    int n = 0;
    switch (clip_triangle(clip, var, nvar, viewport, polygon, n)) {
      case ClipResult::Culled: break;
      case ClipResult::Inside: add(clip, ids); break;
      case ClipResult::Clipped: {
        // New vertices get ids past the vertex buffer; their varyings live in the chunk.
        const auto base = static_cast<std::uint32_t>(verts.size() + chunk.clip_varyings.size() / std::max(nvar, 1));
        std::uint32_t poly_ids[kMaxClipVertices];
        for (int v = 0; v < n; ++v) {
          poly_ids[v] = base + static_cast<std::uint32_t>(v);
          chunk.clip_varyings.insert(chunk.clip_varyings.end(), polygon[v].varyings, polygon[v].varyings + nvar);
        }
        if (nvar == 0) chunk.clip_varyings.resize(chunk.clip_varyings.size() + n);  // keep ids unique
        for (int v = 1; v + 1 < n; ++v) {  // a fan: the polygon is convex
          const glm::vec4 fan[3] = {polygon[0].position, polygon[v].position, polygon[v + 1].position};
          const std::uint32_t fan_ids[3] = {poly_ids[0], poly_ids[v], poly_ids[v + 1]};
          add(fan, fan_ids);
        }
        break;
      }
    }
  }

  // Counting sort of the pairs by tile, stable, so each tile keeps submission order.
  chunk.offsets.assign(grid.count() + 1, 0);
  for (const std::uint32_t t : tile_of) ++chunk.offsets[t + 1];
  for (std::size_t t = 0; t < grid.count(); ++t) chunk.offsets[t + 1] += chunk.offsets[t];
  chunk.list.resize(tile_of.size());
  std::vector<std::uint32_t> cursor(chunk.offsets.begin(), chunk.offsets.end() - 1);
  for (std::size_t i = 0; i < tile_of.size(); ++i) chunk.list[cursor[tile_of[i]]++] = tri_of[i];
}

}  // namespace

void assemble_triangles(ThreadPool& pool, std::span<const std::uint32_t> indices, const TileGrid& grid,
                        DrawGeometry& geometry) {
  const std::size_t triangles = indices.size() / 3;
  if (triangles == 0) return;
  std::size_t chunks = (triangles + kTrianglesPerChunk - 1) / kTrianglesPerChunk;
  chunks = std::max<std::size_t>(1, std::min(chunks, kMaxOffsetEntries / (grid.count() + 1)));
  const std::size_t per_chunk = (triangles + chunks - 1) / chunks;
  geometry.chunks.assign(chunks, {});
  pool.parallel_for(chunks, [&](std::size_t c) {
    const std::size_t first = c * per_chunk;
    const std::size_t last = std::min(triangles, first + per_chunk);
    if (first < last) assemble_chunk(geometry, indices, first, last, grid, geometry.chunks[c]);
  });
}

}  // namespace softpbr::raster
