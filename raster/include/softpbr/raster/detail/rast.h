// softpbr/raster/detail/rast.h — the tile kernel for a shader, at a lane width, for an
// instruction set.
//
// Internal to softpbr::raster (included by renderer.h for its templates): not API, may
// change at any time. The API is renderer.h, shader.h, target.h, color.h, pool.h.
//
// The kernel itself is rast-inl.h, compiled per target; this file holds what every copy
// shares and the one dispatch of a tile to the copy for the renderer's instruction set.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>

#include <glm/vec4.hpp>

#include "softpbr/check.h"
#include "softpbr/raster/detail/bin.h"
#include "softpbr/raster/detail/vertex.h"
#include "softpbr/raster/shader.h"
#include "softpbr/raster/target.h"
#include "softpbr/simd/dispatch.h"
#include "softpbr/simd/simd.h"

namespace softpbr::raster {

// What a tile kernel shaded: fragment-shader invocations (one per pixel a triangle covers
// and that passes the depth test, so at MSAA one per pixel and triangle, not per sample;
// a packet's padding lanes are not counted) and the fragment() / fragment_packet() calls
// that shaded them. Invocations do not depend on threads, tiles or lanes; calls do.
struct ShadeCounts {
  std::uint64_t invocations = 0;
  std::uint64_t calls = 0;
  ShadeCounts& operator+=(const ShadeCounts& o) {
    invocations += o.invocations;
    calls += o.calls;
    return *this;
  }
};

}  // namespace softpbr::raster

namespace softpbr::raster::detail {

// The varying floats the tile kernel computes derivatives of (kDerivativeMask), in order.
template <class S>
inline constexpr auto kDerivativeIndices = [] {
  constexpr int kN = kVaryingCount<typename S::Varyings>;
  constexpr std::uint32_t kMask = kDerivativeMask<S> & (kN >= 32 ? ~std::uint32_t{0} : (std::uint32_t{1} << kN) - 1);
  std::array<int, std::popcount(kMask)> indices{};
  int i = 0;
  for (int k = 0; k < kN; ++k)
    if (kMask >> k & 1) indices[i++] = k;
  return indices;
}();

// MSAA: the tile kernel tests four samples of a quad's four pixels at once, as 16 "sample
// lanes" k = 4·s + j (sample s of pixel j). The bits of such a mask in pixel order, 4·j + s
// (pixel j's samples in nibble j): the 4×4 bit matrix transposed by two delta swaps.
constexpr unsigned transpose_4x4_bits(unsigned x) {
  unsigned t = (x ^ (x >> 3)) & 0x0A0Au;  // (s even, j odd) with (s + 1, j − 1)
  x ^= t ^ (t << 3);
  t = (x ^ (x >> 6)) & 0x00CCu;  // the 2×2 blocks (s < 2, j ≥ 2) with (s + 2, j − 2)
  return x ^ t ^ (t << 6);
}
// The pixels j with some sample in a 16-bit sample-lane mask (bit j set: any bit 4·s + j).
constexpr unsigned pixels_of_sample_lanes(unsigned x) { return (x | x >> 4 | x >> 8 | x >> 12) & 0xFu; }

}  // namespace softpbr::raster::detail

// raster_tile<W, S>() in softpbr::raster::detail::{baseline, avx2, avx512}.
#define SOFTPBR_TARGET_FILE "softpbr/raster/detail/rast-inl.h"
#include "softpbr/simd/foreach_target.h"

namespace softpbr::raster {

namespace detail {
// The widths the baseline copy of the tile kernel is compiled at: 1 and 4, and the build's
// own native width when it is wider (8 or 16 lanes in a build for AVX2 or AVX-512). Wider
// lanes than a target's registers are emulated (16 lanes on SSE2 are four registers): those
// copies were two thirds of a packet shader's kernel compile time and no faster than 4
// lanes, so they are not compiled.
inline constexpr int kBaselineMaxWidth = simd::kNativeWidth > 4 ? simd::kNativeWidth : 4;

// The copy of the tile kernel that runs a request for W lanes on a renderer whose
// instruction set is `isa`: the widest copy compiled that the CPU runs and that is at most
// W lanes wide — AVX-512 at 16 lanes, AVX2 at 8 (and for scalar shaders, W = 0), the
// baseline copy at 1, 4 and kBaselineMaxWidth. Every copy gives the same bits, so this only
// decides speed: RendererOptions::lanes is the widest packet a renderer may use. The widths
// a renderer picks itself (lanes = 0: 16 with AVX-512, 8 with AVX2) run their target's
// copy. Compiling only these copies leaves a packet shader 4 kernels per sample count (of
// 12 for every width on every target) in a build for x86-64's baseline (docs/design.md,
// "SIMD and dispatch").
template <int W, int kMs, Shader S>
auto tile_kernel([[maybe_unused]] simd::Isa isa) {
#if SOFTPBR_SIMD_X86_TARGETS
  if constexpr (W == 16) {
    if (isa == simd::Isa::Avx512) return &avx512::raster_tile<16, kMs, S>;
  }
  if constexpr (W == 16 || W == 8) {
    if (isa != simd::Isa::Baseline) return &avx2::raster_tile<8, kMs, S>;
  } else if constexpr (W == 0) {
    if (isa != simd::Isa::Baseline) return &avx2::raster_tile<0, kMs, S>;
  }
#endif
  return &baseline::raster_tile<(W > kBaselineMaxWidth ? kBaselineMaxWidth : W), kMs, S>;
}

template <int W, Shader S>
ShadeCounts dispatch_tile(simd::Isa isa, const S& shader, const DrawGeometry& geometry, std::size_t tile,
                          const TileRect& rect, const TargetPixels& target) {
  if constexpr (kDepthOnly<S>) {  // 1 sample a pixel only (Renderer::draw checks)
    return tile_kernel<W, 1, S>(isa)(shader, geometry, tile, rect, target);
  } else {
    switch (target.samples) {
      case 4: return tile_kernel<W, 4, S>(isa)(shader, geometry, tile, rect, target);
      case 8: return tile_kernel<W, 8, S>(isa)(shader, geometry, tile, rect, target);
      default: return tile_kernel<W, 1, S>(isa)(shader, geometry, tile, rect, target);
    }
  }
}
}  // namespace detail

// Rasterizes one draw's triangles that touch tile `tile` (rectangle `rect`) into `target`:
// `lanes` pixels per fragment_packet() call (1, 4, 8 or 16; 0: the build's widest native
// width) when the shader has one, else one pixel at a time through fragment(); with the
// kernel compiled for `isa`, which the CPU must support; per sample for a multisampled
// target (target.samples). The same bits for every lane count and instruction set.
// Returns what it shaded.
template <Shader S>
ShadeCounts raster_tile(const S& shader, const DrawGeometry& geometry, std::size_t tile, const TileRect& rect,
                        const TargetPixels& target, int lanes, simd::Isa isa = simd::Isa::Baseline) {
  if constexpr (PacketShaderFor<S, float> && PacketShaderFor<S, simd::Vec<4>>) {
    switch (lanes == 0 ? simd::kNativeWidth : lanes) {
      case 1: return detail::dispatch_tile<1>(isa, shader, geometry, tile, rect, target);
      case 4: return detail::dispatch_tile<4>(isa, shader, geometry, tile, rect, target);
      case 8: return detail::dispatch_tile<8>(isa, shader, geometry, tile, rect, target);
      default: return detail::dispatch_tile<16>(isa, shader, geometry, tile, rect, target);
    }
  } else {
    return detail::dispatch_tile<0>(isa, shader, geometry, tile, rect, target);
  }
}

}  // namespace softpbr::raster
