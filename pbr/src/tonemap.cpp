// Tone mapping and output (see tonemap.h).
#include "softpbr/pbr/tonemap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "softpbr/image/write.h"
#include "softpbr/raster/color.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/simd/simd.h"

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

namespace {

float aces_channel(float x) {
  // Narkowicz 2015, "ACES Filmic Tone Mapping Curve": x(ax + b) / (x(cx + d) + e).
  constexpr float a = 2.51f, b = 0.03f, c = 2.43f, d = 0.59f, e = 0.14f;
  return std::clamp((x * (a * x + b)) / (x * (c * x + d) + e), 0.0f, 1.0f);
}

glm::vec3 pbr_neutral(glm::vec3 color) {
  // Khronos PBR Neutral tone mapper (Khronos 3D Commerce, 2024), as its reference GLSL.
  constexpr float kStartCompression = 0.8f - 0.04f;
  constexpr float kDesaturation = 0.15f;
  const float x = std::min({color.r, color.g, color.b});
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  color -= offset;
  const float peak = std::max({color.r, color.g, color.b});
  if (peak < kStartCompression) return color;
  constexpr float d = 1.0f - kStartCompression;
  const float new_peak = 1.0f - d * d / (peak + d - kStartCompression);
  color *= new_peak / peak;
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  return color * (1.0f - g) + glm::vec3(new_peak) * g;
}

}  // namespace

glm::vec3 apply_tone_map(ToneMap op, glm::vec3 c) {
  // From 1e9 on every operator already returns its maximum (1), so the upper clamp changes
  // no finite result; it keeps +Inf (Inf / Inf) and the ACES fit's x² overflow above ~1e19
  // from turning into NaN, which would encode as black. NaN stays NaN (encoded as 0).
  c = glm::min(glm::max(c, glm::vec3(0.0f)), glm::vec3(1e9f));
  switch (op) {
    case ToneMap::None: return glm::min(c, glm::vec3(1.0f));
    case ToneMap::Reinhard: return c / (glm::vec3(1.0f) + c);
    case ToneMap::Aces: return {aces_channel(c.r), aces_channel(c.g), aces_channel(c.b)};
    default: return glm::clamp(pbr_neutral(c), glm::vec3(0.0f), glm::vec3(1.0f));
  }
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
        const glm::vec3 m = apply_tone_map(kOp, glm::vec3(c) * scale);
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

// apply_tone_map on lanes: the same IEEE operations in the same order, glm's and std's
// min/max/clamp written as simd::min/max/clamp (the same comparisons: glm::min(x, y) is
// y < x ? y : x as simd::min; std::clamp(v, 0, 1) picks as min(max(v, 0), 1)), branches
// as selects of both sides (PBR Neutral's compression is computed for every lane and kept
// where peak ≥ 0.76; a discarded lane's quotient may be Inf or NaN, which no lane keeps).
template <ToneMap kOp, class F>
inline void tone_map_lanes(F& r, F& g, F& b) {
  const auto limit = [](F c) { return simd::min(simd::max(c, F(0.0f)), F(1e9f)); };
  r = limit(r);
  g = limit(g);
  b = limit(b);
  if constexpr (kOp == ToneMap::None) {
    r = simd::min(r, F(1.0f));
    g = simd::min(g, F(1.0f));
    b = simd::min(b, F(1.0f));
  } else if constexpr (kOp == ToneMap::Reinhard) {
    r = r / (F(1.0f) + r);
    g = g / (F(1.0f) + g);
    b = b / (F(1.0f) + b);
  } else if constexpr (kOp == ToneMap::Aces) {
    constexpr float ka = 2.51f, kb = 0.03f, kc = 2.43f, kd = 0.59f, ke = 0.14f;  // aces_channel
    const auto aces = [](F x) {
      return simd::clamp((x * (F(ka) * x + F(kb))) / (x * (F(kc) * x + F(kd)) + F(ke)), F(0.0f), F(1.0f));
    };
    r = aces(r);
    g = aces(g);
    b = aces(b);
  } else {
    constexpr float kStartCompression = 0.8f - 0.04f;  // pbr_neutral's constants
    constexpr float kDesaturation = 0.15f;
    constexpr float d = 1.0f - kStartCompression;
    const F x = simd::min(simd::min(r, g), b);  // std::min({r, g, b})
    const F offset = simd::select(x < F(0.08f), x - F(6.25f) * x * x, F(0.04f));
    r -= offset;
    g -= offset;
    b -= offset;
    const F peak = simd::max(simd::max(r, g), b);  // std::max({r, g, b})
    const F new_peak = F(1.0f) - F(d * d) / (peak + F(d) - F(kStartCompression));
    const F ratio = new_peak / peak;
    const F mix = F(1.0f) - F(1.0f) / (F(kDesaturation) * (peak - new_peak) + F(1.0f));
    const F keep = F(1.0f) - mix, toward = new_peak * mix;
    const auto compress = [&](F c) { return (c * ratio) * keep + toward; };
    const auto below = peak < F(kStartCompression);
    r = simd::clamp(simd::select(below, r, compress(r)), F(0.0f), F(1.0f));
    g = simd::clamp(simd::select(below, g, compress(g)), F(0.0f), F(1.0f));
    b = simd::clamp(simd::select(below, b, compress(b)), F(0.0f), F(1.0f));
  }
}

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

// The codes of N values through the packed table, all in lanes: code_of for curves with at
// most one threshold per key.
template <int N>
inline simd::UintLanes<N> packed_codes(simd::Vec<N> v, const Curve& c) {
  using U = simd::UintLanes<N>;
  using V = simd::Vec<N>;
  const U bits = simd::bits_of(v) & 0x7fffffffu;  // −0 (t[0] = 0) looks up key 0 as +0
  U key = bits >> 16;
  const U lowest = U{} + c.packed_base, highest = U{} + kLastKey;
  key = key < lowest ? lowest : key;  // below t[0]: overridden with 0 below
  key = key > highest ? highest : key;
  const U entry = simd::gather<N>(c.packed, key - lowest);
  U code = (entry >> 17) - (U)((bits & 0xffffu) >= (entry & 0x1ffffu));  // a true comparison is −1
  code = (v < V(1.0f)).m ? code : U{} + 255u;
  return (v >= V(c.t0)).m ? code : U{};
}

// N pixels from `px` to 4N bytes at `out`.
template <int N, ToneMap kOp, int kSteps>
inline void encode_lanes(const glm::vec4* px, float scale, const Curve& curve, std::uint8_t* out) {
  using V = simd::Vec<N>;
  V r, g, b, a;
  simd::load_deinterleave4<N>(&px[0].r, r, g, b, a);
  r *= V(scale);
  g *= V(scale);
  b *= V(scale);
  tone_map_lanes<kOp>(r, g, b);
  // raster::unorm8(a) = a·255 + 0.5 truncated for 0 < a < 1, 0 at or below 0 (and NaN), 255
  // from 1: the same as truncating min(max(0, a), 1)·255 + 0.5 (0.5 → 0, 255.5 → 255; max
  // with 0 first turns NaN into 0), which every lane can convert.
  a = simd::min(simd::max(V(0.0f), a), V(1.0f)) * V(255.0f) + V(0.5f);
  if constexpr (kSteps == kPacked && std::endian::native == std::endian::little) {
    // Each pixel's four codes as one 32-bit lane, bytes r, g, b, a in memory order.
    const simd::UintLanes<N> rgba = packed_codes(r, curve) | packed_codes(g, curve) << 8 |
                                    packed_codes(b, curve) << 16 | simd::truncate_to_uint(a) << 24;
    std::memcpy(out, &rgba, 4 * N);
    return;
  }
  alignas(64) float ch[4][N];
  r.store(ch[0]);
  g.store(ch[1]);
  b.store(ch[2]);
  a.store(ch[3]);
  // The curve in locals: the byte stores below may alias anything to the compiler.
  const float* t = curve.t;
  const std::uint8_t* first = curve.first;
  const float t0 = curve.t0;
  const int steps = curve.steps;
  alignas(64) std::uint8_t bytes[4 * N];
  for (int i = 0; i < N; ++i) {
    bytes[4 * i + 0] = static_cast<std::uint8_t>(code_of<kSteps>(t, first, t0, steps, ch[0][i]));
    bytes[4 * i + 1] = static_cast<std::uint8_t>(code_of<kSteps>(t, first, t0, steps, ch[1][i]));
    bytes[4 * i + 2] = static_cast<std::uint8_t>(code_of<kSteps>(t, first, t0, steps, ch[2][i]));
    bytes[4 * i + 3] = static_cast<std::uint8_t>(static_cast<int>(ch[3][i]));
  }
  std::memcpy(out, bytes, sizeof bytes);
}

template <int N, ToneMap kOp, int kSteps>
inline void encode_rect_lanes(const Job& job) {
  const std::size_t width = static_cast<std::size_t>(job.target->width());
  const glm::vec4* colors = job.target->colors().data();
  const int n = job.x1 - job.x0;
  const int whole = n / N * N;
  // Runs of one colour (the background) are common: a set of N pixels all equal, bit for
  // bit, to the last such set reuses its bytes (no byte changes).
  glm::vec4 run[N];
  std::uint8_t run_bytes[4 * N];
  bool have_run = false;
  for (int y = job.y0; y < job.y1; ++y) {
    const std::size_t start = static_cast<std::size_t>(y) * width + static_cast<std::size_t>(job.x0);
    const glm::vec4* in = colors + start;
    std::uint8_t* out = job.image->rgba.data() + start * 4;
    for (int x = 0; x < whole; x += N) {
      if (have_run && simd::same_bytes<sizeof run>(in + x, run)) {
        std::memcpy(out + 4 * x, run_bytes, sizeof run_bytes);
        continue;
      }
      encode_lanes<N, kOp, kSteps>(in + x, job.scale, job.curve, out + 4 * x);
      if (simd::same_bytes<sizeof(glm::vec4) * (N - 1)>(in + x, in + x + 1)) {  // all N the same
        std::copy(in + x, in + x + N, run);
        std::memcpy(run_bytes, out + 4 * x, sizeof run_bytes);
        have_run = true;
      }
    }
    if (whole < n) {  // the last n − whole pixels, padded with zeros to a full set of lanes
      glm::vec4 rest[N] = {};
      std::uint8_t bytes[4 * N];
      std::copy(in + whole, in + n, rest);
      encode_lanes<N, kOp, kSteps>(rest, job.scale, job.curve, bytes);
      std::memcpy(out + 4 * whole, bytes, static_cast<std::size_t>(n - whole) * 4);
    }
  }
}

template <int N, int kSteps>
inline void encode_with_lanes(ToneMap op, const Job& job) {
  switch (op) {
    case ToneMap::None: return encode_rect_lanes<N, ToneMap::None, kSteps>(job);
    case ToneMap::Reinhard: return encode_rect_lanes<N, ToneMap::Reinhard, kSteps>(job);
    case ToneMap::Aces: return encode_rect_lanes<N, ToneMap::Aces, kSteps>(job);
    default: return encode_rect_lanes<N, ToneMap::Neutral, kSteps>(job);
  }
}
template <int N>
inline void encode_with_lanes(ToneMap op, const Job& job) {
  if (job.curve.packed) return encode_with_lanes<N, kPacked>(op, job);
  switch (job.curve.steps) {
    case -1: return encode_with_lanes<N, -1>(op, job);
    case 1: return encode_with_lanes<N, 1>(op, job);  // sRGB, gamma 2.2 (see the tests)
    case 2: return encode_with_lanes<N, 2>(op, job);  // gamma 1
    default: return encode_with_lanes<N, 0>(op, job);
  }
}

void encode_lanes4(ToneMap op, const Job& job) { encode_with_lanes<4>(op, job); }
#if SOFTPBR_SIMD_DISPATCH
SOFTPBR_TARGET_AVX2 void encode_avx2(ToneMap op, const Job& job) { encode_with_lanes<8>(op, job); }
SOFTPBR_TARGET_AVX512 void encode_avx512(ToneMap op, const Job& job) { encode_with_lanes<16>(op, job); }
#endif
}  // namespace

bool ToneMapper::supported(EncodeKernel kernel) {
  switch (kernel) {
    case EncodeKernel::Avx512: return SOFTPBR_SIMD_DISPATCH && simd::cpu_isa() == simd::Isa::Avx512;
    case EncodeKernel::Avx2: return SOFTPBR_SIMD_DISPATCH && simd::cpu_isa() != simd::Isa::Baseline;
    default: return true;
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
  const Job job{&target, x0, y0, x1, y1, scale_, {padded_.data(), first_.data(), thresholds_[0], steps_, packed_.empty() ? nullptr : packed_.data(), packed_base_}, &image};
  switch (kernel) {
#if SOFTPBR_SIMD_DISPATCH
    case EncodeKernel::Avx512: return encode_avx512(settings_.tone_map, job);
    case EncodeKernel::Avx2: return encode_avx2(settings_.tone_map, job);
#endif
    case EncodeKernel::Scalar: break;
    default: return encode_lanes4(settings_.tone_map, job);
  }
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

raster::Image8 tone_map_to_rgba8(const raster::Target& target, const OutputSettings& s) {
  const ToneMapper mapper(s);
  raster::Image8 image;
  image.width = target.width();
  image.height = target.height();
  image.rgba.resize(target.colors().size() * 4);
  mapper.encode(target, 0, 0, target.width(), target.height(), image);
  return image;
}

namespace {
// The colour buffer of a target as float RGBA samples (a glm::vec4 is four floats), for
// the image library's writers: no copy of the buffer is made.
image::ImageViewF colour_view(const raster::Target& target) {
  static_assert(sizeof(glm::vec4) == 4 * sizeof(float));
  const std::span<const glm::vec4> colors = target.colors();
  return {target.width(), target.height(),
          std::span<const float>(reinterpret_cast<const float*>(colors.data()), colors.size() * 4)};
}
}  // namespace

void write_hdr(const std::filesystem::path& path, const raster::Target& target, float exposure) {
  image::write_hdr(path, colour_view(target), exposure_scale(exposure));
}

void write_exr(const std::filesystem::path& path, const raster::Target& target, float exposure) {
  image::write_exr(path, colour_view(target), exposure_scale(exposure));
}

}  // namespace softpbr::pbr
