// Tone mapping and output (pbr/tonemap.h): each operator against its closed form, ranges and
// monotonicity, the 8-bit transfer curves, exposure, and the .hdr writer.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/vec3.hpp>

#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/color.h"
#include "softpbr/raster/target.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

constexpr pbr::ToneMap kOps[] = {pbr::ToneMap::None, pbr::ToneMap::Reinhard, pbr::ToneMap::Aces, pbr::ToneMap::Neutral};

// The operators in double, written from their sources.
double reinhard(double x) { return x / (1 + x); }
double aces(double x) {  // Narkowicz 2015
  return std::clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}
glm::dvec3 neutral(glm::dvec3 c) {  // Khronos PBR Neutral, the reference GLSL
  const double start = 0.8 - 0.04, desaturation = 0.15;
  const double x = std::min({c.r, c.g, c.b});
  const double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
  c -= offset;
  const double peak = std::max({c.r, c.g, c.b});
  if (peak < start) return c;
  const double d = 1 - start;
  const double new_peak = 1 - d * d / (peak + d - start);
  c *= new_peak / peak;
  const double g = 1 - 1 / (desaturation * (peak - new_peak) + 1);
  return c * (1 - g) + glm::dvec3(new_peak) * g;
}
glm::dvec3 reference(pbr::ToneMap op, glm::dvec3 c) {
  c = glm::max(c, glm::dvec3(0));
  switch (op) {
    case pbr::ToneMap::None: return glm::min(c, glm::dvec3(1));
    case pbr::ToneMap::Reinhard: return {reinhard(c.r), reinhard(c.g), reinhard(c.b)};
    case pbr::ToneMap::Aces: return {aces(c.r), aces(c.g), aces(c.b)};
    default: return glm::clamp(neutral(c), glm::dvec3(0), glm::dvec3(1));
  }
}

// A target holding `values` as grey pixels (alpha 1) in row-major order, rows of up to
// 4096 pixels, the rest black.
raster::Target grey_row(const std::vector<float>& values) {
  const int n = static_cast<int>(values.size());
  const int w = std::min(n, 4096);
  raster::Target t(w, (n + w - 1) / w);
  t.clear({0, 0, 0, 1});
  for (std::size_t i = 0; i < values.size(); ++i) t.colors()[i] = {values[i], values[i], values[i], 1.0f};
  return t;
}

// A fresh, empty folder under the build tree for files a test writes.
fs::path scratch_dir(const std::string& name) {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "test-scratch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("apply_tone_map equals each operator's closed form (None, Reinhard, ACES fit, PBR Neutral)") {
  const glm::vec3 colours[] = {{0, 0, 0},        {1e-4f, 0.01f, 0.05f}, {0.18f, 0.18f, 0.18f}, {0.5f, 0.25f, 0.1f},
                               {1, 1, 1},        {0.9f, 0.2f, 0.05f},   {2, 1, 0.5f},          {4, 4, 4},
                               {10, 0.3f, 0.1f}, {100, 50, 1},          {1e4f, 1e3f, 1e2f},    {0.08f, 0.5f, 0.7f}};
  for (pbr::ToneMap op : kOps)
    for (const glm::vec3& c : colours) {
      const glm::vec3 got = pbr::apply_tone_map(op, c);
      const glm::dvec3 want = reference(op, glm::dvec3(c));
      CAPTURE(pbr::tone_map_name(op));
      CAPTURE(c.r);
      CAPTURE(c.g);
      CAPTURE(c.b);
      for (int k = 0; k < 3; ++k) CHECK(std::fabs(got[k] - want[k]) <= 1e-6);
    }
  // Landmarks: Reinhard maps 1 to 1/2; the ACES fit reaches 1 at x ≈ 7.24 and stays there.
  CHECK(pbr::apply_tone_map(pbr::ToneMap::Reinhard, glm::vec3(1.0f)).r == 0.5f);
  CHECK(pbr::apply_tone_map(pbr::ToneMap::Aces, glm::vec3(7.5f)).r == 1.0f);
  CHECK(pbr::apply_tone_map(pbr::ToneMap::Aces, glm::vec3(7.0f)).r < 1.0f);
  // Negative input is treated as 0 by every operator.
  for (pbr::ToneMap op : kOps) CHECK(pbr::apply_tone_map(op, glm::vec3(-1.0f, -1e-30f, -1e30f)) == glm::vec3(0.0f));
}

// The inputs: float bit patterns from +0 to +Inf at a stride, the specials and negatives;
// each colour takes three of them (PBR Neutral mixes the channels).
namespace {

std::vector<float> tone_map_pin_values() {
  std::vector<float> v;
  for (std::uint32_t b = 0; b <= 0x7f800000u; b += 0x8011u) v.push_back(std::bit_cast<float>(b));
  for (float x : {0.08f, 0.76f, 1.0f, 1e9f, 1e19f, 7.24f, -0.0f, -1.0f, -1e-30f, -std::numeric_limits<float>::infinity(),
                  std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min()})
    v.push_back(x);
  return v;
}
// FNV-1a over the output bits (every NaN hashed as one value: the encoder makes any NaN 0).
std::uint64_t tone_map_pin_hash(pbr::ToneMap op) {
  const std::vector<float> v = tone_map_pin_values();
  std::uint64_t h = 14695981039346656037ull;
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec3 out = pbr::apply_tone_map(op, glm::vec3(v[i], v[(i * 7 + 3) % n], v[(i * 13 + 5) % n]));
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t bits = std::isnan(out[k]) ? 0x7fc00000u : std::bit_cast<std::uint32_t>(out[k]);
      for (int byte = 0; byte < 4; ++byte) h = (h ^ ((bits >> (8 * byte)) & 0xffu)) * 1099511628211ull;
    }
  }
  return h;
}

}  // namespace

TEST_CASE("apply_tone_map gives the same float bits as the scalar operators it replaced (pinned hashes)") {
  // The hashes were taken with the scalar aces_channel/pbr_neutral code that preceded the
  // lane-generic operators (tone_map_operators.h), before that code was removed.
  struct Pin {
    pbr::ToneMap op;
    std::uint64_t hash;
  };
  const Pin pins[] = {{pbr::ToneMap::None, 0xd38ac95e727e2ef0ull},
                      {pbr::ToneMap::Reinhard, 0xe58841b43f44de75ull},
                      {pbr::ToneMap::Aces, 0xfc8835c8531591bfull},
                      {pbr::ToneMap::Neutral, 0x8d609647c387af04ull}};
  CHECK(tone_map_pin_values().size() == 65259);
  for (const Pin& p : pins) {
    CAPTURE(pbr::tone_map_name(p.op));
    CHECK(tone_map_pin_hash(p.op) == p.hash);
  }
}

TEST_CASE("PBR Neutral below the compression start only subtracts the offset") {
  // Colours whose smallest channel is ≥ 0.08 lose exactly 0.04; darker ones lose x − 6.25x²
  // (x the smallest channel); as long as the peak after that stays below 0.76.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 0.8f);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const glm::vec3 c(u(rng), u(rng), u(rng));
    const float x = std::min({c.r, c.g, c.b});
    const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
    if (std::max({c.r, c.g, c.b}) - offset >= 0.76f) continue;
    ++checked;
    CHECK(pbr::apply_tone_map(pbr::ToneMap::Neutral, c) == c - glm::vec3(offset));
  }
  CHECK(checked > 10000);
  CHECK(pbr::apply_tone_map(pbr::ToneMap::Neutral, glm::vec3(0.5f, 0.3f, 0.1f)) ==
        glm::vec3(0.5f, 0.3f, 0.1f) - glm::vec3(0.04f));
}

TEST_CASE("every operator is monotonic per channel along ramps and stays in [0, 1] up to 1e6") {
  const glm::vec3 tints[] = {{1, 1, 1}, {1, 0.5f, 0.2f}, {0.2f, 0.3f, 1}, {0, 1, 0}, {1, 0.99f, 0.98f}};
  for (pbr::ToneMap op : kOps)
    for (const glm::vec3& tint : tints) {
      CAPTURE(pbr::tone_map_name(op));
      glm::vec3 previous(0.0f);
      int decreases = 0, outside = 0;
      for (int i = 0; i <= 6000; ++i) {
        // Linear steps to 1, then geometric steps to 1e6.
        const float t = i <= 1000 ? i / 1000.0f : std::pow(10.0f, (i - 1000) / 5000.0f * 6.0f);
        const glm::vec3 out = pbr::apply_tone_map(op, tint * t);
        for (int k = 0; k < 3; ++k) {
          // PBR Neutral rounds to 1 ulp below its previous value near 1 at t ≈ 1e6 (a
          // float step of 6e-8 that no 8-bit code sees); anything larger is a real dip.
          if (out[k] < previous[k] - 1.2e-7f) ++decreases;
          if (!(out[k] >= 0.0f && out[k] <= 1.0f)) ++outside;
        }
        previous = out;
      }
      CHECK(decreases == 0);
      CHECK(outside == 0);
    }
  // Random colours with channels spread over 0 … 1e6 (log-uniform).
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> e(-6.0f, 6.0f);
  for (pbr::ToneMap op : kOps)
    for (int i = 0; i < 20000; ++i) {
      const glm::vec3 c(std::pow(10.0f, e(rng)), std::pow(10.0f, e(rng)), std::pow(10.0f, e(rng)));
      const glm::vec3 out = pbr::apply_tone_map(op, c);
      for (int k = 0; k < 3; ++k) CHECK_MESSAGE((out[k] >= 0.0f && out[k] <= 1.0f), pbr::tone_map_name(op) << " " << c[k]);
    }
}

TEST_CASE("NaN radiance encodes as 0, huge and infinite radiance encode as white for every operator") {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  raster::Target t(6, 1);
  t.colors()[0] = {nan, 0.5f, nan, 1.0f};
  t.colors()[1] = {inf, inf, inf, 1.0f};
  t.colors()[2] = {1e30f, 1e20f, 1e10f, 1.0f};
  t.colors()[3] = {std::numeric_limits<float>::max(), 1e6f, 100.0f, 0.5f};
  t.colors()[4] = {-inf, -1.0f, 0.0f, 1.0f};
  t.colors()[5] = {inf, 0.0f, 0.0f, 1.0f};
  for (pbr::ToneMap op : kOps)
    for (float gamma : {0.0f, 2.2f}) {
      CAPTURE(pbr::tone_map_name(op));
      CAPTURE(gamma);
      const raster::Image8 img = pbr::tone_map_to_rgba8(t, {0.0f, op, gamma});
      const auto px = [&](int i, int c) { return static_cast<int>(img.rgba[static_cast<std::size_t>(i * 4 + c)]); };
      CHECK(px(0, 0) == 0);
      CHECK(px(0, 2) == 0);
      // Per-channel operators encode the finite channel of that pixel normally; PBR Neutral
      // mixes channels (min, max, desaturation), so there the NaN blanks the whole pixel.
      if (op != pbr::ToneMap::Neutral) CHECK(px(0, 1) > 0);
      for (int c = 0; c < 3; ++c) {
        CHECK(px(1, c) == 255);
        CHECK(px(2, c) == 255);
        CHECK(px(4, c) == 0);
      }
      CHECK(px(3, 0) == 255);
      CHECK(px(3, 3) == 128);  // alpha is linear, rounded
      CHECK(px(5, 0) == 255);
    }
}

TEST_CASE("tone map names round-trip") {
  for (pbr::ToneMap op : kOps) CHECK(pbr::tone_map_from_name(pbr::tone_map_name(op)) == op);
  CHECK(pbr::tone_map_name(pbr::ToneMap::None) == "none");
  CHECK(pbr::tone_map_name(pbr::ToneMap::Reinhard) == "reinhard");
  CHECK(pbr::tone_map_name(pbr::ToneMap::Aces) == "aces");
  CHECK(pbr::tone_map_name(pbr::ToneMap::Neutral) == "neutral");
  for (const char* bad : {"", "Reinhard", "aces ", "filmic", "neutral2"}) CHECK_FALSE(pbr::tone_map_from_name(bad).has_value());
}

TEST_CASE("8-bit encoding: gamma 0 is the exact sRGB curve, gamma 2.2 is round(255 x^(1/2.2))") {
  std::vector<float> values;
  for (int i = 0; i <= 20000; ++i) values.push_back(i / 20000.0f);
  for (float x : {1e-30f, 1e-6f, 0.0031308f, 0.04045f, 0.99999f, 1.5f, 1e6f}) values.push_back(x);
  const raster::Target t = grey_row(values);
  const raster::Image8 srgb = pbr::tone_map_to_rgba8(t, {0.0f, pbr::ToneMap::None, 0.0f});
  const raster::Image8 g22 = pbr::tone_map_to_rgba8(t, {0.0f, pbr::ToneMap::None, 2.2f});
  int srgb_mismatches = 0, g22_mismatches = 0, ties = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const float x = std::min(values[i], 1.0f);
    for (int c = 0; c < 3; ++c)
      if (srgb.rgba[i * 4 + c] != raster::linear_to_srgb8(x)) ++srgb_mismatches;
    CHECK(srgb.rgba[i * 4 + 3] == 255);
    const double code = 255.0 * std::pow(static_cast<double>(x), 1 / 2.2);
    if (std::fabs(code - std::floor(code) - 0.5) < 1e-4) {  // too close to a tie to judge
      ++ties;
      continue;
    }
    if (g22.rgba[i * 4] != std::lround(code)) ++g22_mismatches;
  }
  CHECK(srgb_mismatches == 0);
  CHECK(g22_mismatches == 0);
  CHECK(ties < 50);
  // The thresholds are ascending; threshold k is where the encoding reaches (k + 0.5)/255.
  for (float gamma : {0.0f, 1.8f, 2.2f}) {
    const std::array<float, 255> th = pbr::transfer_thresholds(gamma);
    CHECK(std::is_sorted(th.begin(), th.end()));
    CHECK(th[0] > 0.0f);
    CHECK(th[254] < 1.0f);
  }
  CHECK(pbr::transfer_thresholds(0.0f) == raster::srgb8_thresholds());
  CHECK(pbr::transfer_thresholds(2.2f)[127] == doctest::Approx(std::pow(127.5 / 255.0, 2.2)).epsilon(1e-6));
}

TEST_CASE("exposure +1 stop doubles the input, -1 halves it, bad exposure or gamma throws") {
  std::vector<float> values;
  for (int i = 0; i <= 3000; ++i) values.push_back(i / 1000.0f);  // 0 … 3
  std::vector<float> doubled, halved;
  for (float v : values) {
    doubled.push_back(2.0f * v);
    halved.push_back(0.5f * v);
  }
  for (pbr::ToneMap op : kOps)
    for (float gamma : {0.0f, 2.2f}) {
      CAPTURE(pbr::tone_map_name(op));
      const raster::Image8 plus = pbr::tone_map_to_rgba8(grey_row(values), {1.0f, op, gamma});
      const raster::Image8 minus = pbr::tone_map_to_rgba8(grey_row(values), {-1.0f, op, gamma});
      CHECK(plus.rgba == pbr::tone_map_to_rgba8(grey_row(doubled), {0.0f, op, gamma}).rgba);
      CHECK(minus.rgba == pbr::tone_map_to_rgba8(grey_row(halved), {0.0f, op, gamma}).rgba);
    }
  const raster::Target t = grey_row({0.5f});
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (float exposure : {nan, inf, -inf})
    CHECK_THROWS_WITH_AS(pbr::tone_map_to_rgba8(t, {exposure, pbr::ToneMap::Reinhard, 0.0f}), doctest::Contains("exposure"),
                         std::invalid_argument);
  for (float gamma : {-1.0f, nan, inf})
    CHECK_THROWS_WITH_AS(pbr::tone_map_to_rgba8(t, {0.0f, pbr::ToneMap::Reinhard, gamma}), doctest::Contains("gamma"),
                         std::invalid_argument);
}

TEST_CASE("write_hdr writes a Radiance file atomically, a missing folder throws and leaves nothing") {
  const fs::path dir = scratch_dir("write_hdr");
  raster::Target t(5, 3);
  for (std::size_t i = 0; i < t.colors().size(); ++i) t.colors()[i] = {0.1f * i, 2.0f, 1e3f, 1.0f};
  const fs::path file = dir / "out.hdr";
  pbr::write_hdr(file, t);
  std::ifstream in(file, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(bytes.rfind("#?RADIANCE", 0) == 0);
  CHECK(bytes.find("FORMAT=32-bit_rle_rgbe") != std::string::npos);
  CHECK(bytes.find("-Y 3 +X 5") != std::string::npos);
  // Only the file itself is left: no temporary beside it.
  std::vector<fs::path> entries(fs::directory_iterator(dir), fs::directory_iterator{});
  CHECK(entries == std::vector<fs::path>{file});
  // Overwriting works and still leaves one file.
  CHECK_NOTHROW(pbr::write_hdr(file, t, 1.0f));
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}) == 1);

  const fs::path missing = dir / "no-such-folder" / "out.hdr";
  CHECK_THROWS_WITH_AS(pbr::write_hdr(missing, t), doctest::Contains(missing.string().c_str()), std::runtime_error);
  CHECK_FALSE(fs::exists(missing.parent_path()));
  CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}) == 1);
  CHECK_THROWS_AS(pbr::write_hdr(dir / "bad.hdr", t, std::numeric_limits<float>::infinity()), std::invalid_argument);
  CHECK_FALSE(fs::exists(dir / "bad.hdr"));
  fs::remove_all(dir);
}
