// PNG decoding (libspng, image/src/png.cpp) gives what stb_image gives — the decoder
// softpbr used before, and what every golden was made with — for every colour type, bit
// depth, transparency chunk and interlacing, and files with a bad CRC or zlib checksum
// still load as they did.
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <spng.h>
#include <stb_image.h>

#include "softpbr/image/load.h"

namespace image = softpbr::image;

namespace {

struct Kind {
  int color_type;  // 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
  int depth;
  bool trns;
  int interlace;  // 0 none, 1 Adam7
};

int channels(int color_type) {
  switch (color_type) {
    case 0: return 1;
    case 2: return 3;
    case 3: return 1;
    case 4: return 2;
    default: return 4;
  }
}

// A w × h PNG of `kind` with pseudo-random samples (and palette, tRNS), written by libspng.
std::vector<std::uint8_t> make_png(const Kind& kind, std::uint32_t w, std::uint32_t h, std::uint32_t seed) {
  const std::size_t bits_per_row = std::size_t{w} * channels(kind.color_type) * kind.depth;
  const std::size_t row_bytes = (bits_per_row + 7) / 8;
  std::vector<std::uint8_t> raw(row_bytes * h);
  std::uint32_t s = seed;
  for (std::uint8_t& b : raw) {
    s = s * 1664525u + 1013904223u;
    b = static_cast<std::uint8_t>(s >> 24);
  }
  const std::unique_ptr<spng_ctx, decltype(&spng_ctx_free)> ctx(spng_ctx_new(SPNG_CTX_ENCODER), &spng_ctx_free);
  spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1);
  spng_ihdr ihdr{};
  ihdr.width = w;
  ihdr.height = h;
  ihdr.bit_depth = static_cast<std::uint8_t>(kind.depth);
  ihdr.color_type = static_cast<std::uint8_t>(kind.color_type);
  ihdr.interlace_method = static_cast<std::uint8_t>(kind.interlace);
  REQUIRE(spng_set_ihdr(ctx.get(), &ihdr) == 0);
  if (kind.color_type == 3) {
    // Every index in range: values are reduced modulo the palette's 1 << depth entries.
    spng_plte plte{};
    plte.n_entries = 1u << kind.depth;
    for (std::uint32_t i = 0; i < plte.n_entries; ++i)
      plte.entries[i] = {static_cast<std::uint8_t>(i * 37), static_cast<std::uint8_t>(255 - i * 11),
                         static_cast<std::uint8_t>(i * 5 + 3), 255};
    REQUIRE(spng_set_plte(ctx.get(), &plte) == 0);
  }
  if (kind.trns) {
    spng_trns trns{};
    const std::uint16_t max = static_cast<std::uint16_t>((1u << kind.depth) - 1);
    if (kind.color_type == 0) trns.gray = static_cast<std::uint16_t>(raw[0] & max);
    if (kind.color_type == 2) trns.red = trns.green = trns.blue = static_cast<std::uint16_t>(raw[0] & max);
    if (kind.color_type == 3) {
      trns.n_type3_entries = 1u << (kind.depth - 1);  // half the palette: the rest stays opaque
      for (std::uint32_t i = 0; i < trns.n_type3_entries; ++i) trns.type3_alpha[i] = static_cast<std::uint8_t>(i * 29);
    }
    REQUIRE(spng_set_trns(ctx.get(), &trns) == 0);
  }
  const int e = spng_encode_image(ctx.get(), raw.data(), raw.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  REQUIRE_MESSAGE(e == 0, spng_strerror(e));
  std::size_t size = 0;
  int error = 0;
  void* bytes = spng_get_png_buffer(ctx.get(), &size, &error);
  REQUIRE(bytes != nullptr);
  std::vector<std::uint8_t> png(static_cast<std::uint8_t*>(bytes), static_cast<std::uint8_t*>(bytes) + size);
  std::free(bytes);
  return png;
}

std::vector<std::uint8_t> stb_rgba(const std::vector<std::uint8_t>& png, int& w, int& h) {
  int c = 0;
  stbi_uc* p = stbi_load_from_memory(png.data(), static_cast<int>(png.size()), &w, &h, &c, 4);
  REQUIRE(p != nullptr);
  std::vector<std::uint8_t> out(p, p + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  stbi_image_free(p);
  return out;
}

}  // namespace

TEST_CASE("PNG decoding equals stb_image's for every colour type, depth, tRNS and interlacing") {
  std::vector<Kind> kinds;
  for (const int interlace : {0, 1}) {
    for (const int depth : {1, 2, 4, 8, 16})
      for (const bool trns : {false, true}) kinds.push_back({0, depth, trns, interlace});
    for (const int depth : {1, 2, 4, 8})
      for (const bool trns : {false, true}) kinds.push_back({3, depth, trns, interlace});
    for (const int depth : {8, 16}) {
      kinds.push_back({2, depth, false, interlace});
      kinds.push_back({2, depth, true, interlace});
      kinds.push_back({4, depth, false, interlace});
      kinds.push_back({6, depth, false, interlace});
    }
  }
  int compared = 0;
  for (const Kind& k : kinds)
    for (const auto& size : {std::pair<std::uint32_t, std::uint32_t>{1, 1}, {7, 5}, {33, 17}}) {
      const std::uint32_t w = size.first, h = size.second;  // (Clang 14: no bindings in CAPTURE)
      CAPTURE(k.color_type);
      CAPTURE(k.depth);
      CAPTURE(k.trns);
      CAPTURE(k.interlace);
      CAPTURE(w);
      CAPTURE(h);
      const std::vector<std::uint8_t> png = make_png(k, w, h, w * 131 + h * 7 + static_cast<std::uint32_t>(k.depth));
      const image::Image8 ours = image::load_png(png, "k.png");
      int sw = 0, sh = 0;
      const std::vector<std::uint8_t> theirs = stb_rgba(png, sw, sh);
      REQUIRE(ours.width == sw);
      REQUIRE(ours.height == sh);
      CHECK(std::ranges::equal(ours.rgba, theirs));
      ++compared;
    }
  CHECK(compared == 52 * 3);  // 26 kinds, each plain and Adam7-interlaced, at three sizes
}

TEST_CASE("a PNG with a wrong chunk CRC or zlib checksum loads, as it did with stb_image") {
  std::vector<std::uint8_t> png = make_png({6, 8, false, 0}, 9, 4, 5);
  int w = 0, h = 0;
  const std::vector<std::uint8_t> expected = stb_rgba(png, w, h);
  // The IDAT chunk: its CRC is the 4 bytes after its data, the zlib Adler-32 the 4 before.
  std::size_t at = 8;
  while (at + 8 <= png.size() && std::string(png.begin() + static_cast<long>(at) + 4, png.begin() + static_cast<long>(at) + 8) != "IDAT")
    at += 12 + ((std::size_t{png[at]} << 24) | (std::size_t{png[at + 1]} << 16) | (std::size_t{png[at + 2]} << 8) | png[at + 3]);
  REQUIRE(at + 8 <= png.size());
  const std::size_t length = (std::size_t{png[at]} << 24) | (std::size_t{png[at + 1]} << 16) | (std::size_t{png[at + 2]} << 8) | png[at + 3];
  std::vector<std::uint8_t> bad_crc = png, bad_adler = png;
  bad_crc[at + 8 + length] ^= 0x5a;
  bad_adler[at + 8 + length - 1] ^= 0x5a;
  CHECK(std::ranges::equal(image::load_png(bad_crc, "crc.png").rgba, expected));
  CHECK(std::ranges::equal(image::load_png(bad_adler, "adler.png").rgba, expected));
}

namespace {
// PNG's CRC-32 (ISO/IEC 15948 Annex D) over a chunk's type and data.
std::uint32_t png_crc(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xffffffffu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

// `png` with `count` chunks of `type` holding `data` inserted after IHDR (bytes 8 to 33).
std::vector<std::uint8_t> with_chunks(const std::vector<std::uint8_t>& png, const std::string& type, const std::string& data,
                                      int count) {
  std::string chunk;
  auto be32 = [&](std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) chunk += static_cast<char>(static_cast<std::uint8_t>(v >> s));
  };
  be32(static_cast<std::uint32_t>(data.size()));
  chunk += type + data;
  be32(png_crc(reinterpret_cast<const std::uint8_t*>(chunk.data()) + 4, chunk.size() - 4));
  std::string all;
  for (int i = 0; i < count; ++i) all += chunk;
  std::vector<std::uint8_t> out(png.begin(), png.begin() + 33);
  out.resize(33 + all.size());
  std::memcpy(out.data() + 33, all.data(), all.size());
  out.insert(out.end(), png.begin() + 33, png.end());
  return out;
}
}  // namespace

TEST_CASE("a valid PNG with thousands of text chunks decodes as without them (ancillary chunks are skipped)") {
  // libspng kept every text chunk within its chunk-count and cache limits and refused the
  // file past them ("reached chunk/cache limits"); none of them changes the pixels.
  for (const Kind kind : {Kind{6, 8, false, 0}, Kind{3, 8, true, 0}, Kind{2, 16, true, 1}}) {
    CAPTURE(kind.color_type);
    const std::vector<std::uint8_t> png = make_png(kind, 13, 7, 11);
    const image::Image8 plain = image::load_png(png, "plain.png");
    const auto& expected = plain.rgba;
    const std::vector<std::uint8_t> texts = with_chunks(png, "tEXt", std::string("Comment") + '\0' + "made by a tool", 3000);
    CHECK(std::ranges::equal(image::load_png(texts, "texts.png").rgba, expected));
    // Text chunks together larger than the rest of the file (the cache limit was its size).
    const std::vector<std::uint8_t> big = with_chunks(png, "iTXt", "XML:com.adobe.xmp" + std::string(5, '\0') + std::string(60000, 'x'), 20);
    CHECK(std::ranges::equal(image::load_png(big, "xmp.png").rgba, expected));
  }
}
