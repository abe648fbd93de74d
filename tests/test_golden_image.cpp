// softpbr::golden images: PNG and .hdr loading through stb_image, .hdr writing, and the
// conversions between targets, float and 8-bit images.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <doctest/doctest.h>
#include <stb_image_write.h>

#include "golden_helpers.h"
#include "softpbr/golden/image.h"
#include "softpbr/image/write.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/target.h"

namespace golden = softpbr::golden;
namespace raster = softpbr::raster;
using namespace golden_test;

TEST_CASE("golden images: a PNG written by image::write_png loads back with the same bytes, at odd sizes too") {
  const fs::path dir = scratch("image_png_round_trip");
  for (const std::pair<int, int>& size : {std::pair{1, 1}, {3, 7}, {64, 1}, {1, 33}, {130, 17}}) {
    const int w = size.first, h = size.second;
    CAPTURE(w);
    CAPTURE(h);
    const raster::Image8 im = pattern8(w, h, w + h);
    const fs::path p = dir / ("im" + std::to_string(w) + "x" + std::to_string(h) + ".png");
    softpbr::image::write_png(p, im);
    const raster::Image8 back = golden::load_png(p);
    CHECK(back.width == w);
    CHECK(back.height == h);
    CHECK(back.rgba == im.rgba);
  }
}

TEST_CASE("golden images: grey, grey+alpha and RGB PNGs load as RGBA with the grey replicated and alpha 255") {
  const fs::path dir = scratch("image_png_channels");
  const unsigned char pixels[] = {10, 200, 30, 40, 250, 60};  // two pixels' worth for up to 3 channels
  struct Case {
    int channels;
    std::array<std::uint8_t, 4> first_pixel;
  };
  const Case cases[] = {{1, {10, 10, 10, 255}}, {2, {10, 10, 10, 200}}, {3, {10, 200, 30, 255}}};
  for (const Case& c : cases) {
    CAPTURE(c.channels);
    std::string name = "channels";  // built by appending: GCC 12 warns (-Wrestrict) on "c" + string
    name += std::to_string(c.channels);
    const fs::path p = dir / (name + ".png");
    REQUIRE(stbi_write_png(p.c_str(), 1, 1, c.channels, pixels, c.channels) != 0);
    const raster::Image8 im = golden::load_png(p);
    REQUIRE(im.rgba.size() == 4);
    for (int i = 0; i < 4; ++i) CHECK(im.rgba[i] == c.first_pixel[i]);
  }
}

TEST_CASE("golden images: unreadable files throw an error that starts with the path and says why") {
  const fs::path dir = scratch("image_errors");
  write_bytes(dir / "garbage.png", "this is not an image");
  write_bytes(dir / "empty.png", "");
  // A PNG cut after its header: stb can read the size but not the pixels.
  softpbr::image::write_png(dir / "whole.png", pattern8(40, 40));
  const std::vector<char> whole = file_bytes(dir / "whole.png");
  write_bytes(dir / "truncated.png", std::string(whole.begin(), whole.begin() + 60));
  golden::write_hdr(dir / "float.hdr", patternF(4, 4));
  // A header claiming 1048576 pixels of width (IHDR width, big-endian, at byte 16): refused
  // before any allocation.
  std::string huge(whole.begin(), whole.end());
  huge[16] = 0, huge[17] = 0x10, huge[18] = 0, huge[19] = 0;
  write_bytes(dir / "huge.png", huge);
  struct Case {
    std::string file;
    bool hdr;  // loaded with load_hdr, else load_png
    std::string says;
  };
  const Case cases[] = {{"missing.png", false, "no such file"},
                        {"garbage.png", false, "not a readable image"},
                        {"empty.png", false, "not a readable image"},
                        {"truncated.png", false, "cannot decode"},
                        {"huge.png", false, "image size 1048576x40 is outside"},
                        {"float.hdr", false, "load_hdr"},
                        {"whole.png", true, "load_png"},
                        {"missing.hdr", true, "no such file"},
                        {".", false, "is a folder, not an image"}};
  for (const Case& c : cases) {
    CAPTURE(c.file);
    const fs::path p = dir / c.file;
    std::string what;
    try {
      if (c.hdr) golden::load_hdr(p);
      else golden::load_png(p);
    } catch (const std::runtime_error& e) {
      what = e.what();
    }
    CHECK(what.rfind(p.string() + ": ", 0) == 0);
    CHECK(what.find(c.says) != std::string::npos);
  }
}

TEST_CASE("golden images: write_hdr writes pbr::write_hdr's bytes, and load_hdr reads back hdr_round_trip's values") {
  const fs::path dir = scratch("image_hdr");
  raster::Target target(23, 9);
  const golden::ImageF f = patternF(23, 9);
  for (std::size_t i = 0; i < target.colors().size(); ++i)
    target.colors()[i] = {f.rgba[4 * i], f.rgba[4 * i + 1], f.rgba[4 * i + 2], f.rgba[4 * i + 3]};
  target.color(0, 0) = {-1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), 1.0f};
  target.color(1, 0) = {1e-40f, 1e30f, 0.5f, 0.25f};

  softpbr::pbr::write_hdr(dir / "pbr.hdr", target);
  golden::write_hdr(dir / "golden.hdr", golden::to_image(target));
  CHECK(file_bytes(dir / "pbr.hdr") == file_bytes(dir / "golden.hdr"));

  const golden::ImageF loaded = golden::load_hdr(dir / "golden.hdr");
  const golden::ImageF round = golden::hdr_round_trip(golden::to_image(target));
  CHECK(loaded.width == 23);
  CHECK(loaded.height == 9);
  CHECK(loaded.rgba == round.rgba);
  CHECK(golden::hdr_round_trip(round).rgba == round.rgba);  // RGBE values are fixed points
  // Non-finite and negative → 0; alpha → 1; RGBE keeps 8 bits of the largest channel's mantissa.
  CHECK(round.rgba[0] == 0.0f);
  CHECK(round.rgba[1] == 0.0f);
  CHECK(round.rgba[2] == 0.0f);
  CHECK(round.rgba[7] == 1.0f);
  for (std::size_t i = 8; i < round.rgba.size(); i += 4)
    for (std::size_t c = 0; c < 3; ++c) {
      const float in = f.rgba[i + c], out = round.rgba[i + c];
      const float largest = std::max({f.rgba[i], f.rgba[i + 1], f.rgba[i + 2]});
      CHECK(std::abs(in - out) <= largest / 128.0f);
    }
}

TEST_CASE("golden images: to_srgb8 gives raster::resolve_srgb8's bits, NaN, negatives and values above 1 included") {
  raster::Target target(64, 5);
  const float specials[] = {std::numeric_limits<float>::quiet_NaN(), -0.0f, -1.0f, 1.0f, 1.5f,
                            std::numeric_limits<float>::infinity(), 0.0031308f, 1e-9f};
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 64; ++x) {
      const float ramp = static_cast<float>(x + 64 * y) / 319.0f;
      target.color(x, y) = {ramp, ramp * ramp, specials[(x + y) % 8], specials[x % 8]};
    }
  const raster::Image8 a = golden::to_srgb8(golden::to_image(target));
  const raster::Image8 b = raster::resolve_srgb8(target);
  CHECK(a.width == b.width);
  CHECK(a.height == b.height);
  CHECK(a.rgba == b.rgba);
}

TEST_CASE("golden images: to_image copies the colour buffer's floats, to_float maps code c to c / 255") {
  raster::Target target(3, 2);
  target.color(2, 1) = {0.1f, -2.0f, 7.0f, 0.5f};
  const golden::ImageF f = golden::to_image(target);
  REQUIRE(f.rgba.size() == 24);
  CHECK(f.rgba[20] == 0.1f);
  CHECK(f.rgba[21] == -2.0f);
  CHECK(f.rgba[22] == 7.0f);
  CHECK(f.rgba[23] == 0.5f);
  CHECK(f.rgba[0] == 0.0f);
  CHECK(f.rgba[3] == 1.0f);

  raster::Image8 codes{256, 1, {}};
  for (int c = 0; c < 256; ++c) codes.rgba.insert(codes.rgba.end(), {std::uint8_t(c), std::uint8_t(c), std::uint8_t(255 - c), 255});
  const golden::ImageF g = golden::to_float(codes);
  for (int c = 0; c < 256; ++c) {
    CHECK(g.rgba[4 * c] == static_cast<float>(c) / 255.0f);
    CHECK(g.rgba[4 * c + 2] == static_cast<float>(255 - c) / 255.0f);
  }
}
