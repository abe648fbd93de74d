// softpbr::image: loading from memory as from files, the limits checked before decoding,
// OpenEXR round trips and hostile files, and atomic writes of .png, .hdr and .exr.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "image_helpers.h"
#include "softpbr/image/load.h"
#include "softpbr/image/memory.h"
#include "softpbr/image/write.h"

namespace image = softpbr::image;
using namespace image_test;

namespace {

// The error message of `f`, or "" when it does not throw std::runtime_error.
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

const std::string kHdrHeader = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n";

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

// The offset of `text` in `bytes` (it must be there).
std::size_t offset_of(const std::vector<std::uint8_t>& bytes, const std::string& text) {
  const auto it = std::search(bytes.begin(), bytes.end(), text.begin(), text.end());
  REQUIRE(it != bytes.end());
  return static_cast<std::size_t>(it - bytes.begin());
}

}  // namespace

TEST_CASE("loading from memory gives the file's pixels, and errors start with the buffer's name") {
  const fs::path dir = scratch("image_memory");
  image::write_png(dir / "a.png", smooth8(9, 4));
  write_bytes(dir / "a.jpg", jpeg_of(smooth8(9, 4), 3, 90));
  image::write_hdr(dir / "a.hdr", patternF(9, 4));
  image::write_exr(dir / "a.exr", patternF(9, 4));
  CHECK(image::load_png(read_bytes(dir / "a.png"), "x").rgba == image::load_png(dir / "a.png").rgba);
  CHECK(image::load_jpeg(read_bytes(dir / "a.jpg"), "x").rgba == image::load_jpeg(dir / "a.jpg").rgba);
  CHECK(image::load_image8(read_bytes(dir / "a.jpg"), "x").rgba == image::load_jpeg(dir / "a.jpg").rgba);
  CHECK(image::load_hdr(read_bytes(dir / "a.hdr"), "x").rgba == image::load_hdr(dir / "a.hdr").rgba);
  CHECK(image::load_exr(read_bytes(dir / "a.exr"), "x").rgba == image::load_exr(dir / "a.exr").rgba);
  CHECK(image::load_imagef(read_bytes(dir / "a.exr"), "x").rgba == image::load_exr(dir / "a.exr").rgba);

  const std::string name = "scene.glb: buffer view 3";
  const std::vector<std::uint8_t> garbage = bytes_of("not an image at all");
  const std::vector<std::function<void()>> loads = {
      [&] { image::load_png(garbage, name); },   [&] { image::load_jpeg(garbage, name); },
      [&] { image::load_image8(garbage, name); }, [&] { image::load_hdr(garbage, name); },
      [&] { image::load_exr(garbage, name); },   [&] { image::load_imagef(garbage, name); },
      [&] { image::load_png({}, name); },         [&] { image::load_exr({}, name); }};
  for (std::size_t i = 0; i < loads.size(); ++i) {
    CAPTURE(i);
    const std::string message = error_of(loads[i]);
    CAPTURE(message);
    CHECK(message.rfind(name + ": ", 0) == 0);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("load_image8 and load_imagef choose the decoder by the first bytes, a wrong loader names the right one") {
  const fs::path dir = scratch("image_sniff");
  image::write_png(dir / "png-named.jpg", smooth8(3, 2));
  write_bytes(dir / "jpeg-named.png", jpeg_of(smooth8(3, 2), 3, 90));
  image::write_hdr(dir / "hdr-named.exr", patternF(3, 2));
  image::write_exr(dir / "exr-named.hdr", patternF(3, 2));
  CHECK(image::load_image8(dir / "png-named.jpg").width == 3);
  CHECK(image::load_image8(dir / "jpeg-named.png").width == 3);
  CHECK(image::load_imagef(dir / "hdr-named.exr").width == 3);
  CHECK(image::load_imagef(dir / "exr-named.hdr").width == 3);
  struct Case {
    std::function<void()> load;
    std::string file, says;
  };
  const Case cases[] = {
      {[&] { image::load_png(dir / "jpeg-named.png"); }, "jpeg-named.png", "load it with load_jpeg"},
      {[&] { image::load_jpeg(dir / "png-named.jpg"); }, "png-named.jpg", "load it with load_png"},
      {[&] { image::load_hdr(dir / "exr-named.hdr"); }, "exr-named.hdr", "load it with load_exr"},
      {[&] { image::load_exr(dir / "hdr-named.exr"); }, "hdr-named.exr", "load it with load_hdr"},
      {[&] { image::load_image8(dir / "exr-named.hdr"); }, "exr-named.hdr", "load it with load_exr"},
      {[&] { image::load_imagef(dir / "png-named.jpg"); }, "png-named.jpg", "load it with load_image8"},
      {[&] { image::load_exr(dir / "png-named.jpg"); }, "png-named.jpg", "is an 8-bit image"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.file);
    const std::string message = error_of(c.load);
    CAPTURE(message);
    CHECK(message.rfind((dir / c.file).string() + ": ", 0) == 0);
    CHECK(message.find(c.says) != std::string::npos);
  }
}

TEST_CASE("PNG, .hdr and .exr headers declaring 20000 pixels wide are refused before decoding, naming the size") {
  // PNG: IHDR's big-endian width at byte 16.
  std::vector<std::uint8_t> png = image::encode_png(smooth8(4, 4), "png");
  png[16] = 0, png[17] = 0, png[18] = 20000 >> 8, png[19] = 20000 & 0xff;
  CHECK(error_of([&] { image::load_png(png, "wide.png"); }) == "wide.png: image size 20000x4 is outside 1x1 .. 16384x16384");
  // .hdr: the resolution line, with no data after it.
  CHECK(error_of([&] { image::load_hdr(bytes_of(kHdrHeader + "-Y 4 +X 20000\n"), "wide.hdr"); }) ==
        "wide.hdr: image size 20000x4 is outside 1x1 .. 16384x16384");
  // .exr: the dataWindow attribute's xMax (little-endian int32s xMin, yMin, xMax, yMax).
  std::vector<std::uint8_t> exr = image::encode_exr(patternF(4, 4), "exr");
  const std::size_t window = offset_of(exr, std::string("dataWindow\0box2i\0", 17)) + 17 + 4;
  const std::int32_t x_max = 19999;
  std::memcpy(&exr[window + 8], &x_max, 4);
  CHECK(error_of([&] { image::load_exr(exr, "wide.exr"); }) ==
        "wide.exr: data window (0, 0) - (19999, 3) is not 1 to 16384 pixels on each side");
}

TEST_CASE("Limits: max_side and max_decoded_bytes refuse an image before decoding, one just inside loads") {
  struct Case {
    const char* name;
    std::vector<std::uint8_t> bytes;
    bool is_float;
    std::uint64_t decoded;  // what the loader counts
  };
  const Case cases[] = {
      {"a.png", image::encode_png(smooth8(64, 32), "png"), false, 64 * 32 * 4},
      {"a.jpg", jpeg_of(smooth8(64, 32), 1, 90), false, 64 * 32 * 4 + 64 * 32 + 2 * 32 * 16},  // + Y, Cb, Cr (4:2:0)
      {"a.hdr", image::encode_hdr(patternF(64, 32), "hdr"), true, 64 * 32 * 16},
      {"a.exr", image::encode_exr(patternF(64, 32), "exr"), true, 64 * 32 * 16 + 64 * 32 * 4 * 4},  // + 4 planes
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const auto load = [&](const image::Limits& limits) {
      return error_of([&] {
        if (c.is_float) image::load_imagef(c.bytes, c.name, limits);
        else image::load_image8(c.bytes, c.name, limits);
      });
    };
    image::Limits limits;
    limits.max_decoded_bytes = c.decoded;
    CHECK(load(limits).empty());
    limits.max_decoded_bytes = c.decoded - 1;
    CHECK(load(limits).find("needs " + std::to_string(c.decoded) + " bytes decoded, over the limit of " +
                            std::to_string(c.decoded - 1)) != std::string::npos);
    limits = {};
    limits.max_side = 64;
    CHECK(load(limits).empty());
    limits.max_side = 63;
    CHECK_FALSE(load(limits).empty());
  }
  // The path forms also bound the file they read.
  const fs::path dir = scratch("image_limits");
  image::write_png(dir / "a.png", smooth8(64, 32));
  image::Limits small_file;
  small_file.max_file_bytes = 10;
  CHECK(error_of([&] { image::load_png(dir / "a.png", small_file); }).find("over the limit of 10") != std::string::npos);
}

TEST_CASE("OpenEXR: float RGBA written with write_exr loads back exactly, negatives kept, non-finite values as 0") {
  const fs::path dir = scratch("image_exr_round_trip");
  constexpr float kInf = std::numeric_limits<float>::infinity(), kNaN = std::numeric_limits<float>::quiet_NaN();
  image::ImageF im = patternF(5, 3);
  im.rgba[0] = -2.5f, im.rgba[1] = 1e-30f, im.rgba[2] = 65504.0f * 4, im.rgba[3] = 0.25f;
  im.rgba[4] = kInf, im.rgba[5] = kNaN, im.rgba[6] = -kInf, im.rgba[7] = kNaN;
  image::write_exr(dir / "a.exr", im);
  const image::ImageF back = image::load_exr(dir / "a.exr");
  REQUIRE(back.width == 5);
  REQUIRE(back.height == 3);
  image::ImageF want = im;
  for (int i = 4; i < 8; ++i) want.rgba[static_cast<std::size_t>(i)] = 0.0f;
  CHECK(back.rgba == want.rgba);
  // × scale on colour, not on alpha.
  const image::ImageF scaled = image::load_exr(image::encode_exr(patternF(2, 1), "s", 4.0f), "s");
  const image::ImageF plain = patternF(2, 1);
  for (std::size_t i = 0; i < plain.rgba.size(); ++i) CHECK(scaled.rgba[i] == (i % 4 == 3 ? plain.rgba[i] : plain.rgba[i] * 4));
}

TEST_CASE("OpenEXR: the command line's hostile files are refused with one line naming the file") {
  const fs::path hostile = fs::path(SOFTPBR_SOURCE_DIR) / "cli" / "tests" / "hostile";
  struct Case {
    const char* file;
    const char* says;
  };
  const Case cases[] = {{"data-window-overflow.exr", "data window (4096, -2147483648)"},
                        {"bad-pixel-data.exr", "not a readable OpenEXR file"},
                        {"piz-bitmap-overread.exr", "PIZ-compressed OpenEXR files are not supported"}};
  for (const Case& c : cases) {
    CAPTURE(c.file);
    const fs::path path = hostile / c.file;
    const std::string message = error_of([&] { image::load_exr(path); });
    CAPTURE(message);
    CHECK(message.rfind(path.string() + ": ", 0) == 0);
    CHECK(message.find(c.says) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("write_png, write_hdr and write_exr replace a file whole and leave no temporary file") {
  const fs::path dir = scratch("image_atomic");
  struct Case {
    const char* file;
    std::function<void(const fs::path&, int)> write;               // an image of width w
    std::function<std::vector<std::uint8_t>(int)> encode;          // the same bytes
  };
  const Case cases[] = {
      {"a.png", [](const fs::path& p, int w) { image::write_png(p, smooth8(w, 3)); },
       [](int w) { return image::encode_png(smooth8(w, 3), "png"); }},
      {"a.hdr", [](const fs::path& p, int w) { image::write_hdr(p, patternF(w, 3)); },
       [](int w) { return image::encode_hdr(patternF(w, 3), "hdr"); }},
      {"a.exr", [](const fs::path& p, int w) { image::write_exr(p, patternF(w, 3)); },
       [](int w) { return image::encode_exr(patternF(w, 3), "exr"); }},
  };
  std::size_t files = 0;
  for (const Case& c : cases) {
    CAPTURE(c.file);
    c.write(dir / c.file, 4);
    CHECK(read_bytes(dir / c.file) == c.encode(4));
    c.write(dir / c.file, 7);  // over the old one
    CHECK(read_bytes(dir / c.file) == c.encode(7));
    CHECK(files_in(dir) == ++files);
  }
}

TEST_CASE("a failed write throws naming the path, leaves no temporary file and leaves the old file as it was") {
  const fs::path dir = scratch("image_atomic_failure");
  // Tests run as root, so a read-only folder would not stop them: a parent that is a
  // regular file does, and so does a destination that is a folder with a file in it
  // (creating the temporary works, the rename fails).
  write_bytes(dir / "file", bytes_of("keep"));
  fs::create_directories(dir / "occupied");
  write_bytes(dir / "occupied" / "inside", bytes_of("keep"));
  write_bytes(dir / "old.hdr", bytes_of("old"));
  write_bytes(dir / "old.exr", bytes_of("old"));
  write_bytes(dir / "old.png", bytes_of("old"));
  const std::vector<std::function<void(const fs::path&)>> writers = {
      [](const fs::path& p) { image::write_hdr(p, patternF(2, 2)); },
      [](const fs::path& p) { image::write_exr(p, patternF(2, 2)); },
      [](const fs::path& p) { image::write_png(p, smooth8(2, 2)); }};
  for (std::size_t i = 0; i < writers.size(); ++i) {
    CAPTURE(i);
    for (const fs::path& target : {dir / "file" / "out", dir / "occupied"}) {
      CAPTURE(target);
      const std::string message = error_of([&] { writers[i](target); });
      CHECK(message.rfind(target.string() + ": ", 0) == 0);
    }
    CHECK(files_in(dir) == 5);
    CHECK(files_in(dir / "occupied") == 1);
    CHECK(read_bytes(dir / "file") == bytes_of("keep"));
  }
  // An image whose pixel data disagrees with its size: refused before anything is written.
  image::ImageF broken = patternF(2, 2);
  broken.rgba.pop_back();
  image::Image8 broken8 = smooth8(2, 2);
  broken8.rgba.pop_back();
  CHECK_THROWS_AS(image::write_hdr(dir / "old.hdr", broken), std::invalid_argument);
  CHECK_THROWS_AS(image::write_exr(dir / "old.exr", broken), std::invalid_argument);
  CHECK_THROWS_AS(image::write_png(dir / "old.png", broken8), std::invalid_argument);
  CHECK_THROWS_AS(image::write_png(dir / "old.png", image::Image8{}), std::invalid_argument);
  for (const char* f : {"old.hdr", "old.exr", "old.png"}) CHECK(read_bytes(dir / f) == bytes_of("old"));
  CHECK(files_in(dir) == 5);
}

TEST_CASE("pixel buffers of 4 MiB and more are value-initialized, copy and move as vectors, and on Linux map 2 MiB-aligned") {
  const std::size_t big = image::kHugePageBufferBytes / sizeof(float) + 3;  // just over the threshold
  for (const std::size_t n : {std::size_t{7}, std::size_t{1} << 16, big}) {
    CAPTURE(n);
    image::PixelVector<float> zero(n);
    CHECK(std::all_of(zero.begin(), zero.end(), [](float x) { return x == 0.0f; }));
    image::PixelVector<float> v(n, 0.5f);
    v[n - 1] = 2.0f;
    const image::PixelVector<float> copy = v;
    CHECK(copy == v);
    const float* buffer = v.data();
    image::PixelVector<float> moved = std::move(v);
    CHECK(moved.data() == buffer);  // the allocators compare equal: the buffer changes hands
    CHECK(moved == copy);
    moved.resize(n + 5);  // grows into a new buffer (or the same), keeping the values
    CHECK(std::equal(copy.begin(), copy.end(), moved.begin()));
    CHECK(moved[n + 4] == 0.0f);
  }
#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
#if !defined(__has_feature)
#define SOFTPBR_TEST_NO_ASAN 1
#elif !__has_feature(address_sanitizer)
#define SOFTPBR_TEST_NO_ASAN 1
#endif
#endif
#if defined(SOFTPBR_TEST_NO_ASAN)
  const image::PixelVector<std::uint8_t> mapped(image::kHugePageBufferBytes);
  CHECK(reinterpret_cast<std::uintptr_t>(mapped.data()) % (std::uintptr_t{2} << 20) == 0);
#endif
  // Image8 from a std::vector copies it; from a PixelVector takes it.
  const std::vector<std::uint8_t> pixels(16, 7);
  const image::Image8 a{2, 2, pixels};
  CHECK(std::equal(pixels.begin(), pixels.end(), a.rgba.begin(), a.rgba.end()));
  image::PixelVector<std::uint8_t> own(16, 9);
  const std::uint8_t* data = own.data();
  const image::Image8 b{2, 2, std::move(own)};
  CHECK(b.rgba.data() == data);
}
