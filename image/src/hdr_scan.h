// Internal to softpbr_image: a walk over a Radiance .hdr file's pixel data, run before
// stb_image decodes it, that refuses files whose data ends early.
//
// Why: stb_image (v2.27 in Debian 12's libstb-dev) reads zero bytes past the end of the
// data, and a zero count inside a run-length-encoded scanline does not advance its loop, so
// a file cut inside such a scanline makes stbi_loadf loop forever (found by
// fuzz/fuzz_image). A truncated flat file makes it read up to width × height × 4 bytes of
// nothing. Walking the data the way stb's decoder does, before it runs, turns both into an
// error.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace softpbr::image::detail {

// Walks `file` (a whole Radiance file whose header gave width × height) to the end. Returns "" when every byte stb_image's decoder will read is
// there (or the data is malformed in a way stb reports itself), else what is missing.
std::string hdr_truncation(std::span<const std::uint8_t> file, int width, int height);

}  // namespace softpbr::image::detail
