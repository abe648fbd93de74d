// Hostile PNG and Radiance .hdr files: each loads or is a clear error naming the file, in
// bounded time. Regression tests for fuzz/fuzz_image's findings (softpbr::image's loaders;
// JPEG's are in test_image_jpeg.cpp).
#include <doctest/doctest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

#include "scratch_file.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

namespace image = softpbr::image;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return test_files::scratch_file("test_hostile_image", name); }

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

const std::string kHeader = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";

// One new-style RLE scanline of width 8: the marker, then per component a run of 8.
std::string rle_scanline() {
  std::string s = {2, 2, 0, 8};
  for (int k = 0; k < 4; ++k) s += {static_cast<char>(128 + 8), static_cast<char>(k == 3 ? 129 : 100)};
  return s;
}

// The file forms of the loaders, as callables (the names are overloaded).
const auto load_png = [](const fs::path& p) { return image::load_png(p); };
const auto load_hdr = [](const fs::path& p) { return image::load_hdr(p); };

// Loading `path` with `load` (load_png or load_hdr) throws a
// std::runtime_error whose message starts with "<path>: <what>".
template <class Load>
void check_refused(Load load, const fs::path& path, const std::string& what) {
  try {
    load(path);
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.rfind(path.string() + ": " + what, 0) == 0);
  }
}

}  // namespace

TEST_CASE("an .hdr file cut inside a run-length encoded scanline is an error, not an endless loop") {
  // fuzz_image's finding (timeout, stb_image 2.27 looping on zero counts read past the end):
  // a 8x3 RLE file whose data stops in the middle of the second scanline's runs.
  const std::string finding = kHeader + "-Y 3 +X 8\n" +
                              std::string("\x02\x02\x00\x08\x88\x64\x88\x32\x88\x19\x88\x80"
                                          "\x02\x02\x00\x08\x08\x88\x64\x05\x00\x00\x88\x2e\x32\x88\x19\x88\x80",
                                          30);  // the 29 bytes and the literal's terminating NUL
  const fs::path path = scratch("finding-rle-truncated.hdr");
  write(path, finding);
  check_refused(load_hdr, path, "truncated");
}

TEST_CASE("an .hdr file that ends on its resolution line is an error, not an image read from nothing") {
  // fuzz_image's finding (timeout): no newline after "-Y 16384 +X 1638", so no pixel data;
  // stb_image parsed the size and decoded 16384 x 1638 pixels of zeros from past the end.
  const std::string finding = kHeader + "-Y 16384 +X 1638" +
                              std::string("\xcc\xf5\xfd\xfd\xbf\xff\x43\x45\xbc\xbc\x02\x02\x38\xbc\xbc\xff", 16);
  const fs::path path = scratch("finding-no-data.hdr");
  write(path, finding);
  check_refused(load_hdr, path, "truncated");
}

TEST_CASE("an .hdr header line that starts with a NUL byte ends the header, as stb reads it, missing data is an error") {
  // fuzz_image's finding (timeout): stb_image reads header lines as C strings, so a line
  // starting with NUL is the empty line that ends the header; the resolution line after it
  // (-Y 16384 +X 1638, no pixel data) made stb decode 26M pixels from past the end, while
  // the truncation walk saw no empty line (fuzz/findings/hdr-nul-header-line).
  const fs::path path = scratch("finding-nul-line.hdr");
  using namespace std::string_literals;  // "…"s keeps the NUL byte
  write(path, "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\0IHDR\n-Y 16384 +X 1638\n\x01"s);
  check_refused(load_hdr, path, "truncated");
  const fs::path finding = fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "findings" / "hdr-nul-header-line";
  std::ifstream in(finding, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  REQUIRE(bytes.size() > 1);
  write(path, bytes.substr(1));  // without fuzz_image's selector byte
  check_refused(load_hdr, path, "truncated");
}

TEST_CASE("every prefix of a valid .hdr file is refused, the whole file loads") {
  struct Case {
    const char* name;
    std::string file;
    int width, height;
  };
  const Case cases[] = {
      {"rle", kHeader + "-Y 2 +X 8\n" + rle_scanline() + rle_scanline(), 8, 2},
      {"flat", kHeader + "-Y 1 +X 2\n" + std::string("\x80\x40\x20\x81\x01\x02\x03\x82", 8), 2, 1},
      // A scanline without the RLE marker switches the decoder to flat pixels.
      {"rle-then-flat", kHeader + "-Y 1 +X 8\n" + std::string(8 * 4, '\x81'), 8, 1},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const fs::path path = scratch(std::string("prefix-") + c.name + ".hdr");
    for (std::size_t n = kHeader.size(); n < c.file.size(); ++n) {  // from the resolution line on
      CAPTURE(n);
      write(path, c.file.substr(0, n));
      CHECK_THROWS_AS(image::load_hdr(path), std::runtime_error);
    }
    write(path, c.file);
    const image::ImageF image = image::load_hdr(path);
    CHECK(image.width == c.width);
    CHECK(image.height == c.height);
  }
}

TEST_CASE("only PNG and .hdr files reach stb_image: other formats are refused by their first bytes") {
  // fuzz_image's finding (timeout): 24 bytes of run-length encoded grey TGA claiming
  // 3340 x 3854 pixels, which stb_image decoded from zeros read past the end.
  const std::string tga("\x01\x00\x0b\x00\x00\x31\x00\xb0\x42\x7e\x60\x0b\x0c\x0d\x0e\x0f\x10\x11\xf8\xeb\x15"
                        "\xc3\x16\x82",
                        24);
  struct Case {
    const char* name;
    std::string bytes;
  };
  const Case cases[] = {
      {"finding.tga", tga},
      {"huge.pgm", "P5 16384 16384 255\n"},
      // fuzz_image's finding (UBSan: signed overflow in stb's PNM header parser, which
      // stbi_info tried on any file before the signature checks).
      {"overflow.ppm", std::string("P696666666666b\0bb", 17)},
      {"huge.bmp", std::string("BM\x00\x00\x00\x00\x00\x00\x00\x00\x36\x00\x00\x00\x28\x00\x00\x00"
                               "\x00\x40\x00\x00\x00\x40\x00\x00\x01\x00\x18\x00",
                               30)},
  };
  for (const Case& c : cases)
    for (const bool hdr : {false, true}) {
      CAPTURE(c.name);
      CAPTURE(hdr);
      const fs::path path = scratch(c.name);
      write(path, c.bytes);
      if (hdr) check_refused(load_hdr, path, "not a readable image (no ");
      else check_refused(load_png, path, "not a readable image (no ");
    }
}

TEST_CASE("a PNG chunk claiming more bytes than the file has is refused before stb allocates them") {
  // fuzz_image's finding (malloc of 2 GiB): a 9x1 1-bit PNG whose second IDAT chunk
  // claims 0x5f80000b bytes in an 84-byte file.
  const std::string finding(
      "\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x00\x00\x09\x00\x00\x00\x01\x01\x00\x00\x00\x00\x24\xb9"
      "\xb9\xd0\x00\x00\x00\x0bIDATx\x9c\x63\x24\xb9\xb9\xd0\x00\x00\x00\x00\x60\xe0\x00\x02\x5f\x80\x00"
      "\x0bIDAT\xae\x42\x60\x82\x63\x24\xb9\xb9\xd0\x00\x00\x00\x0bIL:\x00\x00\xe7",
      83);
  const fs::path path = scratch("finding-idat-claim.png");
  write(path, finding);
  check_refused(load_png, path, "cannot decode (truncated: chunk 'IDAT'");
}

TEST_CASE("image headers claiming more than kMaxTargetSize a side are refused before decoding") {
  // A PNG header (IHDR) claiming 100000 x 100000 pixels, and an .hdr resolution line
  // claiming 100000 x 100000; neither has the data.
  const std::string png_ihdr("\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR\x00\x01\x86\xa0\x00\x01\x86\xa0\x08\x02\x00\x00\x00"
                             "\x00\x00\x00\x00\x00\x00\x00\x00IEND\xae\x42\x60\x82",
                             45);
  write(scratch("huge.png"), png_ihdr);
  CHECK_THROWS_AS(image::load_png(scratch("huge.png")), std::runtime_error);
  write(scratch("huge.hdr"), kHeader + "-Y 100000 +X 100000\n");
  try {
    image::load_hdr(scratch("huge.hdr"));
    FAIL("no exception");
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find("100000x100000") != std::string::npos);
  }
}

TEST_CASE("a PNG whose compressed data is far too short for its declared size is refused before the image is allocated") {
  // IHDR: 4096 x 4096 RGBA (64 MiB decoded), then 1000 bytes of IDAT: deflate expands at
  // most 1032-fold, so they cannot hold the image (libspng allocated it, then said "IDAT
  // stream too short"; a 1.4 kB .glb declaring 16384² reached 1 GiB and 1.9 s).
  auto chunk = [](const std::string& type, const std::string& data) {
    const auto n = static_cast<std::uint32_t>(data.size());
    std::string c = {static_cast<char>(n >> 24), static_cast<char>(n >> 16), static_cast<char>(n >> 8), static_cast<char>(n)};
    return c + type + data + std::string(4, '\0');  // (the CRC: never reached)
  };
  const std::string ihdr("\x00\x00\x10\x00\x00\x00\x10\x00\x08\x06\x00\x00\x00", 13);
  const std::string png = "\x89PNG\r\n\x1a\n" + chunk("IHDR", ihdr) + chunk("IDAT", std::string(1000, 'x')) + chunk("IEND", "");
  const fs::path path = scratch("short-idat.png");
  write(path, png);
  check_refused(load_png, path,
                "cannot decode (truncated: its 1000 bytes of compressed image data (IDAT) cannot hold the 4096x4096 image "
                "it declares (67108864 bytes; deflate expands at most 1032-fold))");
  // A uniform image compresses close to that limit, and loads.
  image::Image8 flat(2048, 2048, image::PixelVector<std::uint8_t>(std::size_t{2048} * 2048 * 4, 200));
  const std::vector<std::uint8_t> encoded = image::encode_png(flat, "flat.png");
  CAPTURE(encoded.size());
  CHECK(image::load_png(encoded, "flat.png").rgba == flat.rgba);
}
