// WebP and AVIF textures (image/src/webp.cpp, avif.cpp): lossless files decode to their
// source bit for bit, lossy ones within 1-2 of libwebp's and libavif's own conversions
// (dwebp and avifdec wrote the .png references beside them, avifdec with bilinear
// upsampling, as softpbr upsamples) and to pinned bits on every build and CPU (this file is
// in the determinism matrix); cut files and hostile headers are one line naming the file,
// refused before decoding. The files in tests/webp_avif/ were made with cwebp and avifenc
// from the PNGs there (docs/testing.md).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "softpbr/image/load.h"

namespace image = softpbr::image;
namespace fs = std::filesystem;

namespace {

fs::path file(const std::string& name) { return fs::path(SOFTPBR_SOURCE_DIR) / "tests" / "webp_avif" / name; }

std::vector<std::uint8_t> bytes_of(const std::string& name) { return image::read_file(file(name)); }

std::uint64_t fnv1a(const image::Image8& im) {
  std::uint64_t h = 1469598103934665603ull;
  for (std::uint8_t b : im.rgba) {
    h ^= b;
    h *= 1099511628211ull;
  }
  return h;
}

// The largest difference of each channel; colour compared premultiplied when `premultiplied`
// (where alpha is small, dividing it back magnifies the reference's own rounding).
std::vector<int> max_difference(const image::Image8& a, const image::Image8& b, bool premultiplied = false) {
  REQUIRE(a.width == b.width);
  REQUIRE(a.height == b.height);
  std::vector<int> d(4, 0);
  for (std::size_t i = 0; i < a.rgba.size(); ++i) {
    int x = a.rgba[i], y = b.rgba[i];
    if (premultiplied && i % 4 != 3) {
      x = (x * a.rgba[i - i % 4 + 3] + 127) / 255;
      y = (y * b.rgba[i - i % 4 + 3] + 127) / 255;
    }
    d[i % 4] = std::max(d[i % 4], std::abs(x - y));
  }
  return d;
}

std::string error_of(std::span<const std::uint8_t> bytes, const image::Limits& limits = {}) {
  try {
    image::load_image8(bytes, "t.img", limits);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "(no error)";
}

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) | (std::uint32_t{b[at + 2]} << 8) | b[at + 3];
}
void put_be32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) b[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(v >> (24 - 8 * k));
}
// Where the four-character box type `type` first appears (its payload follows it).
std::size_t find_box(const std::vector<std::uint8_t>& b, const char* type) {
  const std::string t(type);
  const auto it = std::search(b.begin(), b.end(), t.begin(), t.end());
  REQUIRE(it != b.end());
  return static_cast<std::size_t>(it - b.begin());
}

}  // namespace

TEST_CASE("webp: a lossless file decodes to its source PNG bit for bit, colour under zero alpha included") {
  const image::Image8 webp = image::load_webp(file("lossless.webp"));
  const image::Image8 png = image::load_png(file("pattern.png"));
  CHECK(webp.width == 13);
  CHECK(webp.height == 11);
  CHECK(webp.rgba == png.rgba);
  CHECK(image::load_image8(file("lossless.webp")).rgba == png.rgba);
}

TEST_CASE("webp: lossy files decode within 1 of libwebp's own RGB, alpha exact, to pinned bits") {
  struct Case {
    const char* file;
    const char* reference;
    std::uint64_t hash;
  };
  for (const Case& c : {Case{"lossy.webp", "lossy.dwebp.png", 0x4d47e990d1cfaf44ull},
                        Case{"lossy_alpha.webp", "lossy_alpha.dwebp.png", 0xe715a80d5bbbecbdull}}) {
    const std::string name(c.file);
    CAPTURE(name);
    const image::Image8 ours = image::load_image8(file(c.file));
    const std::vector<int> d = max_difference(ours, image::load_png(file(c.reference)));
    CHECK(d[0] <= 1);
    CHECK(d[1] <= 1);
    CHECK(d[2] <= 1);
    CHECK(d[3] == 0);
    CHECK(fnv1a(ours) == c.hash);
  }
}

TEST_CASE("avif: a lossless file (identity matrix, 4:4:4, full range) decodes to its source PNG bit for bit") {
  const image::Image8 avif = image::load_avif(file("lossless.avif"));
  CHECK(avif.rgba == image::load_png(file("pattern.png")).rgba);
}

TEST_CASE("avif: every matrix, range, depth and subsampling decodes within 2 (3 premultiplied) of libavif's own conversion, to pinned bits") {
  struct Case {
    const char* file;  // how avifenc made it is in its name
    int tolerance;
    bool premultiplied;
    std::uint64_t hash;
  };
  for (const Case& c : {Case{"420_bt601_limited.avif", 2, false, 0xc3b63f7a9e915e0dull},
                        Case{"422_bt709_limited_10bit.avif", 1, false, 0x6c90776a8f8eafdfull},
                        Case{"444_bt2020_full_12bit_alpha.avif", 1, false, 0xaaffb4b0ed0dc8e3ull},
                        Case{"400_mono.avif", 0, false, 0xff9dd5032b4ec681ull},
                        Case{"420_unspecified_full_premultiplied.avif", 3, true, 0xd701533b992da248ull}}) {
    const std::string name(c.file);
    CAPTURE(name);
    const image::Image8 ours = image::load_image8(file(name));
    const image::Image8 reference = image::load_png(file(name.substr(0, name.size() - 5) + ".avifdec.png"));
    const std::vector<int> d = max_difference(ours, reference, c.premultiplied);
    CAPTURE(d[0]);
    CAPTURE(d[1]);
    CAPTURE(d[2]);
    CHECK(std::max({d[0], d[1], d[2]}) <= c.tolerance);
    CHECK(d[3] == 0);
    CHECK(fnv1a(ours) == c.hash);
  }
  // 4:0:0 is grey.
  const image::Image8 mono = image::load_avif(file("400_mono.avif"));
  for (std::size_t i = 0; i < mono.rgba.size(); i += 4) {
    CHECK(mono.rgba[i] == mono.rgba[i + 1]);
    CHECK(mono.rgba[i] == mono.rgba[i + 2]);
  }
}

TEST_CASE("webp and avif: picked by their content, their sizes read from the headers without decoding") {
  for (const std::string name : {"lossy.webp", "lossless.webp", "420_bt601_limited.avif", "lossless.avif"}) {
    CAPTURE(name);
    const std::vector<std::uint8_t> b = bytes_of(name);
    const image::ImageHeader h = image::read_image_header(b);
    const bool webp = name.find(".webp") != std::string::npos;
    CHECK(h.format == (webp ? "webp" : "avif"));
    const bool small = name.rfind("lossless", 0) == 0;
    CHECK(h.width == (small ? 13 : 24));
    CHECK(h.height == (small ? 11 : 18));
    std::vector<std::uint8_t> cut(b.begin(), b.begin() + 10);  // too short to say
    CHECK(image::read_image_header(cut).width == 0);
  }
  CHECK(error_of(bytes_of("pattern.png")) == "(no error)");
  const std::vector<std::uint8_t> png = bytes_of("pattern.png");
  try {
    image::load_webp(png, "p.png");
    FAIL("a PNG loaded as WebP");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()) == "p.png: is a PNG image; load it with load_png (or load_image8)");
  }
  try {
    image::load_imagef(bytes_of("lossless.avif"), "a.avif");
    FAIL("an AVIF loaded as a float image");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()) == "a.avif: is an 8-bit image; load it with load_image8");
  }
}

TEST_CASE("webp hostile: a cut file, a size over the limits, and a header over the side limit are one line each, before decoding") {
  const std::vector<std::uint8_t> lossy = bytes_of("lossy.webp");
  std::vector<std::uint8_t> cut(lossy.begin(), lossy.begin() + 200);
  CHECK(error_of(cut) == "t.img: truncated: the RIFF header says " + std::to_string(lossy.size()) + " bytes, the file has 200");
  cut.resize(12);  // the RIFF header alone
  CHECK(error_of(cut) == "t.img: truncated: the RIFF header says " + std::to_string(lossy.size()) + " bytes, the file has 12");
  std::vector<std::uint8_t> tiny = lossy;
  tiny[4] = 4, tiny[5] = tiny[6] = tiny[7] = 0;  // a RIFF size that holds no chunk
  CHECK(error_of(tiny) == "t.img: not a readable image (its RIFF size 4 holds no WebP chunk)");
  // VP8L (WebP lossless bitstream specification, 3.): after the signature 0x2f, 14 bits of
  // width − 1 and 14 of height − 1, little-endian. 16384² is legal and 11 bytes a pixel.
  std::vector<std::uint8_t> big = bytes_of("lossless.webp");
  REQUIRE(big[20] == 0x2f);
  big[21] = 0xff, big[22] = 0xff, big[23] = 0xff, big[24] = static_cast<std::uint8_t>(big[24] | 0x0f);
  CHECK(error_of(big) == "t.img: image size 16384x16384 needs 2952790016 bytes decoded, over the limit of 1073741824");
  image::Limits small;
  small.max_side = 8;
  CHECK(error_of(bytes_of("lossless.webp"), small) == "t.img: image size 13x11 is outside 1x1 .. 8x8");
  // A damaged bitstream inside a whole file.
  std::vector<std::uint8_t> damaged = lossy;
  for (std::size_t i = 40; i < damaged.size(); ++i) damaged[i] = static_cast<std::uint8_t>(damaged[i] ^ 0x5a);
  const std::string m = error_of(damaged);
  CAPTURE(m);
  CHECK((m == "(no error)" || m.rfind("t.img: cannot decode (", 0) == 0));  // VP8 may decode garbage
  CHECK(m.find('\n') == std::string::npos);
}

TEST_CASE("avif hostile: a cut file, a size over the limits, and an unsupported matrix are one line each, before decoding") {
  const std::vector<std::uint8_t> good = bytes_of("420_bt601_limited.avif");
  for (std::size_t keep : {std::size_t{40}, std::size_t{300}, good.size() - 1}) {
    CAPTURE(keep);
    const std::string m = error_of(std::vector<std::uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(keep)));
    CHECK(m.rfind("t.img: cannot decode (Truncated data", 0) == 0);
    CHECK(m.find('\n') == std::string::npos);
  }
  // ISO/IEC 23008-12 6.5.3: ispe's payload is version and flags, then width and height.
  const std::size_t ispe = find_box(good, "ispe") + 8;
  REQUIRE(be32(good, ispe) == 24);
  std::vector<std::uint8_t> big = good;
  put_be32(big, ispe, 16384);
  put_be32(big, ispe + 4, 16384);
  CHECK(error_of(big) == "t.img: image size 16384x16384 needs 3221225472 bytes decoded, over the limit of 1073741824");
  put_be32(big, ispe, 20000);
  put_be32(big, ispe + 4, 4);
  CHECK(error_of(big) == "t.img: image size 20000x4 is outside 1x1 .. 16384x16384");
  image::Limits small;
  small.max_side = 16;
  CHECK(error_of(good, small) == "t.img: image size 24x18 is outside 1x1 .. 16x16");
  // colr nclx (ISO/IEC 23008-12 6.5.5): colour_type, then primaries, transfer and matrix
  // (16 bits each). 8 is YCgCo.
  std::vector<std::uint8_t> ycgco = good;
  const std::size_t nclx = find_box(ycgco, "nclx");
  REQUIRE(ycgco[nclx + 9] == 6);
  ycgco[nclx + 9] = 8;
  CHECK(error_of(ycgco) ==
        "t.img: matrix coefficients 8 are not supported (0 identity, 1 BT.709, 2 unspecified, 5 and 6 BT.601, 9 BT.2020)");
  // An ftyp box without an AVIF brand (a HEIF image) is no AVIF.
  std::vector<std::uint8_t> heif = good;
  for (std::size_t at = 8; at + 4 <= be32(good, 0); at += 4)
    if (std::string(heif.begin() + static_cast<std::ptrdiff_t>(at), heif.begin() + static_cast<std::ptrdiff_t>(at) + 4) == "avif")
      heif[at + 3] = 'x';
  CHECK(error_of(heif) == "t.img: not a readable image (no PNG, JPEG, KTX2, WebP or AVIF signature)");
}
