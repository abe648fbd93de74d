// Real Basis Universal files (tests/ktx2/*.ktx2: a procedural test pattern encoded by
// Binomial's encoder, the npm package ktx2-encoder 0.6.0): ETC1S in BasisLZ with a full mip
// chain, ETC1S with alpha slices at odd sizes, UASTC with Zstandard. Each level decodes to
// the FNV-1a 64 hash of the RGBA that Binomial's transcoder (npm three 0.187.0) gives it,
// written below by tests/ktx2/encode_samples.mjs (docs/testing.md says how): the comparison
// runs everywhere, without Node. Also: the bytes do not depend on the threads a decode is
// given (image::ParallelFor), nor does the error a bad block gives.
#include <doctest/doctest.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "ktx2_checks.h"
#include "ktx2_etc1s_sample.h"
#include "ktx2_writer.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"

namespace image = softpbr::image;
namespace fs = std::filesystem;

namespace {

fs::path file(const std::string& name) { return fs::path(SOFTPBR_SOURCE_DIR) / "tests" / "ktx2" / name; }

std::uint64_t fnv1a(const image::Image8& im) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (std::uint8_t b : im.rgba) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
  return h;
}

struct Expected {
  const char* file;
  int level, width, height;
  std::uint64_t hash;  // of the level's RGBA, as Basis Universal's transcoder decodes it
};

// node tests/ktx2/encode_samples.mjs /tmp/enc/node_modules tests/ktx2 (2026-12-07).
constexpr Expected kExpected[] = {
    {"etc1s_pattern_256x192.ktx2", 0, 256, 192, 0x5897813c969f6802ull},
    {"etc1s_pattern_256x192.ktx2", 1, 128, 96, 0xcb6182ad7db0959dull},
    {"etc1s_pattern_256x192.ktx2", 2, 64, 48, 0x6f1975812d80493full},
    {"etc1s_pattern_256x192.ktx2", 3, 32, 24, 0x122450b62e7505b5ull},
    {"etc1s_pattern_256x192.ktx2", 4, 16, 12, 0x59dd912af3546903ull},
    {"etc1s_pattern_256x192.ktx2", 5, 8, 6, 0x38e2528a72b8b0acull},
    {"etc1s_pattern_256x192.ktx2", 6, 4, 3, 0x262fb67a0ccf5b81ull},
    {"etc1s_pattern_256x192.ktx2", 7, 2, 1, 0x35712f589eba39eaull},
    {"etc1s_pattern_256x192.ktx2", 8, 1, 1, 0xece39b462765bf7bull},
    {"etc1s_alpha_pattern_150x100.ktx2", 0, 150, 100, 0x77012b5d0bbb5240ull},
    {"etc1s_alpha_pattern_150x100.ktx2", 1, 75, 50, 0x81180a2b86a5b38eull},
    {"etc1s_alpha_pattern_150x100.ktx2", 2, 37, 25, 0x86fabc0d7a219477ull},
    {"etc1s_alpha_pattern_150x100.ktx2", 3, 18, 12, 0x0f5aa4cedb3cb43dull},
    {"etc1s_alpha_pattern_150x100.ktx2", 4, 9, 6, 0xf3cbeb81e92fd4aeull},
    {"etc1s_alpha_pattern_150x100.ktx2", 5, 4, 3, 0x86672bda0c81e3feull},
    {"etc1s_alpha_pattern_150x100.ktx2", 6, 2, 1, 0xda1cc2b661117a91ull},
    {"etc1s_alpha_pattern_150x100.ktx2", 7, 1, 1, 0x2b78798082122ebdull},
    {"uastc_zstd_pattern_128x128.ktx2", 0, 128, 128, 0x7c7fbd894658bd52ull},
    {"uastc_zstd_pattern_128x128.ktx2", 1, 64, 64, 0xa4ce24e9bcf89e43ull},
    {"uastc_zstd_pattern_128x128.ktx2", 2, 32, 32, 0x064b902f89d389cbull},
    {"uastc_zstd_pattern_128x128.ktx2", 3, 16, 16, 0x7e35fb3a17793cf2ull},
    {"uastc_zstd_pattern_128x128.ktx2", 4, 8, 8, 0xaf447fd4cfdc6325ull},
    {"uastc_zstd_pattern_128x128.ktx2", 5, 4, 4, 0x101e65e929fbdc2dull},
    {"uastc_zstd_pattern_128x128.ktx2", 6, 2, 2, 0x2cd3538d004985aeull},
    {"uastc_zstd_pattern_128x128.ktx2", 7, 1, 1, 0x7bc7498d40c51cd8ull},
};

struct FileInfo {
  const char* file;
  const char* format;
  const char* supercompression;
  int levels;
};
constexpr FileInfo kFiles[] = {{"etc1s_pattern_256x192.ktx2", "ETC1S", "BasisLZ", 9},
                               {"etc1s_alpha_pattern_150x100.ktx2", "ETC1S", "BasisLZ", 8},
                               {"uastc_zstd_pattern_128x128.ktx2", "UASTC", "Zstandard", 8}};

// `threads` std::threads taking the tasks from a shared counter (the order they run in is
// the scheduler's), or, with `reversed`, every task on the caller, last first.
image::ParallelFor on_threads(int threads, bool reversed = false) {
  return [threads, reversed](std::size_t count, const std::function<void(std::size_t)>& task) {
    if (reversed) {
      for (std::size_t k = count; k-- > 0;) task(k);
      return;
    }
    std::atomic<std::size_t> next{0};
    std::vector<std::thread> pool;
    for (int i = 0; i < threads; ++i)
      pool.emplace_back([&] {
        for (std::size_t k = next++; k < count; k = next++) task(k);
      });
    for (std::thread& t : pool) t.join();
  };
}

std::vector<image::ParallelFor> ways_to_run() {
  return {on_threads(1), on_threads(2), on_threads(3), on_threads(8), on_threads(1, true)};
}

std::string error_of(const std::vector<std::uint8_t>& bytes, const image::ParallelFor& parallel) {
  try {
    image::load_ktx2(bytes, "t.ktx2", {}, nullptr, parallel);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("ktx2 files: Basis Universal's ETC1S and UASTC files decode to its transcoder's RGBA, every level, without Node") {
  for (const FileInfo& f : kFiles) {
    CAPTURE(f.file);
    const image::Ktx2Image k = image::load_ktx2(file(f.file));
    CHECK(k.info.format == f.format);
    CHECK(k.info.supercompression == f.supercompression);
    CHECK(k.info.srgb);
    REQUIRE(static_cast<int>(k.levels.size()) == f.levels);
    int checked = 0;
    for (const Expected& e : kExpected) {
      if (std::string(e.file) != f.file) continue;
      CAPTURE(e.level);
      const image::Image8& im = k.levels[static_cast<std::size_t>(e.level)];
      CHECK(im.width == e.width);
      CHECK(im.height == e.height);
      CHECK(fnv1a(im) == e.hash);
      ++checked;
    }
    CHECK(checked == f.levels);
  }
}

TEST_CASE("ktx2 files: the alpha file's alpha is the pattern's (clear hole, opaque and clear stripes), the others opaque") {
  // Not the transcoder's word: the source pattern's (encode_samples.mjs), within ETC1S's loss.
  const image::Ktx2Image a = image::load_ktx2(file("etc1s_alpha_pattern_150x100.ktx2"));
  const image::Image8& im = a.levels[0];
  auto alpha = [&](int x, int y) { return int(im.rgba[static_cast<std::size_t>(y * im.width + x) * 4 + 3]); };
  CHECK(alpha(37, 30) < 16);           // the hole centred at (37.5, 30)
  CHECK(alpha(140, 30) > 220);          // the ramp's opaque end
  CHECK(alpha(4, 94) < 16);             // stripes of 8 texels in the last 12 rows: clear,
  CHECK(alpha(12, 94) > 240);           // opaque
  const image::Ktx2Image c = image::load_ktx2(file("etc1s_pattern_256x192.ktx2"));
  for (std::size_t i = 3; i < c.levels[0].rgba.size(); i += 4) REQUIRE(c.levels[0].rgba[i] == 255);
}

TEST_CASE("ktx2 files: a decode's bytes are the same on 1, 2, 3 and 8 threads and in reverse task order") {
  std::vector<std::vector<std::uint8_t>> files;
  for (const FileInfo& f : kFiles) files.push_back(image::read_file(file(f.file)));
  files.push_back(ktx2_test::etc1s_sample(true).file());
  for (std::size_t n = 0; n < files.size(); ++n) {
    CAPTURE(n);
    const image::Ktx2Image alone = image::load_ktx2(files[n], "t.ktx2");
    for (const image::ParallelFor& run : ways_to_run()) {
      const image::Ktx2Image k = image::load_ktx2(files[n], "t.ktx2", {}, nullptr, run);
      REQUIRE(k.levels.size() == alone.levels.size());
      for (std::size_t l = 0; l < k.levels.size(); ++l) CHECK(k.levels[l].rgba == alone.levels[l].rgba);
    }
  }
}

TEST_CASE("ktx2 files: the first bad UASTC block in row order is the one reported, whatever the threads") {
  // 64×64: 16 block rows, two ranges of eight. Mode code 0x45 is reserved.
  ktx2_test::Ktx2Spec s;
  s.vk_format = 0;
  s.color_model = 166;
  s.width = s.height = 64;
  std::vector<std::uint8_t> level(16 * 16 * 16, 0);
  for (std::size_t b = 0; b < 256; ++b) level[b * 16] = 0x17;  // solid black blocks
  auto bad = [](std::vector<std::uint8_t> l, int bx, int by) {
    l[static_cast<std::size_t>(by * 16 + bx) * 16] = 0x45;
    return l;
  };
  s.levels = {bad(bad(level, 3, 12), 5, 2)};
  const std::vector<std::uint8_t> both = ktx2_test::write_ktx2(s);
  s.levels = {bad(level, 3, 12)};
  const std::vector<std::uint8_t> second_range = ktx2_test::write_ktx2(s);
  for (const image::ParallelFor& run : ways_to_run()) {
    CHECK(error_of(both, run) == "t.ktx2: level 0: block (5, 2) is not a valid UASTC block");
    CHECK(error_of(second_range, run) == "t.ktx2: level 0: block (3, 12) is not a valid UASTC block");
  }
}

TEST_CASE("ktx2 files: every truncation of the real ETC1S file with alpha is a one-line error naming it") {
  const std::vector<std::uint8_t> whole = image::read_file(file("etc1s_alpha_pattern_150x100.ktx2"));
  for (std::size_t n = 0; n < whole.size(); ++n) {
    CAPTURE(n);
    ktx2_test::check_refused(std::vector<std::uint8_t>(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n)), "");
  }
}
