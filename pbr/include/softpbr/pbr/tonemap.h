// softpbr/pbr/tonemap.h — from HDR linear radiance to an image: exposure → tone map →
// transfer curve → RGBA8 (and the linear float output of raster/write.h: .hdr, OpenEXR).
//
// Every step is basic arithmetic; the transfer curves (exact piecewise sRGB, or a power
// law "gamma") are applied through 255 precomputed thresholds per curve, computed with
// the deterministic dmath functions, so the 8-bit code of a value is exact and the same
// on every platform.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "softpbr/raster/target.h"
#include "softpbr/raster/write.h"

namespace softpbr::pbr {

enum class ToneMap {
  None,      // clamp to [0, 1]
  Reinhard,  // c / (1 + c) per channel (Reinhard et al. 2002, simple form)
  Aces,      // ACES filmic curve fit by K. Narkowicz (2015), per channel
  Neutral    // Khronos PBR Neutral tone mapper (2024)
};

// "none", "reinhard", "aces", "neutral" ↔ ToneMap.
std::optional<ToneMap> tone_map_from_name(std::string_view name);
std::string_view tone_map_name(ToneMap op);

// How a multisampled target (MSAA) becomes one colour a pixel; both are box filters over
// the pixel's samples (raster::resolve_box's pairwise sum in sample order), and give a
// pixel whose samples are all equal exactly the colour a 1-sample target would.
enum class Resolve : std::uint8_t {
  // Exposure and tone map per sample, then the mean, then the transfer curve: an edge
  // between a highlight far above 1 and a dark surface blends the displayed colours, with
  // no dark halo (the default; docs/design.md, MSAA, has the measurement).
  ToneMapped,
  // The mean of the linear samples, then exposure → tone map → curve: physically the
  // pixel's mean radiance, as a GPU's resolve blit before a tone-mapping pass.
  Linear
};

// "tonemapped", "linear" ↔ Resolve.
std::optional<Resolve> resolve_from_name(std::string_view name);
std::string_view resolve_name(Resolve r);

struct OutputSettings {
  float exposure = 0.0f;      // photographic stops: colour × 2^exposure before tone mapping
  ToneMap tone_map = ToneMap::Reinhard;
  float gamma = 0.0f;         // 0: the exact sRGB curve; > 0: encoded = linear^(1/gamma), e.g. 2.2
  Resolve resolve = Resolve::ToneMapped;  // multisampled targets only
};

// Applies one tone-mapping operator to linear colour (after exposure).
glm::vec3 apply_tone_map(ToneMap op, glm::vec3 c);

// Tone maps and encodes the target's colour to 8 bits; alpha stays linear. A multisampled
// target is resolved as settings.resolve says. Throws std::invalid_argument for a
// non-finite exposure or a gamma that is negative or not finite.
raster::Image8 tone_map_to_rgba8(const raster::Target& target, const OutputSettings& settings);

// The same output transform prepared once, to encode a target piece by piece (e.g. each
// tile right after the renderer has drawn it, see render_rgba8 in scene.h). Encoding a
// value looks its 8-bit code up through a table indexed by the float's top 16 bits, then
// steps over the few thresholds left: the same code as a binary search over the 255
// thresholds, in a few operations.
//
// encode() runs on lanes of pixels (simd::Vec<N>: the same IEEE operations per lane as the
// scalar code), compiled for AVX2 or AVX-512 when the CPU has it (runtime dispatch, simd.h):
// the tone map operator for N pixels at once, then the codes branch-free. A curve with at
// most one threshold per table entry (sRGB, gammas from ~1 to ~17) has a packed table
// (code and the threshold's low bits per entry): one lookup and an integer comparison per
// value, in lanes. Others take the table, then exactly as many steps as the curve's most
// crowded entry needs (2 for gamma 0.5), or, for a curve that would need more than
// kMaxSteps (gamma below ~0.25), a branch-free binary search. The plain per-pixel code stays as EncodeKernel::Scalar, the
// reference the others are tested against byte for byte.
enum class EncodeKernel : std::uint8_t {
  Scalar,  // per pixel and channel (the reference)
  Lanes4,  // 4 lanes in the build's own instruction set (SSE2 on x86-64, NEON on AArch64)
  Avx2,    // 8 lanes compiled for AVX2
  Avx512   // 16 lanes compiled for AVX-512
};

class ToneMapper {
 public:
  // Throws std::invalid_argument as tone_map_to_rgba8.
  explicit ToneMapper(const OutputSettings& settings);

  // Tone maps and encodes pixels [x0, x1) × [y0, y1) of `target` into `image` (of the
  // target's size; rgba holds width × height × 4 bytes), with the widest kernel this CPU
  // runs. A multisampled target's pixels are resolved first (OutputSettings::resolve).
  void encode(const raster::Target& target, int x0, int y0, int x1, int y1, raster::Image8& image) const;
  // The same with a given kernel (tests and benchmarks); it must be supported().
  void encode(const raster::Target& target, int x0, int y0, int x1, int y1, raster::Image8& image,
              EncodeKernel kernel) const;
  // Whether this CPU (and build) runs `kernel`.
  static bool supported(EncodeKernel kernel);
  // The widest supported kernel: what encode() without a kernel uses.
  static EncodeKernel widest_kernel();

  // Steps after the table lookup that the lanes kernels take for this curve (the most any
  // table entry needs), or −1 when that is above kMaxSteps and they binary-search instead.
  int code_steps() const { return steps_; }
  static constexpr int kMaxSteps = 4;  // 4 steps + table ≈ the cost of the 8-step search

  // The same for a piece whose every pixel is `color` (e.g. a tile holding only the clear
  // colour): the bytes encode() would write, computed once.
  void encode_uniform(const glm::vec4& color, int x0, int y0, int x1, int y1, raster::Image8& image) const;

  // The 8-bit code of a tone-mapped value: the number of thresholds ≤ v (0 for NaN).
  std::uint8_t encode(float v) const;

  // The resolve of multisampled pixels [x0, x1) × [y0, y1) of `target` into `out`
  // (out_width pixels a row): for Resolve::ToneMapped the mean of the samples' tone-mapped
  // colours (then encoded with the transfer curve alone), for Linear raster::resolve_box.
  void resolve(const raster::Target& target, int x0, int y0, int x1, int y1, glm::vec4* out,
               std::size_t out_width) const;
  // The same from pixels as the renderer hands a tile callback (raster::TargetPixels:
  // a whole target, or a multisampled tile's block of samples), only read.
  void resolve(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1, glm::vec4* out,
               std::size_t out_width) const;
  // encode() of multisampled pixels [x0, x1) × [y0, y1) given as TargetPixels (what a
  // Renderer::TileCallback receives): the same bytes as encode() of their target.
  void encode(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1, raster::Image8& image) const;

 private:
  void resolve(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1, glm::vec4* out,
               std::size_t out_width, EncodeKernel kernel) const;
  void encode_multisampled(const raster::Target& target, int x0, int y0, int x1, int y1, raster::Image8& image,
                           EncodeKernel kernel) const;
  void encode_multisampled(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1, raster::Image8& image,
                           EncodeKernel kernel) const;
  OutputSettings settings_;
  float scale_;
  std::array<float, 255> thresholds_;
  std::vector<std::uint8_t> first_;  // per top-16-bit key k of v in [0, 1): #thresholds < float(k << 16)
  // The thresholds followed by kMaxSteps × +Inf, so that steps from any table entry stay
  // inside the array (+Inf ≤ v only for v = +Inf, whose code the kernels set to 255 anyway).
  std::array<float, 255 + kMaxSteps> padded_;
  int steps_;
  // For curves with at most one threshold per key (steps_ ≤ 1: sRGB, gammas from ~1 up
  // to ~17): per key from packed_base_ (t[0]'s) to that of 1.0f, the code at the key's
  // start << 17 | the low 16 bits of the threshold in the key (0x10000 when none), so a
  // value's code is one lookup and an integer comparison of its low bits. Empty otherwise.
  std::vector<std::uint32_t> packed_;
  std::uint32_t packed_base_ = 0;
  // Resolve::ToneMapped: the transfer curve alone (no exposure, tone map None), for the
  // resolved tone-mapped values; null when this mapper is that already.
  std::shared_ptr<const ToneMapper> display_;
};

// Linear float output, Radiance .hdr and OpenEXR (× 2^exposure, no tone map): softpbr::raster's
// (raster/write.h), named here too, where they were declared before.
using raster::write_exr;
using raster::write_hdr;

// The 255 thresholds of an encoding curve: threshold k is the linear value whose encoding
// is (k + 0.5)/255. gamma 0 selects sRGB.
std::array<float, 255> transfer_thresholds(float gamma);

}  // namespace softpbr::pbr
