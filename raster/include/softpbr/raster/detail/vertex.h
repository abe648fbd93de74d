// softpbr/raster/detail/vertex.h — the vertex stage: the shader's vertex() over a vertex buffer.
//
// Internal to softpbr::raster (included by renderer.h for its templates): not API, may
// change at any time. The API is renderer.h, shader.h, target.h, color.h, pool.h.
//
// Every vertex is transformed exactly once into the post-transform buffer (clip-space
// position + varyings), in parallel chunks; indexed triangles then share the results.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "softpbr/raster/pool.h"
#include "softpbr/raster/detail/setup.h"
#include "softpbr/raster/shader.h"
#include "softpbr/simd/simd.h"

namespace softpbr::raster {

// Vertices per parallel task of the vertex stage.
inline constexpr std::size_t kVertexChunk = 1024;

struct TransformedVertices {
  int varyings = 0;                   // floats per vertex
  std::vector<glm::vec4> position;     // clip space
  std::vector<float> values;           // varyings, `varyings` floats per vertex
  std::vector<std::uint16_t> outcode;  // clip.h's classify()
  std::vector<ScreenVertex> screen;    // setup.h's project(), where no clipping is needed

  std::size_t size() const { return position.size(); }
  const float* varyings_of(std::size_t i) const { return values.data() + i * static_cast<std::size_t>(varyings); }
};

// Classifies and projects vertices [first, last) of `vertices` for `viewport`: the outcode
// is clip.h's classify(), the screen vertex setup.h's project() for a vertex that needs
// neither clipping nor culling as non-finite, else zero. Many vertices at once, in the
// instruction set `isa` (simd.h; at most simd::cpu_isa(), which the first form uses); the
// same bits whatever the instruction set.
void project_vertices(TransformedVertices& vertices, std::size_t first, std::size_t last, Viewport viewport);
void project_vertices(TransformedVertices& vertices, std::size_t first, std::size_t last, Viewport viewport,
                      simd::Isa isa);

template <class V>
inline std::array<float, kVaryingCount<V>> varyings_to_floats(const V& v) {
  if constexpr (kVaryingCount<V> == 0) {
    return {};
  } else {
    return std::bit_cast<std::array<float, kVaryingCount<V>>>(v);
  }
}

template <class V>
inline V varyings_from_floats(const float* f) {
  if constexpr (kVaryingCount<V> == 0) {
    return V{};
  } else {
    std::array<float, kVaryingCount<V>> a;
    std::memcpy(a.data(), f, sizeof(a));
    return std::bit_cast<V>(a);
  }
}

template <Shader S>
void run_vertex_stage(ThreadPool& pool, const S& shader, std::span<const typename S::Vertex> vertices,
                      Viewport viewport, TransformedVertices& out) {
  using V = typename S::Varyings;
  constexpr int kN = kVaryingCount<V>;
  out.varyings = kN;
  out.position.resize(vertices.size());
  out.values.resize(vertices.size() * kN);
  out.outcode.resize(vertices.size());
  out.screen.resize(vertices.size());
  const std::size_t chunks = (vertices.size() + kVertexChunk - 1) / kVertexChunk;
  pool.parallel_for(chunks, [&](std::size_t c) {
    const std::size_t first = c * kVertexChunk;
    const std::size_t end = std::min(vertices.size(), first + kVertexChunk);
    for (std::size_t i = first; i < end; ++i) {
      V v{};
      out.position[i] = shader.vertex(vertices[i], v);
      if constexpr (kN > 0) {
        const auto f = varyings_to_floats(v);
        std::memcpy(out.values.data() + i * kN, f.data(), sizeof(f));
      }
    }
    project_vertices(out, first, end, viewport);
  });
}

}  // namespace softpbr::raster
