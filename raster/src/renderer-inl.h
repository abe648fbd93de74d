// The renderer's clear of a tile block, compiled once per target (renderer.cpp includes it
// through softpbr/simd/foreach_target.h; no include guard, no header included here).

namespace softpbr::raster::detail::SOFTPBR_TARGET_NS {

// Writes `color` into colors[0, n) and `depth` into depths[0, m): a multisampled tile's
// block, cleared in cache before its draws (renderer.cpp). 64-byte vectors of the clear
// values, stored as the target's widest (one store with AVX-512; the baseline build's
// std::fill wrote 16 bytes at a time, and the block is larger than the L1 cache). Each
// float keeps its bits, −0 and NaN payloads included: pure data movement. The same bytes
// from every copy.
SOFTPBR_KERNEL void fill_block(glm::vec4* colors, std::size_t n, glm::vec4 color, float* depths, std::size_t m,
                               float depth) {
  std::size_t i = 0, j = 0;
  typedef float V16 __attribute__((vector_size(64)));
  const V16 c = {color.r, color.g, color.b, color.a, color.r, color.g, color.b, color.a,
                 color.r, color.g, color.b, color.a, color.r, color.g, color.b, color.a};
#if SOFTPBR_TARGET_AVX512
  // Whole 64-byte stores: GCC copies a 64-byte vector by two 32-byte halves (its
  // preferred width), which measured no faster than std::fill.
  const V16 d = depth - V16{};  // a bare broadcast (see simd::Lanes(float))
  for (; i + 4 <= n; i += 4) simd::SOFTPBR_TARGET_NS::store_vector<16>(&colors[i].r, c);
  for (; j + 16 <= m; j += 16) simd::SOFTPBR_TARGET_NS::store_vector<16>(depths + j, d);
#else
  V16 d;
  for (int k = 0; k < 16; ++k) d[k] = depth;
  for (; i + 4 <= n; i += 4) __builtin_memcpy(colors + i, &c, sizeof c);
  for (; j + 16 <= m; j += 16) __builtin_memcpy(depths + j, &d, sizeof d);
#endif
  for (; i < n; ++i) colors[i] = color;
  for (; j < m; ++j) depths[j] = depth;
}

}  // namespace softpbr::raster::detail::SOFTPBR_TARGET_NS
