// Targets and the API boundary: any target size is covered exactly once by a full-screen
// quad, partial edge tiles included; invalid sizes, tile sizes, frame order and indices
// throw; 8-bit resolve and PNG output.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "raster_helpers.h"
#include "softpbr/image/write.h"
#include "softpbr/simd/simd.h"

namespace {

namespace raster = softpbr::raster;
namespace test = softpbr::test;
namespace fs = std::filesystem;

const std::vector<glm::vec4> kFullScreen = {{-1, -1, 0, 1}, {1, -1, 0, 1}, {1, 1, 0, 1}, {-1, 1, 0, 1}};
const std::vector<std::uint32_t> kQuad = {0, 1, 2, 0, 2, 3};

// A fresh folder under the system's temporary folder, removed at the end of the scope.
struct TempDir {
  fs::path path;
  TempDir() {
    std::random_device rd;
    path = fs::temp_directory_path() / ("softpbr-test-" + std::to_string(rd()) + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

std::vector<unsigned char> read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("a full-screen quad covers every pixel of any target size exactly once, partial edge tiles included") {
  struct Case {
    int width, height, tile;
  };
  const Case cases[] = {{1, 1, 8},      {1, 1, 64},      {7, 5, 8},      {7, 5, 64},     {65, 33, 64},
                        {100, 37, 16},  {63, 65, 8},     {129, 2, 128},  {2, 129, 16},   {1920, 1080, 64},
                        {1920, 1080, 24}, {16384, 1, 64}, {1, 16384, 64}, {16384, 1, 8},  {1, 16384, 4096}};
  for (const Case& c : cases)
    for (const unsigned threads : {1u, 3u}) {
      // One pixel at a time with one thread, in packets of 16 with three.
      raster::Renderer renderer({.threads = threads, .tile_size = c.tile, .lanes = 16});
      const std::vector<int> counts =
          threads == 1 ? test::render_counts(renderer, c.width, c.height, kFullScreen, kQuad)
                       : test::render_counts<test::CountPacketShader>(renderer, c.width, c.height, kFullScreen, kQuad);
      CAPTURE(c.width);
      CAPTURE(c.height);
      CAPTURE(c.tile);
      CAPTURE(threads);
      CHECK(static_cast<long>(std::count(counts.begin(), counts.end(), 1)) == static_cast<long>(c.width) * c.height);
    }
}

TEST_CASE("begin_frame with ClearValues clears every pixel, also with no draw, without them the target is kept") {
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  raster::Target target(37, 21);
  target.clear({9, 9, 9, 9}, 0.125f);
  renderer.begin_frame(target);
  renderer.end_frame();
  CHECK(std::all_of(target.colors().begin(), target.colors().end(), [](glm::vec4 c) { return c == glm::vec4(9); }));
  CHECK(std::all_of(target.depths().begin(), target.depths().end(), [](float d) { return d == 0.125f; }));
  renderer.begin_frame(target, raster::ClearValues{{0.25f, 0.5f, 0.75f, 1.0f}, 0.5f});
  renderer.end_frame();
  CHECK(std::all_of(target.colors().begin(), target.colors().end(),
                    [](glm::vec4 c) { return c == glm::vec4(0.25f, 0.5f, 0.75f, 1.0f); }));
  CHECK(std::all_of(target.depths().begin(), target.depths().end(), [](float d) { return d == 0.5f; }));
  // Cleared then drawn over: the same bits as clearing the target first.
  raster::Target a(37, 21), b(37, 21);
  a.clear({0, 0, 0, 0}, 1.0f);
  renderer.begin_frame(a);
  renderer.draw(test::CountShader{}, std::span<const glm::vec4>(kFullScreen), kQuad, test::counting_state());
  renderer.end_frame();
  b.clear({5, 5, 5, 5}, 0.0f);
  renderer.begin_frame(b, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
  renderer.draw(test::CountShader{}, std::span<const glm::vec4>(kFullScreen), kQuad, test::counting_state());
  renderer.end_frame();
  CHECK(raster::hash_colors(a) == raster::hash_colors(b));
  CHECK(raster::hash_depths(a) == raster::hash_depths(b));
}

TEST_CASE("hash_colors and hash_depths are XXH3-64 of the little-endian float bytes (values from xxhsum -H3)") {
  // python3 -c "import struct,sys; sys.stdout.buffer.write(struct.pack('<4f',1,0,0,1)*2)" | xxhsum -H3
  raster::Target small(2, 1);
  small.clear({1.0f, 0.0f, 0.0f, 1.0f}, 1.0f);
  CHECK(raster::hash_colors(small) == 0x2ca2bee11d23a305ull);
  CHECK(raster::hash_depths(small) == 0x774376da7ad20e6bull);
  // 8976 colour bytes: XXH3's long-input path (over 240 bytes), a partial last stripe.
  raster::Target larger(33, 17);
  larger.clear({0.25f, 0.5f, 0.75f, 1.0f}, 0.5f);
  CHECK(raster::hash_colors(larger) == 0xcb98830ec1635f10ull);
  CHECK(raster::hash_depths(larger) == 0xabfef1fc0a82c236ull);
  // One bit of one sample changes the hash.
  raster::Target changed(33, 17);
  changed.clear({0.25f, 0.5f, 0.75f, 1.0f}, 0.5f);
  changed.color(32, 16).a = std::nextafter(1.0f, 2.0f);
  CHECK(raster::hash_colors(changed) != raster::hash_colors(larger));
}

TEST_CASE("invalid target sizes throw std::invalid_argument") {
  const int sizes[][2] = {{0, 1}, {1, 0}, {0, 0}, {-1, 5}, {5, -1}, {16385, 1}, {1, 16385}, {-16384, -16384}};
  for (const auto& s : sizes) {
    CAPTURE(s[0]);
    CAPTURE(s[1]);
    CHECK_THROWS_AS(raster::Target(s[0], s[1]), std::invalid_argument);
  }
  CHECK_NOTHROW(raster::Target(16384, 1));
  CHECK_NOTHROW(raster::Target(1, 16384));
}

TEST_CASE("tile sizes that are odd or outside [8, 4096] throw std::invalid_argument") {
  for (const int tile : {0, -8, 2, 6, 7, 9, 63, 4097, 4098, 8192}) {
    CAPTURE(tile);
    CHECK_THROWS_AS(raster::Renderer({.threads = 1, .tile_size = tile}), std::invalid_argument);
  }
  for (const int tile : {8, 10, 64, 250, 4096}) {
    raster::Renderer r({.threads = 1, .tile_size = tile});
    CHECK(r.tile_size() == tile);
  }
}

TEST_CASE("packet lane counts other than 0, 1, 4, 8 and 16 throw std::invalid_argument") {
  for (const int lanes : {-1, 2, 3, 5, 12, 17, 32}) {
    CAPTURE(lanes);
    CHECK_THROWS_AS(raster::Renderer({.threads = 1, .tile_size = 8, .lanes = lanes}), std::invalid_argument);
  }
  for (const int lanes : {1, 4, 8, 16}) {
    raster::Renderer r({.threads = 1, .tile_size = 8, .lanes = lanes});
    CHECK(r.lanes() == lanes);
  }
  raster::Renderer native({.threads = 1, .tile_size = 8, .lanes = 0, .dispatch = false});  // dispatch: see test_determinism
  CHECK(native.lanes() == softpbr::simd::kNativeWidth);
}

TEST_CASE("drawing or ending outside a frame, or beginning one twice, throws std::logic_error") {
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  raster::Target target(8, 8);
  const test::CountShader shader;
  const std::span<const glm::vec4> verts(kFullScreen);
  CHECK_THROWS_AS(renderer.draw(shader, verts, kQuad), std::logic_error);
  CHECK_THROWS_AS(renderer.end_frame(), std::logic_error);
  renderer.begin_frame(target);
  CHECK_THROWS_AS(renderer.begin_frame(target), std::logic_error);
  CHECK_NOTHROW(renderer.draw(shader, verts, kQuad));
  renderer.end_frame();
  CHECK_THROWS_AS(renderer.draw(shader, verts, kQuad), std::logic_error);
  CHECK_THROWS_AS(renderer.end_frame(), std::logic_error);
  // The renderer still works after all that.
  const std::vector<int> counts = test::render_counts(renderer, 8, 8, kFullScreen, kQuad);
  CHECK(std::count(counts.begin(), counts.end(), 1) == 64);
}

TEST_CASE("bad index buffers throw (out_of_range, invalid_argument) and draw nothing, the rest of the frame still draws") {
  raster::Renderer renderer({.threads = 2, .tile_size = 8});
  raster::Target target(16, 16);
  target.clear({0, 0, 0, 0});
  const test::CountShader shader;
  const std::span<const glm::vec4> verts(kFullScreen);
  const raster::DrawState state = test::counting_state();
  renderer.begin_frame(target);
  CHECK_THROWS_AS(renderer.draw(shader, verts, std::vector<std::uint32_t>{0, 1, 4}, state), std::out_of_range);
  CHECK_THROWS_AS(renderer.draw(shader, verts, std::vector<std::uint32_t>{0, 1, 2, 0, 2, 0xffffffffu}, state),
                  std::out_of_range);
  CHECK_THROWS_AS(renderer.draw(shader, verts, std::vector<std::uint32_t>{0, 1}, state), std::invalid_argument);
  CHECK_THROWS_AS(renderer.draw(shader, verts, std::vector<std::uint32_t>{0, 1, 2, 0}, state), std::invalid_argument);
  CHECK_THROWS_AS(renderer.draw(shader, verts.first(2), state), std::invalid_argument);  // non-indexed, 2 vertices
  CHECK_NOTHROW(renderer.draw(shader, verts, std::vector<std::uint32_t>{}, state));     // empty is fine
  renderer.draw(shader, verts, kQuad, state);
  renderer.end_frame();
  // Only the valid quad landed: every pixel exactly once.
  CHECK(std::all_of(target.colors().begin(), target.colors().end(), [](glm::vec4 c) { return c.r == 1.0f; }));
}

TEST_CASE("resolve_srgb8 encodes colour through the exact sRGB curve, alpha linearly, RGBA row-major from the top") {
  raster::Target target(256, 2);
  // Row 0: the exact decoded value of every code k encodes back to k; alpha k/255 → k.
  for (int k = 0; k < 256; ++k) {
    const float linear = static_cast<float>(raster::srgb_to_linear(k / 255.0));
    target.color(k, 0) = {linear, linear, linear, k / 255.0f};
  }
  // Row 1: known values and out-of-range inputs.
  const struct {
    glm::vec4 in;
    std::uint8_t out[4];
  } known[] = {{{0.0f, 1.0f, 0.5f, 0.5f}, {0, 255, 188, 128}},
               {{0.0031308f, 0.2158605f, 0.0f, 1.0f}, {10, 128, 0, 255}},  // 0.04045 · 255 = 10.3; 128.0
               {{-1.0f, 2.0f, NAN, NAN}, {0, 255, 0, 0}},
               {{INFINITY, -INFINITY, 1e-9f, -0.5f}, {255, 0, 0, 0}},
               {{0.25f, 0.75f, 0.05f, 2.0f}, {137, 225, 63, 255}}};
  for (std::size_t i = 0; i < std::size(known); ++i) target.color(static_cast<int>(i), 1) = known[i].in;
  const raster::Image8 image = raster::resolve_srgb8(target);
  REQUIRE(image.width == 256);
  REQUIRE(image.height == 2);
  REQUIRE(image.rgba.size() == 256u * 2u * 4u);
  int wrong = 0;
  for (int k = 0; k < 256; ++k)
    for (int c = 0; c < 4; ++c) wrong += image.rgba[4 * k + c] != k;
  CHECK(wrong == 0);
  for (std::size_t i = 0; i < std::size(known); ++i)
    for (int c = 0; c < 4; ++c) {
      CAPTURE(i);
      CAPTURE(c);
      CHECK(int{image.rgba[4 * (256 + i) + c]} == int{known[i].out[c]});
    }
}

TEST_CASE("write_png writes a complete PNG, an unwritable path throws and leaves no file") {
  TempDir dir;
  raster::Target target(13, 7);
  target.clear({0.5f, 0.25f, 1.0f, 1.0f});
  const raster::Image8 image = raster::resolve_srgb8(target);
  const fs::path file = dir.path / "out.png";
  softpbr::image::write_png(file, image);
  REQUIRE(fs::exists(file));
  const std::vector<unsigned char> bytes = read_bytes(file);
  REQUIRE(bytes.size() > 33);
  const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  CHECK(std::equal(signature, signature + 8, bytes.begin()));
  // IHDR: the first chunk, big-endian width and height.
  CHECK(std::string(bytes.begin() + 12, bytes.begin() + 16) == "IHDR");
  CHECK((bytes[16] << 24 | bytes[17] << 16 | bytes[18] << 8 | bytes[19]) == 13);
  CHECK((bytes[20] << 24 | bytes[21] << 16 | bytes[22] << 8 | bytes[23]) == 7);
  // Overwriting keeps a complete file, and nothing temporary is left beside it.
  softpbr::image::write_png(file, image);
  CHECK(read_bytes(file) == bytes);
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()) == 1);

  const fs::path missing = dir.path / "no-such-folder" / "out.png";
  CHECK_THROWS_AS(softpbr::image::write_png(missing, image), std::runtime_error);
  CHECK_FALSE(fs::exists(missing));
  CHECK_FALSE(fs::exists(missing.parent_path()));
  CHECK(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()) == 1);
  // An image whose pixel data does not match its size is refused before anything is written.
  raster::Image8 broken = image;
  broken.rgba.resize(broken.rgba.size() - 1);
  CHECK_THROWS_AS(softpbr::image::write_png(dir.path / "broken.png", broken), std::invalid_argument);
  CHECK_FALSE(fs::exists(dir.path / "broken.png"));
}

TEST_CASE("a target made with a pool starts with the samples of one made without: colour (0, 0, 0, 1), depth 1") {
  raster::ThreadPool pool(3);
  for (const int samples : {1, 4}) {
    CAPTURE(samples);
    const raster::Target serial(1031, 517, samples);  // 2.1 M samples: nine pieces, the last one short
    const raster::Target pooled(1031, 517, samples, &pool);
    CHECK(std::all_of(pooled.colors().begin(), pooled.colors().end(),
                      [](const glm::vec4& c) { return c == glm::vec4(0, 0, 0, 1); }));
    CHECK(std::all_of(pooled.depths().begin(), pooled.depths().end(), [](float d) { return d == 1.0f; }));
    CHECK(raster::hash_colors(pooled) == raster::hash_colors(serial));
    CHECK(raster::hash_depths(pooled) == raster::hash_depths(serial));
  }
}
