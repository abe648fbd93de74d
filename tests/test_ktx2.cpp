// KTX2 textures (softpbr/image/ktx2.h): the container's levels, supercompression and
// formats, hostile headers and truncations, and UASTC blocks whose texels are known.
// Decoding against Basis Universal's own transcoder is test_ktx2_reference.cpp.
#include <doctest/doctest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "ktx2_checks.h"
#include "ktx2_writer.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"
#include "uastc.h"

namespace image = softpbr::image;
using ktx2_test::Ktx2Spec;
using ktx2_test::check_refused;
using ktx2_test::write_ktx2;

namespace {

// A w×h level of `channels` bytes a texel, each byte a function of its position.
std::vector<std::uint8_t> texels(int w, int h, int channels, int salt) {
  std::vector<std::uint8_t> v(static_cast<std::size_t>(w) * h * channels);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<std::uint8_t>(i * 7 + salt * 31 + (i >> 5));
  return v;
}

// A 16-byte UASTC block of mode 8 (solid colour): the mode's 5-bit code 0x17, then RGBA.
std::vector<std::uint8_t> solid_block(std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a) {
  std::vector<std::uint8_t> block(16, 0);
  unsigned __int128 bits = 0x17;
  bits |= static_cast<unsigned __int128>(r) << 5 | static_cast<unsigned __int128>(g) << 13 |
          static_cast<unsigned __int128>(b) << 21 | static_cast<unsigned __int128>(a) << 29;
  for (int i = 0; i < 16; ++i) block[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(bits >> (8 * i));
  return block;
}

Ktx2Spec rgba_spec(int w, int h, int levels) {
  Ktx2Spec s;
  s.width = w;
  s.height = h;
  for (int l = 0; l < levels; ++l) s.levels.push_back(texels(std::max(1, w >> l), std::max(1, h >> l), 4, l));
  return s;
}

}  // namespace

TEST_CASE("ktx2: uncompressed R, RG, RGB and RGBA levels read as Vulkan samples them, with and without Zstandard") {
  struct Case {
    std::uint32_t vk_format;
    int channels;
  };
  for (const Case c : {Case{9, 1}, Case{16, 2}, Case{23, 3}, Case{37, 4}, Case{43, 4}, Case{15, 1}})
    for (std::uint32_t scheme : {0u, 2u}) {
      CAPTURE(c.vk_format);
      CAPTURE(scheme);
      Ktx2Spec s;
      s.vk_format = c.vk_format;
      s.width = 13;
      s.height = 6;
      s.scheme = scheme;
      for (int l = 0; l < 4; ++l) s.levels.push_back(texels(std::max(1, 13 >> l), std::max(1, 6 >> l), c.channels, l));
      const image::Ktx2Image k = image::load_ktx2(write_ktx2(s), "t.ktx2");
      REQUIRE(k.levels.size() == 4);
      CHECK(k.info.levels == 4);
      CHECK(k.info.supercompression == (scheme == 2 ? "Zstandard" : "none"));
      for (int l = 0; l < 4; ++l) {
        const image::Image8& im = k.levels[static_cast<std::size_t>(l)];
        REQUIRE(im.width == std::max(1, 13 >> l));
        REQUIRE(im.height == std::max(1, 6 >> l));
        const std::vector<std::uint8_t>& src = s.levels[static_cast<std::size_t>(l)];
        for (std::size_t i = 0; i < static_cast<std::size_t>(im.width) * im.height; ++i)
          for (int k4 = 0; k4 < 4; ++k4) {
            const int expected = k4 < c.channels ? src[i * static_cast<std::size_t>(c.channels) + static_cast<std::size_t>(k4)]
                                 : k4 == 3         ? 255
                                                   : 0;
            REQUIRE(im.rgba[i * 4 + static_cast<std::size_t>(k4)] == expected);
          }
      }
      // load_image8 gives level 0.
      const image::Image8 base = image::load_image8(write_ktx2(s), "t.ktx2");
      CHECK(base.rgba == k.levels[0].rgba);
    }
}

TEST_CASE("ktx2: KTXorientation \"ru\" stores rows bottom up and reads top down") {
  Ktx2Spec s = rgba_spec(5, 3, 1);
  const image::Ktx2Image down = image::load_ktx2(write_ktx2(s), "t.ktx2");
  s.orientation = "ru";
  const image::Ktx2Image up = image::load_ktx2(write_ktx2(s), "t.ktx2");
  for (int y = 0; y < 3; ++y)
    for (int i = 0; i < 5 * 4; ++i)
      CHECK(up.levels[0].rgba[static_cast<std::size_t>(y * 20 + i)] == down.levels[0].rgba[static_cast<std::size_t>((2 - y) * 20 + i)]);
  s.orientation = "lu";
  check_refused(write_ktx2(s), "KTXorientation \"lu\"");
}

TEST_CASE("ktx2: every truncation of a file is a one-line error naming it") {
  for (std::uint32_t scheme : {0u, 2u}) {
    Ktx2Spec s = rgba_spec(9, 7, 3);
    s.scheme = scheme;
    s.orientation = "rd";
    const std::vector<std::uint8_t> whole = write_ktx2(s);
    CHECK_NOTHROW(image::load_ktx2(whole, "t.ktx2"));
    for (std::size_t n = 0; n < whole.size(); ++n) {
      CAPTURE(n);
      check_refused(std::vector<std::uint8_t>(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n)), "");
    }
  }
}

TEST_CASE("ktx2: a header claiming 65536x65536 is refused before anything is allocated") {
  Ktx2Spec s = rgba_spec(4, 4, 1);
  std::vector<std::uint8_t> b = write_ktx2(s);
  ktx2_test::put32(b, 20, 65536);
  ktx2_test::put32(b, 24, 65536);
  check_refused(b, "image size 65536x65536 is outside 1x1 .. 16384x16384");
  // Within the sides but over the decoded-bytes limit: refused from the header too.
  ktx2_test::put32(b, 20, 8192);
  ktx2_test::put32(b, 24, 8192);
  image::Limits small;
  small.max_decoded_bytes = 1 << 20;
  check_refused(b, "image size 8192x8192", small);
}

TEST_CASE("ktx2: cube maps, arrays, 3D and 1D textures, ZLIB, unknown formats and mismatched schemes are refused saying what they are") {
  struct Case {
    const char* what;
    void (*edit)(Ktx2Spec&);
  };
  const Case cases[] = {
      {"is a cube map", [](Ktx2Spec& s) { s.faces = 6; }},
      {"is a texture array (4 layers)", [](Ktx2Spec& s) { s.layers = 4; }},
      {"is a 3D texture", [](Ktx2Spec& s) { s.depth = 4; }},
      {"BasisLZ supercompression of vkFormat 37 is invalid", [](Ktx2Spec& s) { s.scheme = 1; }},
      {"ETC1S data without BasisLZ supercompression is invalid", [](Ktx2Spec& s) { s.vk_format = 0; s.color_model = 163; }},
      // fuzz_ktx2 (fuzz/findings/ktx2-uastc-basislz-overread): UASTC blocks under BasisLZ
      // escaped the level-size check and were read past the level's end.
      {"BasisLZ supercompression of UASTC data is invalid", [](Ktx2Spec& s) { s.vk_format = 0; s.color_model = 166; s.scheme = 1; }},
      {"ZLIB supercompression is not supported", [](Ktx2Spec& s) { s.scheme = 3; }},
      {"unknown supercompression scheme 9", [](Ktx2Spec& s) { s.scheme = 9; }},
      {"vkFormat 131 is not a format this reader decodes", [](Ktx2Spec& s) { s.vk_format = 131; }},
      {"vkFormat 0 with colour model 1", [](Ktx2Spec& s) { s.vk_format = 0; }},
      {"levelCount 9 is more than a 4x4 texture has (3)", [](Ktx2Spec& s) { s.level_count = 9; }},
  };
  for (const Case& c : cases) {
    CAPTURE(c.what);
    Ktx2Spec s = rgba_spec(4, 4, 1);
    c.edit(s);
    check_refused(write_ktx2(s), c.what);
  }
  std::vector<std::uint8_t> one_d = write_ktx2(rgba_spec(4, 4, 1));
  ktx2_test::put32(one_d, 24, 0);
  check_refused(one_d, "is a 1D texture");
}

TEST_CASE("ktx2: level data past the end, levels of the wrong size and bad Zstandard data are refused") {
  const std::vector<std::uint8_t> good = write_ktx2(rgba_spec(8, 8, 2));
  std::vector<std::uint8_t> b = good;
  ktx2_test::put64(b, 80, b.size() - 8);  // level 0 starts 8 bytes before the end
  check_refused(b, "level 0: its data (bytes");
  b = good;
  ktx2_test::put64(b, 80, ~std::uint64_t{0} - 4);  // an offset that overflows when added
  check_refused(b, "lies past the end of the file");
  b = good;
  ktx2_test::put64(b, 88, 100);  // 8×8×4 = 256 bytes expected
  check_refused(b, "level 0: its data is 100 bytes; a 8x8 level of this format is 256");
  b = good;
  ktx2_test::put32(b, 52, 4000);  // the DFD's length past the end
  check_refused(b, "its data format descriptor");

  Ktx2Spec z = rgba_spec(8, 8, 1);
  z.scheme = 2;
  b = write_ktx2(z);
  ktx2_test::put64(b, 96, 300);  // uncompressedByteLength
  check_refused(b, "uncompressedByteLength is 300");
  b = write_ktx2(z);
  b[b.size() - 3] ^= 0x55;  // the frame's end damaged
  check_refused(b, "level 0: ");
  // A frame that inflates to more than the level: stopped at the level's size.
  Ktx2Spec big = rgba_spec(8, 8, 1);
  big.levels[0].resize(8 * 8 * 4 * 4, 7);
  big.scheme = 2;
  b = write_ktx2(big);
  ktx2_test::put64(b, 96, 256);
  check_refused(b, "cannot decode its Zstandard data");
}

TEST_CASE("ktx2: read_image_header and read_ktx2_info describe a texture without decoding it") {
  Ktx2Spec s = rgba_spec(12, 10, 3);
  s.vk_format = 43;
  s.transfer = 2;
  s.scheme = 2;
  const std::vector<std::uint8_t> b = write_ktx2(s);
  const image::ImageHeader h = image::read_image_header(b);
  CHECK(h.format == "ktx2");
  CHECK(h.width == 12);
  CHECK(h.height == 10);
  CHECK(h.detail == "R8G8B8A8_SRGB, Zstandard, 3 levels, sRGB");
  CHECK(image::read_ktx2_info(std::vector<std::uint8_t>(b.begin(), b.begin() + 40)).format.empty());
}

TEST_CASE("uastc: a solid-colour block decodes to its colour, clipped at the level's edge, and the reserved mode is refused") {
  Ktx2Spec s;
  s.vk_format = 0;
  s.color_model = 166;
  s.width = 6;  // two blocks across, the second overhanging by 2 texels
  s.height = 3;
  std::vector<std::uint8_t> level = solid_block(10, 200, 30, 255);
  const std::vector<std::uint8_t> second = solid_block(1, 2, 3, 4);
  level.insert(level.end(), second.begin(), second.end());
  s.levels.push_back(level);
  const image::Ktx2Image k = image::load_ktx2(write_ktx2(s), "t.ktx2");
  CHECK(k.info.format == "UASTC");
  const image::Image8& im = k.levels[0];
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 6; ++x) {
      const std::uint8_t* p = &im.rgba[static_cast<std::size_t>(y * 6 + x) * 4];
      if (x < 4) CHECK((p[0] == 10 && p[1] == 200 && p[2] == 30 && p[3] == 255));
      else CHECK((p[0] == 1 && p[1] == 2 && p[2] == 3 && p[3] == 4));
    }
  // Mode code 0x45 (7 bits) is reserved for future modes.
  s.levels[0][16] = 0x45;
  check_refused(write_ktx2(s), "level 0: block (1, 0) is not a valid UASTC block");
}

TEST_CASE("uastc: ASTC's partition function gives the UASTC specification's common patterns") {
  // Rows of the 4×4 patterns as the specification's tables draw them (partition of texels
  // 0..15), for a few seeds of each table: 2 subsets (28, 20, 16), 3 subsets (260), mode 7's (36).
  struct Case {
    int seed, partitions;
    const char* pattern;
  };
  for (const Case c : {Case{28, 2, "0011001100110011"}, Case{20, 2, "0001000100010001"}, Case{16, 2, "1000100010001000"},
                       Case{260, 3, "0000000011221122"}, Case{36, 2, "0000111100000000"}}) {
    CAPTURE(c.seed);
    std::string got;
    for (int i = 0; i < 16; ++i) got += static_cast<char>('0' + softpbr::image::detail::astc_partition(c.seed, i & 3, i >> 2, c.partitions));
    CHECK(got == c.pattern);
  }
}

TEST_CASE("uastc: ASTC endpoint unquantization matches the specification's tables at their ends and middles") {
  using softpbr::image::detail::astc_unquantize_endpoint;
  // ASTC §23.12: 3 levels are 0, 128, 255; 5 levels 0, 64, 128, 191, 255; a trit range's
  // values in BISE order (trit above the bit) mirror on the low bit: 6 levels read 0, 255,
  // 51, 204, 102, 153;
  // bit ranges replicate their bits; every range's value 0 is 0.
  CHECK(astc_unquantize_endpoint(1, 0) == 0);
  CHECK(astc_unquantize_endpoint(1, 1) == 128);
  CHECK(astc_unquantize_endpoint(1, 2) == 255);
  CHECK(astc_unquantize_endpoint(3, 2) == 128);  // 5 levels: 0, 64, 128, 191, 255
  CHECK(astc_unquantize_endpoint(3, 3) == 191);
  const int six[6] = {0, 255, 51, 204, 102, 153};
  for (int v = 0; v < 6; ++v) CHECK(astc_unquantize_endpoint(4, v) == six[v]);
  for (int range = 0; range <= 20; ++range) {
    CAPTURE(range);
    CHECK(astc_unquantize_endpoint(range, 0) == 0);
  }
  CHECK(astc_unquantize_endpoint(20, 173) == 173);
  CHECK(astc_unquantize_endpoint(8, 15) == 255);
  CHECK(astc_unquantize_endpoint(11, 16) == 132);
}

TEST_CASE("ktx2: the fuzz findings are refused with one line") {
  for (const char* finding : {"ktx2-uastc-basislz-overread"}) {
    CAPTURE(finding);
    std::ifstream in(std::filesystem::path(SOFTPBR_SOURCE_DIR) / "fuzz/findings" / finding, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    REQUIRE(!bytes.empty());
    check_refused(bytes, "");
  }
}
