// Textures: mip chains, and lookups by the OpenGL specification's rules (see texture.h).
#include "softpbr/raster/texture.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "softpbr/raster/color.h"
#include "softpbr/raster/pool.h"
#include "softpbr/simd/isa.h"

namespace softpbr::raster {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct DecodeTables {
  std::array<float, 256> srgb;
  std::array<float, 256> unorm;
  // Each table's floats by byte: byte k of entry c at [256 k + c] (the lane kernel's
  // byte-permute decode).
  std::array<std::uint8_t, 1024> srgb_planes, unorm_planes;
};

DecodeTables make_tables() {
  DecodeTables d{};
  for (int k = 0; k < 256; ++k) {
    // srgb_to_linear is the exact curve in double (basic operations only); one rounding
    // to float.
    d.srgb[static_cast<std::size_t>(k)] = static_cast<float>(srgb_to_linear(k / 255.0));
    d.unorm[static_cast<std::size_t>(k)] = static_cast<float>(k) / 255.0f;
  }
  for (int c = 0; c < 256; ++c) {
    const auto s = std::bit_cast<std::uint32_t>(d.srgb[static_cast<std::size_t>(c)]);
    const auto u = std::bit_cast<std::uint32_t>(d.unorm[static_cast<std::size_t>(c)]);
    for (int k = 0; k < 4; ++k) {
      d.srgb_planes[static_cast<std::size_t>(256 * k + c)] = static_cast<std::uint8_t>(s >> (8 * k));
      d.unorm_planes[static_cast<std::size_t>(256 * k + c)] = static_cast<std::uint8_t>(u >> (8 * k));
    }
  }
  return d;
}

// Built on first use; inline, so that a lookup pays only the guard's test.
inline const DecodeTables& tables() {
  static const DecodeTables t = make_tables();
  return t;
}

// x when finite, else 0 (x − x is 0 only for finite x).
inline float finite_or_zero(float x) { return x - x == 0.0f ? x : 0.0f; }

// i mod size in [0, size): a mask for powers of two (every level of a power-of-two
// texture; two's complement makes it the non-negative remainder for negative i too), a
// division otherwise.
inline int repeat_index(int i, int size) {
  if ((size & (size - 1)) == 0) return i & (size - 1);
  const int r = i % size;
  return r < 0 ? r + size : r;
}

// Texel index i wrapped into [0, size) (OpenGL 4.6, §8.14.2).
inline int wrap_index(Wrap mode, int i, int size) {
  switch (mode) {
    case Wrap::ClampToEdge:
      return i < 0 ? 0 : (i >= size ? size - 1 : i);
    case Wrap::MirroredRepeat: {
      // (size − 1) − mirror((i mod 2·size) − size), mirror(a) = a ≥ 0 ? a : −(1 + a).
      const int r = repeat_index(i, 2 * size) - size;
      const int m = r >= 0 ? r : -(1 + r);
      return size - 1 - m;
    }
    case Wrap::Repeat:
    default:
      return repeat_index(i, size);
  }
}

// Texture coordinates are clamped to ±2^16 before scaling, so that coordinate × size
// (≤ 2^30) converts to int exactly; a float that large has no fraction left to filter.
constexpr float kMaxCoordinate = 65536.0f;
inline float coordinate(float x) { return std::clamp(finite_or_zero(x), -kMaxCoordinate, kMaxCoordinate); }

}  // namespace

const float* srgb8_decode_table() { return tables().srgb.data(); }
const float* unorm8_decode_table() { return tables().unorm.data(); }

namespace {
// lod_log2(), inline for the lookups (the same operations: the same bits).
inline float log2_of(float x) {
  if (x != x || x < 0.0f) return std::numeric_limits<float>::quiet_NaN();
  if (x == 0.0f) return -kInf;
  if (x == kInf) return kInf;
  int e = 0;
  if (x < std::numeric_limits<float>::min()) {  // subnormal: scale into the normal range
    x *= 16777216.0f;                            // 2^24
    e = -24;
  }
  const auto bits = std::bit_cast<std::uint32_t>(x);
  e += static_cast<int>((bits >> 23) & 0xffu) - 127;
  float m = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);  // [1, 2)
  if (m > 1.41421356f) {
    m *= 0.5f;
    ++e;
  }
  // log₂ m = (2 / ln 2) · atanh s, s = (m − 1)/(m + 1), |s| ≤ 0.1716: the series to s⁹
  // leaves under 4·10⁻⁹. m = 1 gives exactly 0, so powers of two are exact.
  const float s = (m - 1.0f) / (m + 1.0f);
  const float s2 = s * s;
  float p = 1.0f / 9.0f;
  p = p * s2 + 1.0f / 7.0f;
  p = p * s2 + 1.0f / 5.0f;
  p = p * s2 + 1.0f / 3.0f;
  p = p * s2 + 1.0f;
  constexpr float kTwoOverLn2 = 2.88539008f;  // 2 / ln 2
  return static_cast<float>(e) + s * p * kTwoOverLn2;
}
}  // namespace

float lod_log2(float x) { return log2_of(x); }

int mip_level_count(int width, int height) {
  int side = std::max(width, height);
  int count = 1;
  while (side > 1) {
    side >>= 1;
    ++count;
  }
  return count;
}

void validate(const Sampler& s) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("sampler: " + what); };
  if (static_cast<unsigned>(s.wrap_u) > 2) fail("wrap_u is not a wrap mode");
  if (static_cast<unsigned>(s.wrap_v) > 2) fail("wrap_v is not a wrap mode");
  if (static_cast<unsigned>(s.mag_filter) > 1) fail("mag_filter is not a filter");
  if (static_cast<unsigned>(s.min_filter) > 1) fail("min_filter is not a filter");
  if (static_cast<unsigned>(s.mip_filter) > 2) fail("mip_filter is not a mip filter");
  if (s.max_anisotropy < 1 || s.max_anisotropy > kMaxAnisotropy)
    fail("max_anisotropy " + std::to_string(s.max_anisotropy) + " is outside [1, 16]");
  if (!std::isfinite(s.lod_bias)) fail("lod_bias is not finite");
  if (std::isnan(s.min_lod) || std::isnan(s.max_lod)) fail("min_lod and max_lod must be numbers");
  if (s.min_lod > s.max_lod) fail("min_lod is above max_lod");
}

// ---- Construction ----------------------------------------------------------------------

void Texture::allocate_levels(int width, int height, bool mipmaps) {
  if (width < 1 || height < 1 || width > kMaxTextureSide || height > kMaxTextureSide)
    throw std::invalid_argument("texture: size " + std::to_string(width) + "x" + std::to_string(height) +
                                " is outside 1 … " + std::to_string(kMaxTextureSide) + " per side");
  const int count = mipmaps ? mip_level_count(width, height) : 1;
  std::size_t texels = 0;
  for (int l = 0; l < count; ++l) {
    const int w = std::max(1, width >> l), h = std::max(1, height >> l);
    levels_.push_back({w, h, texels});
    texels += static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  }
}

namespace {

// One axis of the downsampling filter from n texels to m = max(1, ⌊n/2⌋): destination
// texel i averages the source interval [i·n/m, (i+1)·n/m) exactly — a box over the
// footprint, with fractional weights at its ends when n is odd — so every level keeps
// the image's mean. In units of 1/m of a source texel the interval is [i·n, (i+1)·n) and
// source texel j is [j·m, (j+1)·m): the overlaps are integers, the weights overlap / n.
struct AxisFilter {
  struct Taps {
    int first;
    int count;
    std::array<float, 4> weight;
  };
  std::vector<Taps> taps;

  AxisFilter(int n, int m) : taps(static_cast<std::size_t>(m)) {
    for (int i = 0; i < m; ++i) {
      const long long lo = static_cast<long long>(i) * n, hi = lo + n;
      Taps& t = taps[static_cast<std::size_t>(i)];
      t.first = static_cast<int>(lo / m);
      t.count = 0;
      for (long long j = t.first; j * m < hi; ++j) {
        const long long overlap = std::min((j + 1) * m, hi) - std::max(j * m, lo);
        t.weight[static_cast<std::size_t>(t.count++)] = static_cast<float>(overlap) / static_cast<float>(n);
      }
    }
  }
};

// Builds level `dst` from level `src` (the stored texels, decoded): per destination row,
// the source rows are combined vertically, then that row horizontally, each sum in tap
// order — the same operations whichever thread runs the row.
template <class Fetch, class Store>
void downsample(const Texture::Level& src, const Texture::Level& dst, const Fetch& fetch, const Store& store,
                ThreadPool* pool) {
  const AxisFilter fx(src.width, dst.width), fy(src.height, dst.height);
  constexpr int kRowsPerJob = 8;
  const std::size_t jobs = static_cast<std::size_t>((dst.height + kRowsPerJob - 1) / kRowsPerJob);
  // Even sides (every level of a power-of-two texture but the last ones): AxisFilter(2m, m)
  // gives destination texel i the taps 2i and 2i + 1 with weight 1/2 each, so the sums
  // below are those of the general loop, term for term and in its order (0 + a·½ + b·½),
  // without the tap tables (test_texture.cpp compares both with a reference).
  const bool even = src.width % 2 == 0 && src.height % 2 == 0;
  auto run_even = [&](std::size_t job) {
    std::vector<float> row(static_cast<std::size_t>(src.width) * 4);
    const int y_end = std::min(dst.height, static_cast<int>(job + 1) * kRowsPerJob);
    for (int y = static_cast<int>(job) * kRowsPerJob; y < y_end; ++y) {
      for (int x = 0; x < src.width; ++x) {
        float a[4], b[4];
        fetch(x, 2 * y, a);
        fetch(x, 2 * y + 1, b);
        float* r = row.data() + 4 * x;
        for (int ch = 0; ch < 4; ++ch) r[ch] = (0.0f + a[ch] * 0.5f) + b[ch] * 0.5f;
      }
      for (int x = 0; x < dst.width; ++x) {
        const float* c = row.data() + 8 * x;
        float acc[4];
        for (int ch = 0; ch < 4; ++ch) acc[ch] = (0.0f + c[ch] * 0.5f) + c[4 + ch] * 0.5f;
        store(x, y, acc);
      }
    }
  };
  auto run = [&](std::size_t job) {
    if (even) {
      run_even(job);
      return;
    }
    std::vector<float> row(static_cast<std::size_t>(src.width) * 4);
    const int y_end = std::min(dst.height, static_cast<int>(job + 1) * kRowsPerJob);
    for (int y = static_cast<int>(job) * kRowsPerJob; y < y_end; ++y) {
      const AxisFilter::Taps& ty = fy.taps[static_cast<std::size_t>(y)];
      for (int x = 0; x < src.width; ++x) {
        float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int k = 0; k < ty.count; ++k) {
          float c[4];
          fetch(x, ty.first + k, c);
          const float w = ty.weight[static_cast<std::size_t>(k)];
          for (int ch = 0; ch < 4; ++ch) acc[ch] += c[ch] * w;
        }
        std::copy(acc, acc + 4, row.begin() + 4 * x);
      }
      for (int x = 0; x < dst.width; ++x) {
        const AxisFilter::Taps& tx = fx.taps[static_cast<std::size_t>(x)];
        float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        for (int k = 0; k < tx.count; ++k) {
          const float* c = row.data() + 4 * (tx.first + k);
          const float w = tx.weight[static_cast<std::size_t>(k)];
          for (int ch = 0; ch < 4; ++ch) acc[ch] += c[ch] * w;
        }
        store(x, y, acc);
      }
    }
  };
  // Small levels are not worth waking the pool for.
  const std::size_t work = static_cast<std::size_t>(src.width) * static_cast<std::size_t>(src.height);
  if (pool != nullptr && work >= (std::size_t{1} << 16)) {
    pool->parallel_for(jobs, run);
  } else {
    for (std::size_t j = 0; j < jobs; ++j) run(j);
  }
}

}  // namespace

std::size_t Texture::levels8(const image::ImageView8& image, const TextureOptions& options) {
  image::check_pixels(image, "texture");
  if (space_ != ColorSpace::Linear && space_ != ColorSpace::Srgb)
    throw std::invalid_argument("texture: colour space is neither linear nor sRGB");
  allocate_levels(image.width, image.height, options.mipmaps);
  return (levels_.back().offset + static_cast<std::size_t>(levels_.back().width) *
                                      static_cast<std::size_t>(levels_.back().height)) * 4;
}

Texture::Texture(const image::ImageView8& image, ColorSpace space, const TextureOptions& options, ThreadPool* pool)
    : space_(space) {
  texels8_.resize(levels8(image, options));
  std::copy(image.rgba.begin(), image.rgba.end(), texels8_.begin());
  build_mips8(pool);
}

Texture::Texture(image::Image8&& image, ColorSpace space, const TextureOptions& options, ThreadPool* pool)
    : space_(space) {
  const std::size_t bytes = levels8(image, options);
  texels8_ = std::move(image.rgba);  // level 0 is at offset 0, in the image's row order
  image.width = image.height = 0;
  texels8_.resize(bytes);  // within the capacity: no copy
  build_mips8(pool);
}

std::size_t Texture::rgba8_chain_bytes(int width, int height) {
  if (width < 1 || height < 1 || width > kMaxTextureSide || height > kMaxTextureSide) return 0;
  std::size_t texels = 0;
  for (int l = 0; l < mip_level_count(width, height); ++l)
    texels += static_cast<std::size_t>(std::max(1, width >> l)) * static_cast<std::size_t>(std::max(1, height >> l));
  return texels * 4;
}

Texture::Texture(image::Image8&& image, std::span<const image::Image8> more_levels, ColorSpace space,
                 const TextureOptions& options, ThreadPool* pool)
    : space_(space) {
  const std::size_t bytes = levels8(image, options);
  const std::size_t given = std::min(more_levels.size(), levels_.size() - 1);
  for (std::size_t l = 0; l < given; ++l) {
    const Level& level = levels_[l + 1];
    image::check_pixels(more_levels[l], "texture level " + std::to_string(l + 1));
    if (more_levels[l].width != level.width || more_levels[l].height != level.height)
      throw std::invalid_argument("texture: level " + std::to_string(l + 1) + " is " + std::to_string(more_levels[l].width) +
                                  "x" + std::to_string(more_levels[l].height) + ", not " + std::to_string(level.width) + "x" +
                                  std::to_string(level.height));
  }
  texels8_ = std::move(image.rgba);
  image.width = image.height = 0;
  texels8_.resize(bytes);
  for (std::size_t l = 0; l < given; ++l)
    std::copy(more_levels[l].rgba.begin(), more_levels[l].rgba.end(), texels8_.begin() + static_cast<std::ptrdiff_t>(levels_[l + 1].offset * 4));
  build_mips8(pool, given + 1);
}

void Texture::build_mips8(ThreadPool* pool, std::size_t first) {
  const ColorSpace space = space_;
  rgb_table_ = space == ColorSpace::Srgb ? srgb8_decode_table() : unorm8_decode_table();
  const float* alpha_table = unorm8_decode_table();
  for (std::size_t l = first; l < levels_.size(); ++l) {
    const Level& src = levels_[l - 1];
    const Level& dst = levels_[l];
    const std::uint8_t* in = texels8_.data() + src.offset * 4;
    std::uint8_t* out = texels8_.data() + dst.offset * 4;
    const float* rgb = rgb_table_;
    auto fetch = [&](int x, int y, float c[4]) {
      const std::uint8_t* p = in + (static_cast<std::size_t>(y) * static_cast<std::size_t>(src.width) +
                                    static_cast<std::size_t>(x)) * 4;
      c[0] = rgb[p[0]];
      c[1] = rgb[p[1]];
      c[2] = rgb[p[2]];
      c[3] = alpha_table[p[3]];
    };
    const bool srgb = space == ColorSpace::Srgb;
    auto store = [&](int x, int y, const float c[4]) {
      std::uint8_t* p = out + (static_cast<std::size_t>(y) * static_cast<std::size_t>(dst.width) +
                               static_cast<std::size_t>(x)) * 4;
      for (int ch = 0; ch < 3; ++ch) p[ch] = srgb ? linear_to_srgb8(c[ch]) : unorm8(c[ch]);
      p[3] = unorm8(c[3]);
    };
    downsample(src, dst, fetch, store, pool);
  }
}

Texture::Texture(const image::ImageViewF& image, const TextureOptions& options, ThreadPool* pool) {
  image::check_pixels(image, "texture");
  for (float x : image.rgba)
    if (!std::isfinite(x)) throw std::invalid_argument("texture: a float texel is not finite");
  allocate_levels(image.width, image.height, options.mipmaps);
  const std::size_t texels = levels_.back().offset + static_cast<std::size_t>(levels_.back().width) *
                                                          static_cast<std::size_t>(levels_.back().height);
  texels_f_.resize(texels * 4);
  std::copy(image.rgba.begin(), image.rgba.end(), texels_f_.begin());
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    const Level& src = levels_[l - 1];
    const Level& dst = levels_[l];
    const float* in = texels_f_.data() + src.offset * 4;
    float* out = texels_f_.data() + dst.offset * 4;
    auto fetch = [&](int x, int y, float c[4]) {
      const float* p = in + (static_cast<std::size_t>(y) * static_cast<std::size_t>(src.width) +
                             static_cast<std::size_t>(x)) * 4;
      std::copy(p, p + 4, c);
    };
    auto store = [&](int x, int y, const float c[4]) {
      std::copy(c, c + 4, out + (static_cast<std::size_t>(y) * static_cast<std::size_t>(dst.width) +
                                 static_cast<std::size_t>(x)) * 4);
    };
    downsample(src, dst, fetch, store, pool);
  }
}

// ---- Lookups ---------------------------------------------------------------------------

namespace detail {
std::atomic<bool> texture_vbmi_allowed{true};
void allow_texture_vbmi(bool allowed) { texture_vbmi_allowed.store(allowed, std::memory_order_relaxed); }
}  // namespace detail

}  // namespace softpbr::raster

// detail::{avx2, avx512}::sample_lanes() (the baseline copy has none unless the build
// itself targets AVX); sample_batch() runs the AVX-512 copy (16 lanes) where the CPU has
// it, else the AVX2 copy (8 lanes): the same bits. And detail::avx512vbmi::sample_lanes():
// the AVX-512 kernel with its table lookups done by VBMI's byte permutes, run in place of
// detail::avx512's where the CPU has VBMI. Pure data movement: the same bits
// (tests/test_texture_lanes.cpp runs both).
#define SOFTPBR_TARGET_FILE "texture-inl.h"
#define SOFTPBR_TARGET_ALSO_VBMI
#include "softpbr/simd/foreach_target.h"

namespace softpbr::raster {

namespace {

struct Rgba {
  float c[4];
};

// The samplers of the fast paths: repeat both ways, every filter linear (any anisotropy).
inline bool repeat_trilinear(const Sampler& s) {
  return s.wrap_u == Wrap::Repeat && s.wrap_v == Wrap::Repeat && s.mag_filter == Filter::Linear &&
         s.min_filter == Filter::Linear && s.mip_filter == MipFilter::Linear;
}
inline bool power_of_two(int x) { return (x & (x - 1)) == 0; }  // for x ≥ 1

// The four channels of a texel or of a filtered value in one vector (GCC/Clang vector
// extension): every operation is element-wise, so each channel gets the IEEE operation the
// scalar code gives it, in the same order (no contraction: -ffp-contract=off).
typedef float Rgba4 __attribute__((vector_size(16)));

inline Rgba to_rgba(const Rgba4& v) { return {{v[0], v[1], v[2], v[3]}}; }

// std::floor(x) as an int and as a float, for x in (−2^31, 2^31) other than −0: the
// truncation, one less when it lies above x. Every float of magnitude 2^23 or more is an
// integer, so the conversions are exact and the float is floor's value; its sign is
// floor's too (only floor(−0) is −0). The fast path's arguments qualify: x − 0.5 of a
// clamped coordinate times a side (|x| ≤ 2^30 + 1, and a difference is −0 only for
// −0 − +0), and λ in (0, 15). Baseline x86-64 has no floor instruction (roundss is
// SSE4.1): this is four instructions against GCC's sixteen.
struct Floor {
  int i;
  float f;
};
inline Floor floor_of(float x) {
  int i = static_cast<int>(x);
  if (static_cast<float>(i) > x) --i;
  return {i, static_cast<float>(i)};
}

// The internals of a lookup, shared by the scalar and batch entry points.
class Lookup {
 public:
  explicit Lookup(const Texture& t)
      : levels_(t.levels()),
        t8_(t.is_float() ? nullptr : t.texels8().data()),
        tf_(t.is_float() ? t.texels_f().data() : nullptr),
        rgb_(t.rgb_decode_table()),
        alpha_(unorm8_decode_table()) {}

  Rgba fetch(const Texture::Level& lv, int x, int y) const {
    const std::size_t i = lv.offset + static_cast<std::size_t>(y) * static_cast<std::size_t>(lv.width) +
                          static_cast<std::size_t>(x);
    if (tf_ != nullptr) {
      const float* p = tf_ + i * 4;
      return {{p[0], p[1], p[2], p[3]}};
    }
    const std::uint8_t* p = t8_ + i * 4;
    return {{rgb_[p[0]], rgb_[p[1]], rgb_[p[2]], alpha_[p[3]]}};
  }

  // One level, one filter (§8.14.2: nearest reads the texel holding the point; linear
  // blends the four around it, texel centres at half-integers).
  Rgba filter_level(const Sampler& s, int level, Filter filter, float u, float v) const {
    const Texture::Level& lv = levels_[static_cast<std::size_t>(level)];
    const float x = coordinate(u) * static_cast<float>(lv.width);
    const float y = coordinate(v) * static_cast<float>(lv.height);
    if (filter == Filter::Nearest) {
      const int i = wrap_index(s.wrap_u, static_cast<int>(std::floor(x)), lv.width);
      const int j = wrap_index(s.wrap_v, static_cast<int>(std::floor(y)), lv.height);
      return fetch(lv, i, j);
    }
    const float xs = x - 0.5f, ys = y - 0.5f;
    const float x0 = std::floor(xs), y0 = std::floor(ys);
    const float ax = xs - x0, ay = ys - y0;  // exact
    const int i0 = static_cast<int>(x0), j0 = static_cast<int>(y0);
    const int ia = wrap_index(s.wrap_u, i0, lv.width), ib = wrap_index(s.wrap_u, i0 + 1, lv.width);
    const int ja = wrap_index(s.wrap_v, j0, lv.height), jb = wrap_index(s.wrap_v, j0 + 1, lv.height);
    const Rgba c00 = fetch(lv, ia, ja), c10 = fetch(lv, ib, ja);
    const Rgba c01 = fetch(lv, ia, jb), c11 = fetch(lv, ib, jb);
    const float bx = 1.0f - ax, by = 1.0f - ay;
    Rgba out;
    for (int ch = 0; ch < 4; ++ch) {
      const float top = c00.c[ch] * bx + c10.c[ch] * ax;
      const float bottom = c01.c[ch] * bx + c11.c[ch] * ax;
      out.c[ch] = top * by + bottom * ay;
    }
    return out;
  }

  // At a level of detail λ already biased and clamped (§8.14: λ ≤ 0 magnifies; §8.14.3:
  // the mip levels).
  Rgba at_lod(const Sampler& s, float lod, float u, float v) const {
    if (!(lod > 0.0f)) return filter_level(s, 0, s.mag_filter, u, v);
    const int q = static_cast<int>(levels_.size()) - 1;
    const float fq = static_cast<float>(q);
    switch (s.mip_filter) {
      case MipFilter::None:
        return filter_level(s, 0, s.min_filter, u, v);
      case MipFilter::Nearest: {
        int d = 0;
        if (lod > 0.5f) d = lod < fq + 0.5f ? static_cast<int>(std::ceil(lod + 0.5f)) - 1 : q;
        return filter_level(s, d, s.min_filter, u, v);
      }
      case MipFilter::Linear:
      default: {
        if (!(lod < fq)) return filter_level(s, q, s.min_filter, u, v);
        const float f = std::floor(lod);
        const int d1 = static_cast<int>(f);
        const float t = lod - f;  // exact
        const Rgba a = filter_level(s, d1, s.min_filter, u, v);
        const Rgba b = filter_level(s, d1 + 1, s.min_filter, u, v);
        Rgba out;
        for (int ch = 0; ch < 4; ++ch) out.c[ch] = a.c[ch] * (1.0f - t) + b.c[ch] * t;
        return out;
      }
    }
  }

  float clamp_lod(const Sampler& s, float lod) const {
    // −∞ (zero derivatives) stays below min_lod; NaN cannot occur (inputs are sanitized).
    const float biased = lod + s.lod_bias;
    return std::clamp(biased, s.min_lod, s.max_lod);
  }

  Texture::Footprint footprint(const Sampler& s, float dudx, float dvdx, float dudy, float dvdy, float bias,
                               float* major_u, float* major_v) const {
    const float w = static_cast<float>(levels_[0].width), h = static_cast<float>(levels_[0].height);
    dudx = finite_or_zero(dudx);
    dvdx = finite_or_zero(dvdx);
    dudy = finite_or_zero(dudy);
    dvdy = finite_or_zero(dvdy);
    const float ux = dudx * w, vx = dvdx * h, uy = dudy * w, vy = dvdy * h;
    const float px = std::sqrt(ux * ux + vx * vx);  // may be +∞ for huge derivatives
    const float py = std::sqrt(uy * uy + vy * vy);
    const bool x_major = !(px < py);
    const float pmax = x_major ? px : py, pmin = x_major ? py : px;
    if (major_u != nullptr) {
      *major_u = x_major ? dudx : dudy;
      *major_v = x_major ? dvdx : dvdy;
    }
    int probes = 1;
    if (s.max_anisotropy > 1 && pmax > 0.0f) {
      const float ratio = pmax / pmin;  // +∞ for pmin = 0; NaN for ∞/∞
      const float limit = static_cast<float>(s.max_anisotropy);
      probes = ratio < limit ? static_cast<int>(std::ceil(ratio)) : s.max_anisotropy;
    }
    const float lod = log2_of(probes > 1 ? pmax / static_cast<float>(probes) : pmax);
    return {clamp_lod(s, lod + finite_or_zero(bias)), probes};
  }

  Rgba sample(const Sampler& s, float u, float v, float dudx, float dvdx, float dudy, float dvdy, float bias) const {
    float mu = 0.0f, mv = 0.0f;
    const Texture::Footprint fp = footprint(s, dudx, dvdx, dudy, dvdy, bias, &mu, &mv);
    if (fp.probes == 1) return at_lod(s, fp.lod, u, v);
    // EXT_texture_filter_anisotropic: the mean of N probes at u + d·(i/(N + 1) − ½),
    // i = 1 … N, along the major axis d of the footprint.
    u = coordinate(u);
    v = coordinate(v);
    const float n1 = static_cast<float>(fp.probes + 1);
    Rgba sum{{0.0f, 0.0f, 0.0f, 0.0f}};
    for (int i = 1; i <= fp.probes; ++i) {
      const float t = static_cast<float>(i) / n1 - 0.5f;
      const Rgba c = at_lod(s, fp.lod, u + mu * t, v + mv * t);
      for (int ch = 0; ch < 4; ++ch) sum.c[ch] += c.c[ch];
    }
    const float n = static_cast<float>(fp.probes);
    for (float& c : sum.c) c /= n;
    return sum;
  }

  // ---- The fast path ----
  // An 8-bit texture read through a sampler that repeats in both directions and filters
  // linearly everywhere (trilinear; isotropic or anisotropic): the general code's
  // operations on the values it computes, without its per-texel branches on the format,
  // the wrap modes and the filters, with the mask for power-of-two wraps, the second index
  // of each pair from the first, the coordinates clamped once for both levels, the
  // channels as one vector and log₂ inline. The same bits (tests/test_texture.cpp, the
  // textured goldens).
  bool fast(const Sampler& s) const { return t8_ != nullptr && repeat_trilinear(s); }

  Rgba4 decode(const std::uint8_t* p) const { return Rgba4{rgb_[p[0]], rgb_[p[1]], rgb_[p[2]], alpha_[p[3]]}; }

  // filter_level(s, level, Filter::Linear, u, v) with both wraps Repeat, for cu =
  // coordinate(u), cv = coordinate(v).
  Rgba4 bilinear_repeat(int level, float cu, float cv) const {
    const Texture::Level& lv = levels_[static_cast<std::size_t>(level)];
    const float x = cu * static_cast<float>(lv.width);
    const float y = cv * static_cast<float>(lv.height);
    const float xs = x - 0.5f, ys = y - 0.5f;
    const Floor x0 = floor_of(xs), y0 = floor_of(ys);
    const float ax = xs - x0.f, ay = ys - y0.f;  // exact
    const int ia = repeat_index(x0.i, lv.width), ja = repeat_index(y0.i, lv.height);
    const int ib = ia + 1 == lv.width ? 0 : ia + 1, jb = ja + 1 == lv.height ? 0 : ja + 1;
    const std::size_t w = static_cast<std::size_t>(lv.width);
    const std::uint8_t* row_a = t8_ + (lv.offset + static_cast<std::size_t>(ja) * w) * 4;
    const std::uint8_t* row_b = t8_ + (lv.offset + static_cast<std::size_t>(jb) * w) * 4;
    const std::size_t xa = static_cast<std::size_t>(ia) * 4, xb = static_cast<std::size_t>(ib) * 4;
    const Rgba4 c00 = decode(row_a + xa), c10 = decode(row_a + xb);
    const Rgba4 c01 = decode(row_b + xa), c11 = decode(row_b + xb);
    const float bx = 1.0f - ax, by = 1.0f - ay;
    const Rgba4 top = c00 * bx + c10 * ax;
    const Rgba4 bottom = c01 * bx + c11 * ax;
    return top * by + bottom * ay;
  }

  // at_lod() for the fast path's samplers.
  Rgba4 trilinear_repeat(float lod, float u, float v) const {
    const float cu = coordinate(u), cv = coordinate(v);
    if (!(lod > 0.0f)) return bilinear_repeat(0, cu, cv);
    const int q = static_cast<int>(levels_.size()) - 1;
    if (!(lod < static_cast<float>(q))) return bilinear_repeat(q, cu, cv);
    const Floor f = floor_of(lod);
    const int d1 = f.i;
    const float t = lod - f.f;  // exact
    const Rgba4 a = bilinear_repeat(d1, cu, cv);
    const Rgba4 b = bilinear_repeat(d1 + 1, cu, cv);
    return a * (1.0f - t) + b * t;
  }

  // sample() for the fast path's samplers.
  Rgba4 sample_fast(const Sampler& s, float u, float v, float dudx, float dvdx, float dudy, float dvdy,
                    float bias) const {
    float mu = 0.0f, mv = 0.0f;
    const Texture::Footprint fp = footprint(s, dudx, dvdx, dudy, dvdy, bias, &mu, &mv);
    if (fp.probes == 1) return trilinear_repeat(fp.lod, u, v);
    u = coordinate(u);
    v = coordinate(v);
    const float n1 = static_cast<float>(fp.probes + 1);
    Rgba4 sum = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int i = 1; i <= fp.probes; ++i) {
      const float t = static_cast<float>(i) / n1 - 0.5f;
      sum = sum + trilinear_repeat(fp.lod, u + mu * t, v + mv * t);
    }
    return sum / static_cast<float>(fp.probes);
  }

  Rgba sample_lod(const Sampler& s, float u, float v, float lod) const {
    // An explicit λ that is NaN reads as 0; ±∞ clamps to the limits.
    return at_lod(s, clamp_lod(s, lod != lod ? 0.0f : lod), u, v);
  }

 private:
  std::span<const Texture::Level> levels_;
  const std::uint8_t* t8_;
  const float* tf_;
  const float* rgb_;
  const float* alpha_;
};

inline glm::vec4 to_vec4(const Rgba& c) { return {c.c[0], c.c[1], c.c[2], c.c[3]}; }

}  // namespace


glm::vec4 Texture::texel(int level, int x, int y) const {
  return to_vec4(Lookup(*this).fetch(levels_[static_cast<std::size_t>(level)], x, y));
}

glm::vec4 Texture::sample(const Sampler& s, glm::vec2 uv, glm::vec2 dx, glm::vec2 dy, float bias) const {
  const Lookup lookup(*this);
  if (lookup.fast(s)) return to_vec4(to_rgba(lookup.sample_fast(s, uv.x, uv.y, dx.x, dx.y, dy.x, dy.y, bias)));
  return to_vec4(lookup.sample(s, uv.x, uv.y, dx.x, dx.y, dy.x, dy.y, bias));
}

glm::vec4 Texture::sample_lod(const Sampler& s, glm::vec2 uv, float lod) const {
  return to_vec4(Lookup(*this).sample_lod(s, uv.x, uv.y, lod));
}

Texture::Footprint Texture::footprint(const Sampler& s, glm::vec2 dx, glm::vec2 dy, float bias) const {
  return Lookup(*this).footprint(s, dx.x, dx.y, dy.x, dy.y, bias, nullptr, nullptr);
}

Texture::LaneKernel Texture::lane_kernel([[maybe_unused]] const Sampler& s, [[maybe_unused]] simd::Isa isa,
                                         [[maybe_unused]] detail::LaneTexture& lanes) const {
#if SOFTPBR_SIMD_X86_TARGETS
  if (!is_float() && repeat_trilinear(s) && power_of_two(width()) && power_of_two(height()) &&
      isa != simd::Isa::Baseline) {
    lanes = {texels8_.data(),
             rgb_table_,
             tables().unorm.data(),
             levels_.data(),
             static_cast<int>(levels_.size()) - 1,
             static_cast<float>(width()),
             static_cast<float>(height()),
             s.lod_bias,
             s.min_lod,
             s.max_lod,
             s.max_anisotropy,
             space_ == ColorSpace::Srgb ? tables().srgb_planes.data() : tables().unorm_planes.data()};
    // 16 lanes at once with AVX-512 (with VBMI where the CPU has it and tests allow),
    // else 8.
    if (isa == simd::Isa::Avx512 && detail::texture_vbmi_allowed.load(std::memory_order_relaxed) &&
        simd::cpu_has_avx512_vbmi())
      return detail::avx512vbmi::sample_lanes;
    if (isa == simd::Isa::Avx512) return detail::avx512::sample_lanes;
    return detail::avx2::sample_lanes;
  }
#endif
  return nullptr;
}

void Texture::sample_batch(const Sampler& s, int n, const Batch& b, simd::Isa isa) const {
  detail::LaneTexture lanes;
  if (const LaneKernel kernel = lane_kernel(s, isa, lanes)) {
    kernel(lanes, n, b);
    return;
  }
  const Lookup lookup(*this);
  if (lookup.fast(s)) {
    for (int i = 0; i < n; ++i) {
      const Rgba4 c = lookup.sample_fast(s, b.u[i], b.v[i], b.dudx[i], b.dvdx[i], b.dudy[i], b.dvdy[i], 0.0f);
      b.r[i] = c[0];
      b.g[i] = c[1];
      b.b[i] = c[2];
      b.a[i] = c[3];
    }
    return;
  }
  for (int i = 0; i < n; ++i) {
    const Rgba c = lookup.sample(s, b.u[i], b.v[i], b.dudx[i], b.dvdx[i], b.dudy[i], b.dvdy[i], 0.0f);
    b.r[i] = c.c[0];
    b.g[i] = c.c[1];
    b.b[i] = c.c[2];
    b.a[i] = c.c[3];
  }
}

void Texture::sample_lod_batch(const Sampler& s, int n, const Batch& b) const {
  const Lookup lookup(*this);
  for (int i = 0; i < n; ++i) {
    const Rgba c = lookup.sample_lod(s, b.u[i], b.v[i], b.lod[i]);
    b.r[i] = c.c[0];
    b.g[i] = c.c[1];
    b.b[i] = c.c[2];
    b.a[i] = c.c[3];
  }
}

}  // namespace softpbr::raster
