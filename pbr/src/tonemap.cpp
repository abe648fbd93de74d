// Tone mapping and output (see tonemap.h).
#include "softpbr/pbr/tonemap.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <stb_image_write.h>

#include "softpbr/raster/color.h"
#include "softpbr/raster/dmath.h"

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

raster::Image8 tone_map_to_rgba8(const raster::Target& target, const OutputSettings& s) {
  if (!(s.gamma >= 0.0f) || !std::isfinite(s.gamma))
    throw std::invalid_argument("gamma: must be 0 (sRGB) or a positive number");
  const float scale = exposure_scale(s.exposure);
  const std::array<float, 255> t = transfer_thresholds(s.gamma);
  raster::Image8 image;
  image.width = target.width();
  image.height = target.height();
  image.rgba.resize(target.colors().size() * 4);
  std::uint8_t* out = image.rgba.data();
  for (const glm::vec4& c : target.colors()) {
    const glm::vec3 m = apply_tone_map(s.tone_map, glm::vec3(c) * scale);
    *out++ = encode(t, m.r);
    *out++ = encode(t, m.g);
    *out++ = encode(t, m.b);
    *out++ = raster::unorm8(c.a);
  }
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
