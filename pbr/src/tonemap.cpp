// Tone mapping and output (see tonemap.h).
#include "softpbr/pbr/tonemap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "softpbr/raster/color.h"
#include "softpbr/check.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/simd/dispatch.h"
#include "softpbr/simd/simd.h"
#include "tone_map_operators.h"

namespace softpbr::pbr {

std::optional<ToneMap> tone_map_from_name(std::string_view name) {
  if (name == "none") return ToneMap::None;
  if (name == "reinhard") return ToneMap::Reinhard;
  if (name == "aces") return ToneMap::Aces;
  if (name == "neutral") return ToneMap::Neutral;
  return std::nullopt;
}

std::string_view tone_map_name(ToneMap op) {
  switch (op) {
    case ToneMap::None: return "none";
    case ToneMap::Reinhard: return "reinhard";
    case ToneMap::Aces: return "aces";
    default: return "neutral";
  }
}

std::optional<Resolve> resolve_from_name(std::string_view name) {
  if (name == "tonemapped") return Resolve::ToneMapped;
  if (name == "linear") return Resolve::Linear;
  return std::nullopt;
}

std::string_view resolve_name(Resolve r) { return r == Resolve::Linear ? "linear" : "tonemapped"; }

glm::vec3 apply_tone_map(ToneMap op, glm::vec3 c) {
  using tone_map_operators::tone_map;
  switch (op) {
    case ToneMap::None: tone_map<ToneMap::None>(c.r, c.g, c.b); break;
    case ToneMap::Reinhard: tone_map<ToneMap::Reinhard>(c.r, c.g, c.b); break;
    case ToneMap::Aces: tone_map<ToneMap::Aces>(c.r, c.g, c.b); break;
    default: tone_map<ToneMap::Neutral>(c.r, c.g, c.b); break;
  }
  return c;
}

std::array<float, 255> transfer_thresholds(float gamma) {
  if (gamma == 0.0f) return raster::srgb8_thresholds();
  std::array<float, 255> t{};
  for (int k = 0; k < 255; ++k) t[k] = static_cast<float>(dmath::pow((k + 0.5) / 255.0, gamma));
  return t;
}

namespace {
std::uint8_t encode(const std::array<float, 255>& t, float v) {
  if (!(v >= t[0])) return 0;  // NaN too
  return static_cast<std::uint8_t>(std::upper_bound(t.begin(), t.end(), v) - t.begin());
}
float exposure_scale(float stops) {
  if (!std::isfinite(stops)) throw std::invalid_argument("exposure: must be a finite number of stops");
  return static_cast<float>(dmath::exp2(stops));
}
}  // namespace

namespace {
OutputSettings checked(const OutputSettings& s) {
  if (!(s.gamma >= 0.0f) || !std::isfinite(s.gamma))
    throw std::invalid_argument("gamma: must be 0 (sRGB) or a positive number");
  return s;
}
}  // namespace

namespace {
// Positive floats order as their bits, so key k = bits >> 16 covers the values from
// float(k << 16) up to the next key's start; keys up to that of 1.0f cover [0, 1].
constexpr std::uint32_t kLastKey = 0x3f800000u >> 16;
// The key of v (its sign bit dropped: below 1 only −0 reaches the table with it set),
// clamped to the table: any float gives an index inside it.
inline std::uint32_t table_key(float v) {
  return std::min((std::bit_cast<std::uint32_t>(v) & 0x7fffffffu) >> 16, kLastKey);
}
}  // namespace

ToneMapper::ToneMapper(const OutputSettings& s)
    : settings_(checked(s)), scale_(exposure_scale(s.exposure)), thresholds_(transfer_thresholds(s.gamma)) {
  if (s.resolve == Resolve::ToneMapped && !(s.tone_map == ToneMap::None && scale_ == 1.0f))
    display_ = std::make_shared<const ToneMapper>(OutputSettings{0.0f, ToneMap::None, s.gamma, Resolve::ToneMapped});
  first_.resize(kLastKey + 1);
  std::size_t below = 0;
  for (std::uint32_t k = 0; k <= kLastKey; ++k) {
    const float start = std::bit_cast<float>(k << 16);
    while (below < thresholds_.size() && thresholds_[below] < start) ++below;
    first_[k] = static_cast<std::uint8_t>(below);
  }
  // Steps a key below 1 needs: the thresholds ≤ its largest value that its table entry
  // does not count. No float lies between a key's largest value and the next key's start,
  // so those are the thresholds < the next key's start: first_[k + 1] − first_[k]. The
  // lanes kernels encode v ≥ 1 as 255, which is the count only while no threshold exceeds
  // 1 (true of every curve: (k + 0.5)/255 < 1 raised to a positive power); otherwise they
  // binary-search every value.
  int most = 0;
  for (std::uint32_t k = 0; k < kLastKey; ++k) most = std::max(most, first_[k + 1] - first_[k]);
  steps_ = most <= kMaxSteps && thresholds_.back() <= 1.0f ? most : -1;
  std::copy(thresholds_.begin(), thresholds_.end(), padded_.begin());
  std::fill(padded_.begin() + 255, padded_.end(), std::numeric_limits<float>::infinity());
  if (steps_ == 0 || steps_ == 1) {
    // A threshold inside key k shares its top 16 bits, so v ≥ it compares as their low 16
    // bits; 0x10000 is above every value's. The last key (1.0f and, clamped, everything
    // above or NaN) is only looked up by values whose code the kernels override.
    packed_base_ = table_key(thresholds_[0]);
    packed_.resize(kLastKey - packed_base_ + 1);
    for (std::uint32_t k = packed_base_; k <= kLastKey; ++k) {
      const bool holds = k < kLastKey && first_[k + 1] > first_[k];
      const std::uint32_t low = holds ? std::bit_cast<std::uint32_t>(thresholds_[first_[k]]) & 0xffffu : 0x10000u;
      packed_[k - packed_base_] = static_cast<std::uint32_t>(first_[k]) << 17 | low;
    }
  }
}

namespace {
// The code of v: first[] gives the thresholds below v's key, then a step or two.
inline std::uint8_t encode_fast(const std::array<float, 255>& t, const std::uint8_t* first, float v) {
  if (!(v >= t[0])) return 0;  // NaN too
  if (!(v < 1.0f)) return encode(t, v);
  unsigned k = first[table_key(v)];  // v = −0 when t[0] = 0 (gamma ≳ 17) has the sign bit
  while (k < t.size() && t[k] <= v) ++k;
  return static_cast<std::uint8_t>(k);
}

template <ToneMap kOp>
void encode_rect(const raster::Target& target, int x0, int y0, int x1, int y1, float scale,
                 const std::array<float, 255>& t, const std::uint8_t* first, raster::Image8& image) {
  const std::size_t width = static_cast<std::size_t>(target.width());
  const glm::vec4* colors = target.colors().data();
  // Runs of equal pixels (the background) are common: the previous pixel's code is reused
  // when the float bits are the same, which changes no byte.
  glm::vec4 last;
  std::uint8_t last_code[4] = {0, 0, 0, 0};
  bool have_last = false;
  for (int y = y0; y < y1; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * width;
    std::uint8_t* out = image.rgba.data() + (row + static_cast<std::size_t>(x0)) * 4;
    for (int x = x0; x < x1; ++x, out += 4) {
      const glm::vec4& c = colors[row + static_cast<std::size_t>(x)];
      if (!have_last || std::memcmp(&c, &last, sizeof c) != 0) {
        glm::vec3 m = glm::vec3(c) * scale;
        tone_map_operators::tone_map<kOp>(m.r, m.g, m.b);
        last_code[0] = encode_fast(t, first, m.r);
        last_code[1] = encode_fast(t, first, m.g);
        last_code[2] = encode_fast(t, first, m.b);
        last_code[3] = raster::unorm8(c.a);
        last = c;
        have_last = true;
      }
      std::memcpy(out, last_code, 4);
    }
  }
}

// --- The lanes kernels: encode_rect's transform on simd::Vec<N>, N pixels at a time. ---

// What a kernel needs of the ToneMapper.
struct Curve {
  const float* t;             // the thresholds, then kMaxSteps × +Inf
  const std::uint8_t* first;  // ToneMapper::first_
  float t0;                   // t[0]: below it (and NaN) the code is 0
  int steps;                  // ToneMapper::steps_ (−1: binary search)
  const std::uint32_t* packed;  // ToneMapper::packed_ (null when empty)
  std::uint32_t packed_base;
};

// kSteps of the kernels for a curve with a packed table (ToneMapper::packed_).
constexpr int kPacked = -2;

struct Job {
  const raster::Target* target;
  int x0, y0, x1, y1;
  float scale;
  Curve curve;
  raster::Image8* image;
};

// encode_fast without branches: the number of thresholds ≤ v, 0 for NaN. kSteps: how many
// steps after the table (1 or 2, known when compiled; 0: `steps`, known at run time; −1:
// the binary search instead of the table).
template <int kSteps>
inline unsigned code_of(const float* t, const std::uint8_t* first, float t0, int steps, float v) {
  unsigned k;
  if constexpr (kSteps >= 0) {
    k = first[table_key(v)];
    const int n = kSteps > 0 ? kSteps : steps;
    for (int s = 0; s < n; ++s) k += t[k] <= v ? 1u : 0u;
    k = v < 1.0f ? k : 255u;  // every threshold is ≤ 1 here (see the constructor)
  } else {
    // Binary search over the 255 thresholds plus a virtual +Inf at 255: after the steps
    // 128 … 1, k counts the thresholds ≤ v (indices read stay ≤ 254).
    k = 0;
    for (unsigned step = 128; step != 0; step >>= 1) k += t[k + step - 1] <= v ? step : 0u;
  }
  return v >= t0 ? k : 0u;  // NaN fails the comparison
}

// A multisampled rectangle to resolve (ToneMapper::resolve, Resolve::ToneMapped) into
// `out`, out_width pixels a row.
struct ResolveJob {
  const raster::TargetPixels* pixels;
  int x0, y0, x1, y1;
  float scale;
  glm::vec4* out;
  std::size_t out_width;
};

// The mean of kS values, as raster::resolve_box sums them: pairwise in sample order.
template <int kS, class F>
inline F box_mean(const F (&v)[kS]) {
  if constexpr (kS == 4) return ((v[0] + v[1]) + (v[2] + v[3])) * F(0.25f);
  else return (((v[0] + v[1]) + (v[2] + v[3])) + ((v[4] + v[5]) + (v[6] + v[7]))) * F(0.125f);
}

// Resolve::ToneMapped of one pixel, sample s at colors[s · plane + i]: the operations of
// one lane of the lanes forms (the tails of rows that fill no set of lanes).
template <ToneMap kOp, int kS>
inline glm::vec4 resolve_tone_mapped_pixel(const glm::vec4* colors, std::size_t plane, std::size_t i, float scale) {
  float r[kS], g[kS], b[kS], a[kS];
  for (int s = 0; s < kS; ++s) {
    const glm::vec4& c = colors[static_cast<std::size_t>(s) * plane + i];
    r[s] = c.r * scale, g[s] = c.g * scale, b[s] = c.b * scale, a[s] = c.a;
    tone_map_operators::tone_map<kOp>(r[s], g[s], b[s]);
  }
  return {box_mean(r), box_mean(g), box_mean(b), box_mean(a)};
}

}  // namespace
}  // namespace softpbr::pbr

// {baseline, avx2, avx512}::encode_with_lanes<N>() and resolve_with_lanes<N>() in
// softpbr::pbr's unnamed namespace.
#define SOFTPBR_TARGET_FILE "tonemap-inl.h"
#include "softpbr/simd/foreach_target.h"

namespace softpbr::pbr {
namespace {
// The lanes kernels: EncodeKernel names an instruction set and its lane count.
simd::Isa kernel_isa(EncodeKernel kernel) {
  switch (kernel) {
    case EncodeKernel::Avx512: return simd::Isa::Avx512;
    case EncodeKernel::Avx2: return simd::Isa::Avx2;
    default: return simd::Isa::Baseline;
  }
}
void encode_lanes(EncodeKernel kernel, ToneMap op, const Job& job) {
  const simd::Isa isa = kernel_isa(kernel);
  switch (kernel) {
    case EncodeKernel::Avx512: return SOFTPBR_DISPATCH(isa, encode_with_lanes<16>)(op, job);
    case EncodeKernel::Avx2: return SOFTPBR_DISPATCH(isa, encode_with_lanes<8>)(op, job);
    default: return SOFTPBR_DISPATCH(isa, encode_with_lanes<4>)(op, job);
  }
}
void resolve_lanes(EncodeKernel kernel, ToneMap op, const ResolveJob& job) {
  const simd::Isa isa = kernel_isa(kernel);
  switch (kernel) {
    case EncodeKernel::Avx512: return SOFTPBR_DISPATCH(isa, resolve_with_lanes<16>)(op, job);
    case EncodeKernel::Avx2: return SOFTPBR_DISPATCH(isa, resolve_with_lanes<8>)(op, job);
    default: return SOFTPBR_DISPATCH(isa, resolve_with_lanes<4>)(op, job);
  }
}
}  // namespace

bool ToneMapper::supported(EncodeKernel kernel) {
  switch (kernel) {
    case EncodeKernel::Scalar: return true;
    default: return simd::supported(kernel_isa(kernel));
  }
}

EncodeKernel ToneMapper::widest_kernel() {
  for (EncodeKernel k : {EncodeKernel::Avx512, EncodeKernel::Avx2})
    if (supported(k)) return k;
  return EncodeKernel::Lanes4;
}

std::uint8_t ToneMapper::encode(float v) const { return encode_fast(thresholds_, first_.data(), v); }

void ToneMapper::encode_uniform(const glm::vec4& c, int x0, int y0, int x1, int y1, raster::Image8& image) const {
  const glm::vec3 m = apply_tone_map(settings_.tone_map, glm::vec3(c) * scale_);
  const std::uint8_t code[4] = {encode(m.r), encode(m.g), encode(m.b), raster::unorm8(c.a)};
  // Four pixels' bytes as one 16-byte pattern, written with streaming stores: the image
  // is not read again in this frame (simd.h; the bits are copied, not computed on).
  float pattern[4];
  for (float& p : pattern) std::memcpy(&p, code, 4);
  const int n = x1 - x0;
  for (int y = y0; y < y1; ++y) {
    std::uint8_t* out = image.rgba.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                                             static_cast<std::size_t>(x0)) * 4;
    simd::stream_fill4(reinterpret_cast<float*>(out), pattern, static_cast<std::size_t>(n / 4));
    for (int x = n / 4 * 4; x < n; ++x) std::memcpy(out + 4 * x, code, 4);
  }
  simd::stream_fence();
}

void ToneMapper::encode(const raster::Target& target, int x0, int y0, int x1, int y1, raster::Image8& image) const {
  static const EncodeKernel widest = widest_kernel();
  encode(target, x0, y0, x1, y1, image, widest);
}

void ToneMapper::encode(const raster::Target& target, int x0, int y0, int x1, int y1, raster::Image8& image,
                        EncodeKernel kernel) const {
  if (target.samples() > 1) return encode_multisampled(target, x0, y0, x1, y1, image, kernel);
  const Job job{&target, x0, y0, x1, y1, scale_, {padded_.data(), first_.data(), thresholds_[0], steps_, packed_.empty() ? nullptr : packed_.data(), packed_base_}, &image};
  if (kernel != EncodeKernel::Scalar) return encode_lanes(kernel, settings_.tone_map, job);
  const auto run = [&]<ToneMap kOp>() {
    encode_rect<kOp>(target, x0, y0, x1, y1, scale_, thresholds_, first_.data(), image);
  };
  switch (settings_.tone_map) {
    case ToneMap::None: return run.template operator()<ToneMap::None>();
    case ToneMap::Reinhard: return run.template operator()<ToneMap::Reinhard>();
    case ToneMap::Aces: return run.template operator()<ToneMap::Aces>();
    default: return run.template operator()<ToneMap::Neutral>();
  }
}

namespace {
// Resolve::ToneMapped for pixels [x0, x1) of row y: exposure and the tone map per sample
// (tone_map_operators, lanes of 4 pixels then single pixels: the same operations per
// lane), the box mean of each channel; alpha is the mean of the linear alphas.
template <ToneMap kOp, int kS>
void resolve_tone_mapped_row(const glm::vec4* colors, std::size_t plane, std::size_t row, int x0, int x1, float scale,
                             glm::vec4* out) {
  using V = simd::Vec<4>;
  int x = x0;
  for (; x + 4 <= x1; x += 4, out += 4) {
    V r[kS], g[kS], b[kS], a[kS];
    for (int s = 0; s < kS; ++s) {
      simd::load_deinterleave4<4>(&colors[static_cast<std::size_t>(s) * plane + row + static_cast<std::size_t>(x)].r,
                                  r[s], g[s], b[s], a[s]);
      r[s] *= V(scale);
      g[s] *= V(scale);
      b[s] *= V(scale);
      tone_map_operators::tone_map<kOp>(r[s], g[s], b[s]);
    }
    alignas(16) float ch[4][4];
    box_mean(r).store(ch[0]);
    box_mean(g).store(ch[1]);
    box_mean(b).store(ch[2]);
    box_mean(a).store(ch[3]);
    for (int i = 0; i < 4; ++i) out[i] = {ch[0][i], ch[1][i], ch[2][i], ch[3][i]};
  }
  for (; x < x1; ++x, ++out)
    *out = resolve_tone_mapped_pixel<kOp, kS>(colors, plane, row + static_cast<std::size_t>(x), scale);
}
}  // namespace

void ToneMapper::resolve(const raster::Target& target, int x0, int y0, int x1, int y1, glm::vec4* out,
                         std::size_t out_width) const {
  resolve(raster::read_pixels(target), x0, y0, x1, y1, out, out_width);
}

void ToneMapper::resolve(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1, glm::vec4* out,
                         std::size_t out_width) const {
  static const EncodeKernel widest = widest_kernel();
  resolve(pixels, x0, y0, x1, y1, out, out_width, widest);
}

void ToneMapper::resolve(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1, glm::vec4* out,
                         std::size_t out_width, EncodeKernel kernel) const {
  if (settings_.resolve == Resolve::Linear || pixels.samples == 1)
    return raster::resolve_box(pixels, x0, y0, x1, y1, out, out_width);
  if (kernel != EncodeKernel::Scalar)
    return resolve_lanes(kernel, settings_.tone_map, {&pixels, x0, y0, x1, y1, scale_, out, out_width});
  const std::size_t width = static_cast<std::size_t>(pixels.width);
  const glm::vec4* colors = pixels.colors;
  const auto run = [&]<ToneMap kOp, int kS>() {
    // Row indices relative to the pixels' origin (unsigned arithmetic: row + x − origin).
    for (int y = y0; y < y1; ++y)
      resolve_tone_mapped_row<kOp, kS>(colors, pixels.plane, static_cast<std::size_t>(y) * width - pixels.origin, x0,
                                       x1, scale_, out + static_cast<std::size_t>(y - y0) * out_width);
  };
  const auto with_samples = [&]<ToneMap kOp>() {
    if (pixels.samples == 4) run.template operator()<kOp, 4>();
    else run.template operator()<kOp, 8>();
  };
  switch (settings_.tone_map) {
    case ToneMap::None: return with_samples.template operator()<ToneMap::None>();
    case ToneMap::Reinhard: return with_samples.template operator()<ToneMap::Reinhard>();
    case ToneMap::Aces: return with_samples.template operator()<ToneMap::Aces>();
    default: return with_samples.template operator()<ToneMap::Neutral>();
  }
}

void ToneMapper::encode_multisampled(const raster::Target& target, int x0, int y0, int x1, int y1,
                                     raster::Image8& image, EncodeKernel kernel) const {
  encode_multisampled(raster::read_pixels(target), x0, y0, x1, y1, image, kernel);
}

void ToneMapper::encode(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1,
                        raster::Image8& image) const {
  static const EncodeKernel widest = widest_kernel();
  encode_multisampled(pixels, x0, y0, x1, y1, image, widest);
}

void ToneMapper::encode_multisampled(const raster::TargetPixels& pixels, int x0, int y0, int x1, int y1,
                                     raster::Image8& image, EncodeKernel kernel) const {
  // Blocks of up to kBlock² pixels resolved into a 1-sample scratch target, encoded into a
  // scratch image, copied into place. The scratch buffers belong to the thread (a frame's
  // tiles run on the pool's threads), so a frame allocates nothing after the first tile.
  constexpr int kBlock = 64;
  thread_local raster::Target resolved(kBlock, kBlock);
  thread_local raster::Image8 piece{kBlock, kBlock, image::PixelVector<std::uint8_t>(kBlock * kBlock * 4)};
  const ToneMapper& encoder = settings_.resolve == Resolve::ToneMapped && display_ ? *display_ : *this;
  glm::vec4* const scratch = resolved.colors().data();
  for (int by = y0; by < y1; by += kBlock)
    for (int bx = x0; bx < x1; bx += kBlock) {
      const int w = std::min(kBlock, x1 - bx), h = std::min(kBlock, y1 - by);
      resolve(pixels, bx, by, bx + w, by + h, scratch, kBlock, kernel);
      encoder.encode(resolved, 0, 0, w, h, piece, kernel);
      for (int y = 0; y < h; ++y)
        std::memcpy(image.rgba.data() + ((static_cast<std::size_t>(by + y) * static_cast<std::size_t>(image.width)) +
                                         static_cast<std::size_t>(bx)) * 4,
                    piece.rgba.data() + static_cast<std::size_t>(y) * kBlock * 4, static_cast<std::size_t>(w) * 4);
    }
}

raster::Image8 tone_map_to_rgba8(const raster::Target& target, const OutputSettings& s) {
  const ToneMapper mapper(s);
  raster::Image8 image;
  image.width = target.width();
  image.height = target.height();
  image.rgba.resize(static_cast<std::size_t>(target.width()) * static_cast<std::size_t>(target.height()) * 4);
  mapper.encode(target, 0, 0, target.width(), target.height(), image);
  return image;
}

}  // namespace softpbr::pbr
