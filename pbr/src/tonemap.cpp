// Tone mapping and output (see tonemap.h).
#include "softpbr/pbr/tonemap.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <stb_image_write.h>

#include "softpbr/raster/color.h"
#include "softpbr/raster/dmath.h"
#include "softpbr/raster/simd.h"

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

ToneMapper::ToneMapper(const OutputSettings& s)
    : settings_(checked(s)), scale_(exposure_scale(s.exposure)), thresholds_(transfer_thresholds(s.gamma)) {
  // Positive floats order as their bits, so key k = bits >> 16 covers the values from
  // float(k << 16) up to the next key's start; keys up to that of 1.0f cover [0, 1].
  constexpr std::uint32_t kLastKey = 0x3f800000u >> 16;
  first_.resize(kLastKey + 1);
  std::size_t below = 0;
  for (std::uint32_t k = 0; k <= kLastKey; ++k) {
    const float start = std::bit_cast<float>(k << 16);
    while (below < thresholds_.size() && thresholds_[below] < start) ++below;
    first_[k] = static_cast<std::uint8_t>(below);
  }
}

namespace {
// The code of v: first[] gives the thresholds below v's key, then a step or two.
inline std::uint8_t encode_fast(const std::array<float, 255>& t, const std::uint8_t* first, float v) {
  if (!(v >= t[0])) return 0;  // NaN too
  if (!(v < 1.0f)) return encode(t, v);
  unsigned k = first[std::bit_cast<std::uint32_t>(v) >> 16];
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
}  // namespace

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
void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}
}  // namespace

void write_hdr(const std::filesystem::path& path, const raster::Target& target, float exposure) {
  const float scale = exposure_scale(exposure);
  std::vector<float> rgb;
  rgb.reserve(target.colors().size() * 3);
  for (const glm::vec4& c : target.colors())
    for (int i = 0; i < 3; ++i) rgb.push_back(std::isfinite(c[i]) ? std::max(c[i] * scale, 0.0f) : 0.0f);
  std::vector<unsigned char> bytes;
  if (!stbi_write_hdr_to_func(append_bytes, &bytes, target.width(), target.height(), 3, rgb.data()))
    throw std::runtime_error(path.string() + ": HDR encoding failed");
  raster::write_file_atomic(path, bytes);
}

}  // namespace softpbr::pbr
