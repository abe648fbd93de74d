// Internal to softpbr_image: a walk over a PNG file's chunk list, run before stb_image
// decodes it, that refuses chunks claiming more bytes than the file has left.
//
// Why: stb_image (v2.27 in Debian 12's libstb-dev) grows its buffer for the compressed
// data to a chunk's declared length before reading the chunk, so an 84-byte file whose
// IDAT chunk claims 1.6 GB makes it allocate 2 GiB (found by fuzz/fuzz_image).
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace softpbr::image::detail {

// Walks `file` (a whole file with the PNG signature) up to the IEND chunk. Returns "" when
// every chunk's data lies inside the file and its IDAT chunks' compressed bytes can inflate
// to the image IHDR declares (deflate expands at most 1032-fold), else which chunk runs past
// the end, or that the compressed data is too short: before the decoder allocates the image.
std::string png_truncation(std::span<const std::uint8_t> file);

}  // namespace softpbr::image::detail
