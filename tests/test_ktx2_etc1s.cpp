// ETC1S in BasisLZ (image/src/etc1s.h) on files made by tests/etc1s_writer.h: block colours
// and alpha from the ETC1 tables, truncations, corrupted Huffman tables, codebook indices
// out of range. Against Basis Universal's transcoder: test_ktx2_reference.cpp.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "etc1s_writer.h"
#include "ktx2_etc1s_sample.h"
#include "ktx2_checks.h"
#include "ktx2_writer.h"
#include "softpbr/image/ktx2.h"

namespace image = softpbr::image;
using namespace ktx2_test;

namespace {

// The RGBA texel (x, y) should have: the ETC1 colour of its block's endpoint and selector
// (KHR Data Format Specification 1.3, Table 128's modifiers; the 5-bit colour widened by
// replicating its top bits), alpha the green of the alpha slice's block (255 without one).
std::array<int, 4> expected_texel(const Etc1sSample& s, int x, int y) {
  static constexpr int kModifiers[8][4] = {{-8, -2, 2, 8},     {-17, -5, 5, 17},   {-29, -9, 9, 29},
                                           {-42, -13, 13, 42}, {-60, -18, 18, 60}, {-80, -24, 24, 80},
                                           {-106, -33, 33, 106}, {-183, -47, 47, 183}};
  auto colour = [&](const Etc1sBlock& b, int c) {
    const Etc1sEndpointSpec& e = s.endpoints[static_cast<std::size_t>(b.endpoint)];
    const int v = c == 0 ? e.r : c == 1 ? e.g : e.b;
    const int sel = (s.selectors[static_cast<std::size_t>(b.selector)][static_cast<std::size_t>(y % 4)] >> (2 * (x % 4))) & 3;
    return std::clamp(((v << 3) | (v >> 2)) + kModifiers[e.inten][sel], 0, 255);
  };
  const std::size_t block = static_cast<std::size_t>((y / 4) * s.bw + x / 4);
  std::array<int, 4> t{};
  for (int c = 0; c < 3; ++c) t[static_cast<std::size_t>(c)] = colour(s.colour[block], c);
  t[3] = s.alpha.empty() ? 255 : colour(s.alpha[block], 1);
  return t;
}

}  // namespace

TEST_CASE("etc1s: each texel is its block's ETC1 colour, alpha the alpha slice's green, clipped at the image's edge") {
  for (bool with_alpha : {false, true}) {
    CAPTURE(with_alpha);
    const Etc1sSample s = etc1s_sample(with_alpha);
    const image::Ktx2Image k = image::load_ktx2(s.file(), "t.ktx2");
    CHECK(k.info.format == "ETC1S");
    CHECK(k.info.supercompression == "BasisLZ");
    const image::Image8& im = k.levels[0];
    REQUIRE(im.width == s.width);
    REQUIRE(im.height == s.height);
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        const std::array<int, 4> t = expected_texel(s, x, y);
        for (int c = 0; c < 4; ++c) {
          CAPTURE(x);
          CAPTURE(y);
          CAPTURE(c);
          REQUIRE(im.rgba[static_cast<std::size_t>((y * s.width + x) * 4 + c)] == t[static_cast<std::size_t>(c)]);
        }
      }
  }
}

TEST_CASE("etc1s: every truncation of a file is a one-line error naming it") {
  const std::vector<std::uint8_t> whole = etc1s_sample(true).file();
  CHECK_NOTHROW(image::load_ktx2(whole, "t.ktx2"));
  for (std::size_t n = 0; n < whole.size(); ++n) {
    CAPTURE(n);
    check_refused(std::vector<std::uint8_t>(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n)), "");
  }
}

TEST_CASE("etc1s: every bit of the global data flipped loads or is a one-line error, and over-full Huffman tables are refused") {
  const Etc1sSample s = etc1s_sample(true);
  const std::vector<std::uint8_t> whole = s.file();
  const std::size_t sgd = static_cast<std::size_t>(whole[64]) | (static_cast<std::size_t>(whole[65]) << 8);
  int refused = 0, huffman = 0;
  for (std::size_t at = sgd; at < sgd + s.data.sgd.size(); ++at)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<std::uint8_t> b = whole;
      b[at] ^= static_cast<std::uint8_t>(1 << bit);
      try {
        const image::Ktx2Image k = image::load_ktx2(b, "t.ktx2");
        CHECK(k.levels[0].rgba.size() == static_cast<std::size_t>(s.width * s.height * 4));
      } catch (const std::runtime_error& e) {
        const std::string message = e.what();
        CAPTURE(message);
        CHECK(message.rfind("t.ktx2: ", 0) == 0);
        CHECK(message.find('\n') == std::string::npos);
        ++refused;
        if (message.find("invalid Huffman table") != std::string::npos) ++huffman;
      }
    }
  CHECK(refused > 0);
  CHECK(huffman > 0);
  // The slice tables' first table with one code length changed: 512 symbols of length 9
  // plus a symbol of length 8 overfill the code space.
  BitWriter t;
  t.put(512, 14);
  t.put(7, 5);                                            // code-length codes 17, 18, 19, 20, 0, 8, 7
  for (int code : {0, 0, 0, 0, 0, 1, 0}) t.put(static_cast<std::uint32_t>(code), 3);  // only "8": one symbol
  for (int i = 0; i < 512; ++i) t.put(0, 1);  // 512 × length 8: twice the code space
  std::vector<std::uint8_t> overfull = s.data.sgd;
  const std::size_t tables_at = overfull.size() - s.tables_bytes;
  const std::vector<std::uint8_t> tb = t.bytes();
  for (std::size_t i = 0; i < std::min(tb.size(), s.tables_bytes); ++i) overfull[tables_at + i] = tb[i];
  Etc1sSample corrupt = s;
  corrupt.data.sgd = overfull;
  check_refused(corrupt.file(), "its BasisLZ slice tables have an invalid Huffman table");
}

TEST_CASE("etc1s: selector and endpoint references beyond the codebooks and the history buffer are refused") {
  Etc1sSample s = etc1s_sample(false);
  // Selector symbols: codebook indices, then the history buffer's 4 entries, then the run
  // symbol; one past that names no entry.
  s.colour[3].selector = static_cast<int>(s.selectors.size()) + 4 + 1;
  s.rewrite();
  check_refused(s.file(), "level 0: a slice refers to a selector history entry beyond the buffer");
  s = etc1s_sample(false);
  // A delta that lands past the codebook even after the decoder's one wrap (index − 4).
  s.colour[4].endpoint = 2 * static_cast<int>(s.endpoints.size()) + 1;
  s.rewrite();
  check_refused(s.file(), "level 0: a slice refers to endpoint");
}
