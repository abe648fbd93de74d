// softpbr's KTX2 decode against the reference decoder, byte for byte: Binomial's Basis
// Universal transcoder (the WebAssembly build the npm package `three` ships), run by Node
// through tests/ktx2/basis_reference.cjs, transcoding every level to RGBA32.
//
// Needs `node` on PATH and SOFTPBR_BASIS_TRANSCODER_DIR naming the folder of
// basis_transcoder.js and .wasm (`npm pack three@0.187.0`, then
// package/examples/jsm/libs/basis); skipped, with a message, when either is absent.
// The files: AnisotropyBarnLamp's four UASTC textures (../shared, or SOFTPBR_SHARED),
// textures of random valid UASTC blocks made here, every mode and partition pattern many
// times over, with full mip chains of odd sizes, stored plain and with Zstandard, the
// ETC1S sample of ktx2_etc1s_sample.h with and without an alpha slice, the real ETC1S and
// UASTC files of tests/ktx2 (made with Basis Universal's encoder), and the
// KTX2 files SOFTPBR_KTX2_REFERENCE_FILES lists (colon-separated; e.g. Basis Universal's
// own ETC1S and UASTC samples: test_files/kodim23.ktx2, webgl/ktx2_studio/assets/*.ktx2).
#include <doctest/doctest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ktx2_etc1s_sample.h"
#include "ktx2_writer.h"
#include "scratch_file.h"
#include "shared_assets.h"
#include "softpbr/image/ktx2.h"
#include "uastc.h"

namespace image = softpbr::image;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return test_files::scratch_file("test_ktx2_reference", name); }

// The transcoder's folder, or "" (with a message) when the reference cannot run.
std::string transcoder_dir() {
  const char* dir = std::getenv("SOFTPBR_BASIS_TRANSCODER_DIR");
  if (dir == nullptr || !fs::exists(fs::path(dir) / "basis_transcoder.wasm")) {
    MESSAGE("skipped: SOFTPBR_BASIS_TRANSCODER_DIR does not name a folder with basis_transcoder.js/.wasm");
    return "";
  }
  if (std::system("command -v node > /dev/null 2>&1") != 0) {
    MESSAGE("skipped: node is not on PATH");
    return "";
  }
  return dir;
}

std::vector<std::uint8_t> read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Every level of `file` decoded by softpbr equals the reference's RGBA32, byte for byte.
void check_against_reference(const std::string& dir, const fs::path& file) {
  CAPTURE(file);
  const fs::path out = scratch(file.filename().string() + ".rgba");
  const std::string command = "node \"" + (fs::path(SOFTPBR_SOURCE_DIR) / "tests/ktx2/basis_reference.cjs").string() +
                              "\" \"" + dir + "\" \"" + file.string() + "\" \"" + out.string() + "\"";
  REQUIRE(std::system(command.c_str()) == 0);
  const std::vector<std::uint8_t> expected = read_bytes(out);
  const image::Ktx2Image k = image::load_ktx2(file);
  std::size_t at = 0, mismatched = 0;
  for (std::size_t l = 0; l < k.levels.size(); ++l) {
    const image::Image8& im = k.levels[l];
    REQUIRE(at + im.rgba.size() <= expected.size());
    for (std::size_t i = 0; i < im.rgba.size(); ++i)
      if (im.rgba[i] != expected[at + i] && mismatched++ < 5) {
        const std::size_t texel = i / 4;
        const int x = static_cast<int>(texel % static_cast<std::size_t>(im.width)), y = static_cast<int>(texel / static_cast<std::size_t>(im.width));
        MESSAGE("level " << l << " texel (" << x << ", " << y << ") channel " << i % 4 << ": " << int(im.rgba[i])
                         << ", the reference " << int(expected[at + i]));
      }
    at += im.rgba.size();
  }
  CHECK(at == expected.size());
  CHECK(mismatched == 0);
}

// A deterministic stream of 64-bit values (SplitMix64).
struct Random {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
};

// A level of random UASTC blocks, each one the decoder accepts (random bits in every
// field; the reserved mode and partition indices beyond their tables drawn again).
std::vector<std::uint8_t> random_blocks(int w, int h, Random& rng) {
  const std::size_t blocks = static_cast<std::size_t>((w + 3) / 4) * static_cast<std::size_t>((h + 3) / 4);
  std::vector<std::uint8_t> data(blocks * 16);
  std::uint8_t texels[64];
  for (std::size_t b = 0; b < blocks; ++b) {
    std::uint8_t* block = &data[b * 16];
    do {
      const std::uint64_t lo = rng.next(), hi = rng.next();
      for (int i = 0; i < 8; ++i) {
        block[i] = static_cast<std::uint8_t>(lo >> (8 * i));
        block[8 + i] = static_cast<std::uint8_t>(hi >> (8 * i));
      }
    } while (!image::detail::decode_uastc_block(block, texels));
  }
  return data;
}

}  // namespace

TEST_CASE("ktx2 reference: UASTC of random valid blocks decodes as Basis Universal's transcoder, every level") {
  const std::string dir = transcoder_dir();
  if (dir.empty()) return;
  Random rng{54};
  for (std::uint32_t scheme : {0u, 2u}) {
    ktx2_test::Ktx2Spec s;
    s.vk_format = 0;
    s.color_model = 166;
    s.width = 262;  // odd sizes: levels whose last blocks overhang them
    s.height = 130;
    s.scheme = scheme;
    for (int l = 0; (s.width >> l) > 0 || (s.height >> l) > 0; ++l)
      s.levels.push_back(random_blocks(std::max(1, s.width >> l), std::max(1, s.height >> l), rng));
    const fs::path file = scratch(scheme ? "random_uastc_zstd.ktx2" : "random_uastc.ktx2");
    const std::vector<std::uint8_t> bytes = ktx2_test::write_ktx2(s);
    std::ofstream(file, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    check_against_reference(dir, file);
  }
}

TEST_CASE("ktx2 reference: ETC1S with and without alpha slices (tests/etc1s_writer.h) decodes as Basis Universal's transcoder") {
  const std::string dir = transcoder_dir();
  if (dir.empty()) return;
  for (bool with_alpha : {false, true}) {
    const std::vector<std::uint8_t> bytes = ktx2_test::etc1s_sample(with_alpha).file();
    const fs::path file = scratch(with_alpha ? "etc1s_alpha.ktx2" : "etc1s.ktx2");
    std::ofstream(file, std::ios::binary | std::ios::trunc)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    check_against_reference(dir, file);
  }
}

TEST_CASE("ktx2 reference: the committed Basis Universal files (tests/ktx2: ETC1S, ETC1S with alpha, UASTC with Zstandard)") {
  // test_ktx2_files.cpp checks them everywhere against hashes of this reference's output.
  const std::string dir = transcoder_dir();
  if (dir.empty()) return;
  for (const char* name : {"etc1s_pattern_256x192.ktx2", "etc1s_alpha_pattern_150x100.ktx2", "uastc_zstd_pattern_128x128.ktx2"})
    check_against_reference(dir, fs::path(SOFTPBR_SOURCE_DIR) / "tests/ktx2" / name);
}

TEST_CASE("ktx2 reference: AnisotropyBarnLamp's UASTC textures decode as Basis Universal's transcoder") {
  const fs::path model = shared_assets::folder() / "gltf/AnisotropyBarnLamp/glTF-KTX2-Basisu";
  if (!fs::exists(model)) {
    MESSAGE("skipped: " << model << " is absent");
    return;
  }
  const std::string dir = transcoder_dir();
  if (dir.empty()) return;
  for (const char* name : {"AnisotropyBarnLamp_basecolor.ktx2", "AnisotropyBarnLamp_normalbump.ktx2",
                           "AnisotropyBarnLamp_occlusionroughnessmetal.ktx2", "AnisotropyBarnLamp_anisotropy.ktx2"})
    check_against_reference(dir, model / name);
}

TEST_CASE("ktx2 reference: the files SOFTPBR_KTX2_REFERENCE_FILES lists decode as Basis Universal's transcoder") {
  const char* list = std::getenv("SOFTPBR_KTX2_REFERENCE_FILES");
  if (list == nullptr || *list == 0) {
    MESSAGE("skipped: SOFTPBR_KTX2_REFERENCE_FILES is not set");
    return;
  }
  const std::string dir = transcoder_dir();
  if (dir.empty()) return;
  const std::string files = list;
  for (std::size_t start = 0; start <= files.size();) {
    const std::size_t end = std::min(files.find(':', start), files.size());
    if (end > start) check_against_reference(dir, files.substr(start, end - start));
    start = end + 1;
  }
}
