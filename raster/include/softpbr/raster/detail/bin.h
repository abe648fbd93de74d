// softpbr/raster/detail/bin.h — primitive assembly and binning into screen tiles.
//
// Internal to softpbr::raster (included by renderer.h for its templates): not API, may
// change at any time. The API is renderer.h, shader.h, target.h, color.h, pool.h.
//
// Triangles are assembled from the index buffer in fixed-size chunks, in parallel: each
// chunk clips, sets up and bins its triangles into a list per tile (compressed rows: one
// offset per tile). Reading a tile's lists chunk after chunk gives its triangles in
// submission order, whatever thread built which chunk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "softpbr/raster/pool.h"
#include "softpbr/raster/detail/setup.h"
#include "softpbr/raster/shader.h"
#include "softpbr/raster/detail/vertex.h"

namespace softpbr::raster {

struct TileRect {
  int x0, y0, x1, y1;  // pixels [x0, x1) × [y0, y1)
};

// The target cut into square tiles of tile_size pixels (the last row and column may be
// smaller).
struct TileGrid {
  int tile_size = 64;
  int width = 0;
  int height = 0;
  int columns = 0;
  int rows = 0;
  int sample_reach = 0;  // of the target's sample pattern (Viewport::sample_reach)

  TileGrid() = default;
  TileGrid(int target_width, int target_height, int tile);
  std::size_t count() const { return static_cast<std::size_t>(columns) * static_cast<std::size_t>(rows); }
  TileRect rect(std::size_t tile) const;
};

// Aligned to a cache line: workers assemble neighbouring chunks at the same time, and two
// chunks' vector end pointers sharing a line would make every push_back a coherence miss
// (docs/design.md, "Performance notes").
struct alignas(64) TriangleChunk {
  std::vector<Triangle> triangles;
  std::vector<float> clip_varyings;    // varyings of vertices made by clipping
  std::vector<std::uint32_t> offsets;  // per tile: its triangles are list[offsets[t], offsets[t+1])
  std::vector<std::uint32_t> list;     // indices into `triangles`
  std::vector<std::uint32_t> scratch;  // assembly's working memory, kept to save allocations

  std::span<const std::uint32_t> tile(std::size_t t) const {
    if (offsets.empty()) return {};
    return std::span<const std::uint32_t>(list).subspan(offsets[t], offsets[t + 1] - offsets[t]);
  }
};

// Everything one draw leaves for the raster stage.
struct DrawGeometry {
  DrawState state;
  TransformedVertices vertices;
  std::vector<TriangleChunk> chunks;

  // Empties the triangles and bins but keeps the memory for the next draw; the vertex
  // arrays keep their stale contents until the next vertex stage overwrites them.
  void recycle();

  // Bytes held (capacity) by the vertices, triangles and bins.
  std::size_t bytes() const;

  // Whether any triangle of the draw was binned to tile `t`.
  bool touches(std::size_t t) const {
    for (const TriangleChunk& c : chunks)
      if (!c.offsets.empty() && c.offsets[t + 1] != c.offsets[t]) return true;
    return false;
  }

  // Varyings of vertex `id` of a triangle in chunk `chunk`.
  const float* varyings(const TriangleChunk& chunk, std::uint32_t id) const {
    const std::size_t n = static_cast<std::size_t>(vertices.varyings);
    return id < vertices.size() ? vertices.varyings_of(id)
                                : chunk.clip_varyings.data() + (id - vertices.size()) * n;
  }
};

// Throws std::invalid_argument if the index count is not a multiple of 3 and
// std::out_of_range if an index does not name a vertex.
void validate_indices(std::span<const std::uint32_t> indices, std::size_t vertex_count);

// Clips, sets up and bins the triangles of `indices` (three per triangle) over the
// post-transform vertices in `geometry`.
void assemble_triangles(ThreadPool& pool, std::span<const std::uint32_t> indices, const TileGrid& grid,
                        DrawGeometry& geometry);

}  // namespace softpbr::raster
