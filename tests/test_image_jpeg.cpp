// softpbr::image JPEG loading: round trips through stbi_write_jpg, and hostile files (cut
// short, garbage structure, frame headers claiming too much) refused before stb decodes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "image_helpers.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

namespace image = softpbr::image;
using namespace image_test;

namespace {

// The error of loading `bytes` as a JPEG buffer named `name`, or "" when it loads.
std::string jpeg_error(const std::vector<std::uint8_t>& bytes, const std::string& name,
                       const image::Limits& limits = {}) {
  try {
    image::load_jpeg(bytes, name, limits);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("JPEG: a file written by stbi_write_jpg loads at its size within the codec's error, alpha 255, from a file "
          "and from memory alike") {
  const fs::path dir = scratch("image_jpeg_round_trip");
  struct Case {
    int w, h, components, quality;
  };
  // 4:4:4 and subsampled 4:2:0 colour, grey, RGBA (alpha dropped), 1x1 and sizes that are
  // not whole 8x8 blocks or MCUs.
  const Case cases[] = {{1, 1, 3, 95}, {17, 5, 3, 95}, {17, 5, 3, 60}, {16, 16, 1, 95}, {33, 9, 4, 95}, {8, 40, 3, 80}};
  for (const Case& c : cases) {
    CAPTURE(c.w);
    CAPTURE(c.h);
    CAPTURE(c.components);
    CAPTURE(c.quality);
    const image::Image8 original = smooth8(c.w, c.h);
    const std::vector<std::uint8_t> jpeg = jpeg_of(original, c.components, c.quality);
    REQUIRE(jpeg.size() > 100);
    const fs::path path = dir / "round.jpg";
    write_bytes(path, jpeg);
    const image::Image8 loaded = image::load_jpeg(path);
    REQUIRE(loaded.width == c.w);
    REQUIRE(loaded.height == c.h);
    REQUIRE(loaded.rgba.size() == original.rgba.size());
    int worst = 0;
    for (std::size_t i = 0; i < loaded.rgba.size(); i += 4)
      for (std::size_t k = 0; k < 4; ++k) {
        // Grey files hold the red channel in all three.
        const int want = k == 3 ? 255 : original.rgba[i + (c.components == 1 ? 0 : k)];
        worst = std::max(worst, std::abs(int{loaded.rgba[i + k]} - want));
      }
    CHECK(worst <= (c.quality >= 90 ? 6 : 16));
    CHECK(image::load_jpeg(jpeg, "round.jpg").rgba == loaded.rgba);
    CHECK(image::load_image8(path).rgba == loaded.rgba);
  }
}

TEST_CASE("JPEG: every prefix of a valid file is refused before decoding, with an error naming the buffer") {
  const std::vector<std::uint8_t> whole = jpeg_of(smooth8(24, 16), 3, 75);
  REQUIRE(jpeg_error(whole, "whole.jpg").empty());
  for (std::size_t n = 0; n < whole.size(); ++n) {
    CAPTURE(n);
    const std::string message = jpeg_error({whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n)}, "cut.jpg");
    CHECK(message.rfind("cut.jpg: ", 0) == 0);
  }
  // Past the signature, the walk itself says so.
  CHECK(jpeg_error({whole.begin(), whole.end() - 2}, "cut.jpg").find("truncated") != std::string::npos);
  CHECK(jpeg_error({whole.begin(), whole.begin() + 20}, "cut.jpg").find("truncated") != std::string::npos);
}

TEST_CASE("JPEG: garbage structure is refused before decoding and says what is wrong") {
  const std::vector<std::uint8_t> whole = jpeg_of(smooth8(16, 16), 3, 75);
  const std::size_t sof = find_marker(whole, 0xc0), sos = find_marker(whole, 0xda);
  REQUIRE(sof > 0);
  REQUIRE(sos > sof);
  struct Case {
    const char* name;
    std::vector<std::uint8_t> bytes;
    const char* says;
  };
  std::vector<Case> cases;
  auto patched = [&](std::size_t at, std::uint8_t value) {
    std::vector<std::uint8_t> b = whole;
    b[at] = value;
    return b;
  };
  // A segment length running past the end of the file (the first segment after SOI).
  cases.push_back({"long-segment", patched(4, 0xff), "claims"});
  // Not a marker where one must be.
  std::vector<std::uint8_t> no_marker(whole.begin(), whole.begin() + 2);
  no_marker.insert(no_marker.end(), {0xff, 0xe0, 0x00, 0x04, 0x00, 0x00, 0x12, 0x34});
  cases.push_back({"no-marker", no_marker, "is not a marker"});
  cases.push_back({"12-bit", patched(sof + 4, 12), "12-bit"});
  cases.push_back({"two-components", patched(sof + 9, 2), "components"});
  cases.push_back({"zero-height", [&] {
                     std::vector<std::uint8_t> b = patched(sof + 5, 0);
                     b[sof + 6] = 0;
                     return b;
                   }(),
                   "a side of 0"});
  cases.push_back({"arithmetic", patched(sof + 1, 0xc9), "arithmetic"});
  cases.push_back({"scan-first", [&] {  // the SOF marker renamed to an APP segment
                     return patched(sof + 1, 0xe5);
                   }(),
                   "scan before the frame header"});
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const std::string message = jpeg_error(c.bytes, c.name);
    CAPTURE(message);
    CHECK(message.rfind(std::string(c.name) + ": ", 0) == 0);
    CHECK(message.find(c.says) != std::string::npos);
  }
}

TEST_CASE("JPEG: a frame header declaring 20000 pixels wide is refused before decoding, naming the size") {
  std::vector<std::uint8_t> jpeg = jpeg_of(smooth8(16, 8), 3, 75);
  const std::size_t sof = find_marker(jpeg, 0xc0);
  REQUIRE(sof > 0);
  jpeg[sof + 7] = 20000 >> 8;  // width, big-endian, after length, precision and height
  jpeg[sof + 8] = 20000 & 0xff;
  const std::string message = jpeg_error(jpeg, "wide.jpg");
  CHECK(message == "wide.jpg: image size 20000x8 is outside 1x1 .. 16384x16384");
}

TEST_CASE("JPEG: a baseline file whose coded data is too short for the blocks its frame header claims is refused") {
  // 8000x8000 within the side and byte limits, but 1M blocks cannot fit in the few bytes
  // of a 16x8 image's data: stb_image would decode them from zeros read past the end.
  std::vector<std::uint8_t> jpeg = jpeg_of(smooth8(16, 8), 1, 75);
  const std::size_t sof = find_marker(jpeg, 0xc0);
  REQUIRE(sof > 0);
  jpeg[sof + 5] = 8000 >> 8, jpeg[sof + 6] = 8000 & 0xff;
  jpeg[sof + 7] = 8000 >> 8, jpeg[sof + 8] = 8000 & 0xff;
  const std::string message = jpeg_error(jpeg, "claims.jpg");
  CAPTURE(message);
  CHECK(message.rfind("claims.jpg: cannot decode (truncated: ", 0) == 0);
  CHECK(message.find("blocks of a 8000x8000 image") != std::string::npos);
}

TEST_CASE("JPEG: decoded bytes count stb's component planes, the limit refuses before decoding") {
  // 16x16: 1024 bytes of RGBA, and stb_image_write's YCbCr 4:2:0 planes (it writes three
  // components even for grey): 16x16 of Y, 8x8 each of Cb and Cr.
  const std::vector<std::uint8_t> jpeg = jpeg_of(smooth8(16, 16), 1, 90);
  image::Limits limits;
  limits.max_decoded_bytes = 1024 + 256 + 2 * 64;
  CHECK(jpeg_error(jpeg, "fits.jpg", limits).empty());
  limits.max_decoded_bytes = 1024 + 256 + 2 * 64 - 1;
  CHECK(jpeg_error(jpeg, "over.jpg", limits) ==
        "over.jpg: image size 16x16 needs 1408 bytes decoded, over the limit of 1407");
}

TEST_CASE("JPEG: a Huffman table of more than 256 codes, or with more codes of a length than fit, is refused before "
          "stb builds it") {
  // fuzz_image's finding (UBSan, index 257 out of bounds): stb_image 2.27 copies a DHT
  // table's code lengths into a 257-entry array without checking their count
  // (fuzz/findings/jpeg-dht-overflow).
  const std::vector<std::uint8_t> whole = jpeg_of(smooth8(16, 16), 3, 75);
  const std::size_t dht = find_marker(whole, 0xc4);
  REQUIRE(dht > 0);
  std::vector<std::uint8_t> many = whole;
  for (int bits = 9; bits <= 16; ++bits) many[dht + 4 + static_cast<std::size_t>(bits)] = 200;  // counts after Tc/Th
  CHECK(jpeg_error(many, "many.jpg").rfind("many.jpg: cannot decode (Huffman table of ", 0) == 0);
  std::vector<std::uint8_t> crowded = whole;
  crowded[dht + 5] = 3;  // three 1-bit codes
  CHECK(jpeg_error(crowded, "crowded.jpg") ==
        "crowded.jpg: cannot decode (Huffman table: more codes of length 1 than fit)");
  const std::vector<std::uint8_t> finding = read_bytes(fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "findings" / "jpeg-dht-overflow");
  REQUIRE(finding.size() > 1);
  CHECK(jpeg_error({finding.begin() + 1, finding.end()}, "finding.jpg").find("Huffman table") != std::string::npos);
}

TEST_CASE("JPEG: coded data that ends inside a block loads as a damaged image or is refused, in one line") {
  // fuzz_image's finding (UBSan: shift exponent 33 inside stb_image 2.27, which takes more
  // bits than are left; fuzz/findings/jpeg-shift-exponent): no memory is touched, so the
  // outcome is a damaged image or stb's error, never more.
  const std::vector<std::uint8_t> finding =
      read_bytes(fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "findings" / "jpeg-shift-exponent");
  REQUIRE(finding.size() > 1);
  const std::string message = jpeg_error({finding.begin() + 1, finding.end()}, "finding.jpg");
  if (!message.empty()) CHECK(message.rfind("finding.jpg: ", 0) == 0);
  CHECK(message.find('\n') == std::string::npos);
}

TEST_CASE("read_image_header: the size of PNG and JPEG files from their headers, without decoding, 0x0 when cut short") {
  const image::Image8 original = smooth8(33, 9);
  const std::vector<std::uint8_t> jpeg = jpeg_of(original, 3, 90);
  const std::vector<std::uint8_t> png = image::encode_png(original, "h.png");
  image::ImageHeader h = image::read_image_header(jpeg);
  CHECK(h.format == "jpeg");
  CHECK(h.width == 33);
  CHECK(h.height == 9);
  h = image::read_image_header(png);
  CHECK(h.format == "png");
  CHECK(h.width == 33);
  CHECK(h.height == 9);
  // A PNG header claiming 30000x30000 is reported as such (and nothing is allocated).
  std::vector<std::uint8_t> huge(png.begin(), png.begin() + 33);
  huge[16] = huge[20] = 0;
  huge[17] = huge[21] = 0;
  huge[18] = huge[22] = 0x75;
  huge[19] = huge[23] = 0x30;
  h = image::read_image_header(huge);
  CHECK(h.width == 30000);
  CHECK(h.height == 30000);
  // Cut short: the format, no size.
  h = image::read_image_header(std::span<const std::uint8_t>(png.data(), 12));
  CHECK(h.format == "png");
  CHECK(h.width == 0);
  h = image::read_image_header(std::span<const std::uint8_t>(jpeg.data(), 4));
  CHECK(h.format == "jpeg");
  CHECK(h.width == 0);
  const std::uint8_t text[] = {'h', 'e', 'l', 'l', 'o'};
  CHECK(image::read_image_header(text).format.empty());
}
