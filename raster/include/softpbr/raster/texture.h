// softpbr/raster/texture.h — mipmapped textures and the sampling rules of the OpenGL
// specification, bit-exact at every lane width.
//
//   auto wood = std::make_shared<const raster::Texture>(image, raster::ColorSpace::Srgb);
//   raster::Sampler sampler;                       // repeat, trilinear
//   sampler.max_anisotropy = 8;
//   // in a shader's fragment(f):
//   glm::vec4 c = wood->sample(sampler, f.v.uv, f.ddx.uv, f.ddy.uv);
//   // in fragment_packet<F>(p): the same per lane
//   raster::Color<F> c = raster::sample(*wood, sampler, u, v, dudx, dvdx, dudy, dvdy);
//   // or with the texture and sampler bound once per draw, not resolved on every call:
//   raster::BoundTexture bound(*wood, sampler);
//   raster::Color<F> c = raster::sample(bound, u, v, dudx, dvdx, dudy, dvdy);
//
// Conventions (docs/design.md, "Textures"):
// - UV (0, 0) is the top-left corner of the image — its first row in memory — and (1, 1) the
//   bottom-right corner, as in glTF (v grows down the image). Texel (i, j) of a level of
//   size w × h covers [i/w, (i+1)/w) × [j/h, (j+1)/h): its centre is ((i + ½)/w, (j + ½)/h).
// - Sampling returns linear values: 8-bit sRGB colour channels are decoded through an
//   exact 256-entry table before filtering (never after), alpha and linear textures read
//   code/255. Float textures return their values as stored.
// - Level of detail, mip selection, filtering and wrapping follow the OpenGL 4.6
//   specification, §8.14 (the scale factor ρ, λ = log₂ ρ + bias clamped to [min_lod,
//   max_lod], λ ≤ 0 magnifies) and §8.14.2 (wrap modes), with anisotropic filtering as
//   EXT_texture_filter_anisotropic describes it: N = min(⌈P_max/P_min⌉, max_anisotropy)
//   trilinear probes along the major axis of the pixel's footprint at λ = log₂(P_max/N).
//
// Determinism: every lookup is computed out of line (texture.cpp), each value by the same
// IEEE operations in the same order whatever the form, the lane width or the instruction
// set: the packet form runs the scalar code per lane, or, on x86-64 CPUs with AVX2 and for
// 8-bit textures with power-of-two sides through repeat, trilinear samplers, a lane
// kernel (8 lanes with AVX2, 16 with AVX-512) with those operations per lane (selects for
// branches, no FMA). So a texel value is the same bits at every width, with dispatch on
// or off. log₂ is computed from the float's bits and a fixed polynomial (no libm). Mip
// chains are built with a fixed order of operations per texel, so they do not depend on
// the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "softpbr/image/image.h"
#include "softpbr/raster/shader.h"
#include "softpbr/simd/simd.h"

namespace softpbr::raster {

class ThreadPool;

// How the colour channels of an 8-bit texture are read (alpha is always linear).
enum class ColorSpace : std::uint8_t { Linear, Srgb };

enum class Wrap : std::uint8_t { Repeat, ClampToEdge, MirroredRepeat };
enum class Filter : std::uint8_t { Nearest, Linear };
// Minification across levels: None reads the base level only; Nearest the level nearest
// λ; Linear blends the two levels around λ (trilinear with Filter::Linear).
enum class MipFilter : std::uint8_t { None, Nearest, Linear };

inline constexpr int kMaxTextureSide = 16384;
inline constexpr int kMaxAnisotropy = 16;

struct Sampler {
  Wrap wrap_u = Wrap::Repeat;
  Wrap wrap_v = Wrap::Repeat;
  Filter mag_filter = Filter::Linear;
  Filter min_filter = Filter::Linear;
  MipFilter mip_filter = MipFilter::Linear;
  int max_anisotropy = 1;  // 1 (isotropic) … kMaxAnisotropy
  float lod_bias = 0.0f;   // added to λ before the clamp
  float min_lod = 0.0f;
  float max_lod = 1000.0f;
};

// Throws std::invalid_argument naming the field: an anisotropy outside [1, 16], a
// non-finite bias, min_lod > max_lod or NaN limits, an enumerator out of range.
void validate(const Sampler& sampler);

namespace detail {
struct LaneTexture;  // what a lane kernel reads (defined below Texture)
}  // namespace detail

struct TextureOptions {
  bool mipmaps = true;  // false: the base level only (every lookup reads it)
};

class Texture {
 public:
  struct Level {
    int width;
    int height;
    std::size_t offset;  // first texel of the level in the texel array
  };

  // An 8-bit RGBA texture. Its colour channels are sRGB-encoded or linear; the mip chain
  // is filtered in linear light and stored encoded the same way. `pool`, when given,
  // builds large levels in parallel (the same bits as without). Throws
  // std::invalid_argument for a side outside [1, kMaxTextureSide] or pixel data of the
  // wrong size, std::bad_alloc when the texels do not fit in memory.
  Texture(const image::ImageView8& image, ColorSpace space, const TextureOptions& options = {},
          ThreadPool* pool = nullptr);
  // The same, taking over the image's pixel buffer: with capacity for the mip chain
  // (image::load_image8 with rgba8_chain_bytes as its capacity) the base level is not
  // copied and no second buffer is allocated; otherwise the texels move to a new buffer.
  // The same texels either way.
  Texture(image::Image8&& image, ColorSpace space, const TextureOptions& options = {}, ThreadPool* pool = nullptr);
  // The same with mip levels the image came with (a KTX2 file's, image::load_ktx2): level
  // l + 1 is `more_levels[l]`, which must be max(1, ⌊w/2^(l+1)⌋) × max(1, ⌊h/2^(l+1)⌋)
  // (std::invalid_argument otherwise), used as stored; the levels after the last given are
  // built from it as above. Levels beyond the chain (or any, without mipmaps) are ignored.
  Texture(image::Image8&& image, std::span<const image::Image8> more_levels, ColorSpace space,
          const TextureOptions& options = {}, ThreadPool* pool = nullptr);
  // Bytes of an 8-bit texture's texels with its whole mip chain, for a base of width ×
  // height (its level count as mip_level_count); 0 for a size outside [1, kMaxTextureSide].
  static std::size_t rgba8_chain_bytes(int width, int height);
  // A float RGBA texture (HDR): values are used as stored and must be finite
  // (std::invalid_argument otherwise).
  explicit Texture(const image::ImageViewF& image, const TextureOptions& options = {}, ThreadPool* pool = nullptr);

  int width() const { return levels_[0].width; }
  int height() const { return levels_[0].height; }
  int level_count() const { return static_cast<int>(levels_.size()); }
  const Level& level(int l) const { return levels_[static_cast<std::size_t>(l)]; }
  bool is_float() const { return !texels_f_.empty(); }
  ColorSpace color_space() const { return space_; }
  // Bytes held by the texels of every level.
  std::size_t texel_bytes() const { return texels8_.size() + texels_f_.size() * sizeof(float); }

  // Every level, base first, and their stored texels (RGBA, level by level, rows top
  // down): 8-bit codes when !is_float(), floats otherwise — e.g. to upload the same mip
  // chain elsewhere. rgb_decode_table() maps an 8-bit colour code to linear.
  std::span<const Level> levels() const { return levels_; }
  std::span<const std::uint8_t> texels8() const { return texels8_; }
  std::span<const float> texels_f() const { return texels_f_; }
  const float* rgb_decode_table() const { return rgb_table_; }

  // Texel (x, y) of `level` as linear RGBA (no wrapping: coordinates must be in range).
  glm::vec4 texel(int level, int x, int y) const;

  // Filtered lookups (see the header comment). `uv` in texture coordinates; the
  // derivatives are of uv along +x and +y on screen (a Fragment's ddx/ddy); `bias` is
  // added to the sampler's. sample_lod() reads at the given λ (before bias and clamps),
  // as GLSL's textureLod. Non-finite coordinates read as 0, non-finite derivatives as 0
  // (magnification).
  glm::vec4 sample(const Sampler& s, glm::vec2 uv, glm::vec2 duv_dx, glm::vec2 duv_dy, float bias = 0.0f) const;
  glm::vec4 sample_lod(const Sampler& s, glm::vec2 uv, float lod) const;

  // The level of detail λ a gradient lookup uses: log₂ of the scale factor (anisotropic:
  // of P_max/N) plus the biases, clamped to [min_lod, max_lod]; −∞ before the clamp for
  // zero derivatives. And N, the probes an anisotropic lookup takes (1 when isotropic).
  struct Footprint {
    float lod;
    int probes;
  };
  Footprint footprint(const Sampler& s, glm::vec2 duv_dx, glm::vec2 duv_dy, float bias = 0.0f) const;

  // Lookups of `n` points at once (the packet form's lanes), each exactly as sample() /
  // sample_lod() of that point: arrays of n floats in, four arrays of n floats out.
  struct Batch {
    const float* u;
    const float* v;
    const float* dudx;  // gradient form only
    const float* dvdx;
    const float* dudy;
    const float* dvdy;
    const float* lod;  // explicit-LOD form only
    float* r;
    float* g;
    float* b;
    float* a;
    // The channels the caller reads (bit c: channel c, r = 0 … a = 3): a lookup may skip
    // decoding and filtering the others and leave their outputs unwritten (the lane
    // kernel does, for rgb, gb and r; a metallic-roughness map needs two channels of four).
    unsigned channels = kRgba;
  };
  // Channel sets for Batch::channels and raster::sample.
  static constexpr unsigned kRed = 1, kGreen = 2, kBlue = 4, kAlpha = 8;
  static constexpr unsigned kRgb = kRed | kGreen | kBlue, kRgba = kRgb | kAlpha;
  void sample_batch(const Sampler& s, int n, const Batch& batch) const { sample_batch(s, n, batch, simd::cpu_isa()); }
  // The same with the lane kernel for `isa` (which the CPU must support), where one runs:
  // 16 lanes with Avx512, 8 with Avx2, the scalar lookup with Baseline. The same bits.
  void sample_batch(const Sampler& s, int n, const Batch& batch, simd::Isa isa) const;
  void sample_lod_batch(const Sampler& s, int n, const Batch& batch) const;

 private:
  friend class BoundTexture;
  // A lane kernel (texture-inl.h): sample_batch's lookups for one instruction set.
  using LaneKernel = void (*)(const detail::LaneTexture&, int, const Batch&);
  // The lane kernel that runs sample_batch(s, …, isa), with what it reads in `lanes`;
  // nullptr where the scalar lookup runs instead.
  LaneKernel lane_kernel(const Sampler& s, simd::Isa isa, detail::LaneTexture& lanes) const;
  void allocate_levels(int width, int height, bool mipmaps);
  // Checks an 8-bit image and space_, sets levels_; returns the bytes of every level.
  std::size_t levels8(const image::ImageView8& image, const TextureOptions& options);
  // The 8-bit texture's levels after the base, which texels8_ holds (sized for all).
  // Levels [first, level_count()) from the one before each.
  void build_mips8(ThreadPool* pool, std::size_t first = 1);

  std::vector<Level> levels_;
  image::PixelVector<std::uint8_t> texels8_;  // RGBA8, every level
  image::PixelVector<float> texels_f_;     // RGBA float, every level
  ColorSpace space_ = ColorSpace::Linear;
  const float* rgb_table_ = nullptr;   // 8-bit colour code → linear (sRGB or /255)
};

namespace detail {
// What the lane kernel (texture-inl.h) reads: an 8-bit texture whose sides are powers
// of two, through a sampler that repeats both ways and filters linearly everywhere.
struct LaneTexture {
  const std::uint8_t* texels;  // RGBA8, every level
  const float* rgb;            // colour code → linear
  const float* alpha;          // alpha code → k/255
  const Texture::Level* levels;
  int q;                       // the last level
  float width, height;         // level 0's sides
  float lod_bias, min_lod, max_lod;
  int max_anisotropy;
  const std::uint8_t* planes;  // rgb's floats by byte: byte k of entry c at [256 k + c]
};
}  // namespace detail

// A texture and a sampler bound together for many lookups, as a shader binds its
// textures once per draw: which code runs them (and what it reads) is settled here, not
// on every call — by the CPU, `isa` and detail::allow_texture_vbmi as they are when bound.
// Lookups through it are sample_batch()'s, bit for bit. The texture must outlive it; the
// sampler must be valid (validate()). A default-constructed one is unbound: no lookups.
class BoundTexture {
 public:
  BoundTexture() = default;
  BoundTexture(const Texture& texture, const Sampler& sampler, simd::Isa isa = simd::cpu_isa())
      : texture_(&texture), sampler_(sampler), isa_(isa), kernel_(texture.lane_kernel(sampler, isa, lanes_)) {}

  const Texture* texture() const { return texture_; }
  const Sampler& sampler() const { return sampler_; }
  // Texture::sample_batch(sampler(), n, batch, isa).
  void sample_batch(int n, const Texture::Batch& batch) const {
    if (kernel_ != nullptr) kernel_(lanes_, n, batch);
    else texture_->sample_batch(sampler_, n, batch, isa_);
  }

 private:
  const Texture* texture_ = nullptr;
  Sampler sampler_;
  simd::Isa isa_ = simd::Isa::Baseline;
  detail::LaneTexture lanes_{};
  Texture::LaneKernel kernel_ = nullptr;
};

namespace detail {
// For tests: whether Texture::sample_batch's AVX-512 kernel may run its VBMI copy where the
// CPU has VBMI (the default); false runs the plain AVX-512 copy, so that a test on a VBMI
// CPU checks both. The same bits either way.
void allow_texture_vbmi(bool allowed);
}  // namespace detail

// The mip chain's level count for a base of w × h: ⌊log₂ max(w, h)⌋ + 1 (level l is
// max(1, ⌊w / 2^l⌋) × max(1, ⌊h / 2^l⌋), as GL).
int mip_level_count(int width, int height);

// The exact decoding tables: sRGB code k → linear (IEC 61966-2-1, correctly rounded to
// float) and k → k/255.
const float* srgb8_decode_table();
const float* unorm8_decode_table();

// log₂ x for the level of detail, from the float's exponent and a fixed odd polynomial in
// (m − 1)/(m + 1) (relative error below 2·10⁻⁷; exact at powers of two): −∞ for 0, NaN for
// negatives and NaN, +∞ for +∞. Basic operations only.
float lod_log2(float x);

// The packet form: lane i of the result is texture.sample() (sample_lod()) of lane i's
// arguments, for F = float or simd lanes of any width. `channels` (Texture::Batch::channels)
// names the channels the caller reads; with lanes the others may come back as 0.
// Through a BoundTexture: the lookups of its texture and sampler, bit for bit.
template <class F>
inline Color<F> sample(const BoundTexture& bound, F u, F v, F dudx, F dvdx, F dudy, F dvdy,
                       unsigned channels = Texture::kRgba) {
  if constexpr (std::is_same_v<F, float>) {
    const glm::vec4 c = bound.texture()->sample(bound.sampler(), {u, v}, {dudx, dvdx}, {dudy, dvdy});
    return {c.r, c.g, c.b, c.a};
  } else {
    constexpr int N = simd::LaneCount<F>::value;
    alignas(64) float in[6][N];
    alignas(64) float out[4][N];
    u.store(in[0]);
    v.store(in[1]);
    dudx.store(in[2]);
    dvdx.store(in[3]);
    dudy.store(in[4]);
    dvdy.store(in[5]);
    bound.sample_batch(N,
                       {in[0], in[1], in[2], in[3], in[4], in[5], nullptr, out[0], out[1], out[2], out[3], channels});
    auto load = [&](int c) { return channels >> c & 1 ? F::load(out[c]) : F(0.0f); };
    return {load(0), load(1), load(2), load(3)};
  }
}

// The same for a texture and a sampler bound for this lookup alone.
template <class F>
inline Color<F> sample(const Texture& texture, const Sampler& s, F u, F v, F dudx, F dvdx, F dudy, F dvdy,
                       unsigned channels = Texture::kRgba) {
  if constexpr (std::is_same_v<F, float>) {
    const glm::vec4 c = texture.sample(s, {u, v}, {dudx, dvdx}, {dudy, dvdy});
    return {c.r, c.g, c.b, c.a};
  } else {
    return sample(BoundTexture(texture, s), u, v, dudx, dvdx, dudy, dvdy, channels);
  }
}

template <class F>
inline Color<F> sample_lod(const Texture& texture, const Sampler& s, F u, F v, F lod) {
  if constexpr (std::is_same_v<F, float>) {
    const glm::vec4 c = texture.sample_lod(s, {u, v}, lod);
    return {c.r, c.g, c.b, c.a};
  } else {
    constexpr int N = simd::LaneCount<F>::value;
    alignas(64) float in[3][N];
    alignas(64) float out[4][N];
    u.store(in[0]);
    v.store(in[1]);
    lod.store(in[2]);
    texture.sample_lod_batch(s, N,
                             {in[0], in[1], nullptr, nullptr, nullptr, nullptr, in[2], out[0], out[1], out[2], out[3]});
    return {F::load(out[0]), F::load(out[1]), F::load(out[2]), F::load(out[3])};
  }
}

}  // namespace softpbr::raster
