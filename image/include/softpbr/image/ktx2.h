// softpbr/image/ktx2.h — KTX 2.0 textures (Khronos KTX File Format Specification 2.0),
// decoded to 8-bit RGBA on the CPU with integer arithmetic only: the same bytes on every
// machine.
//
// Read: 2D textures (one layer, one face) with their mip levels, supercompressed or not:
// - Basis Universal UASTC blocks (vkFormat 0, colour model KHR_DF_MODEL_UASTC), plain or
//   Zstandard;
// - Basis Universal ETC1S in BasisLZ supercompression (colour model KHR_DF_MODEL_ETC1S),
//   with its alpha slices;
// - the uncompressed formats glTF assets use — R8G8B8A8, R8G8B8, R8G8, R8 (UNORM or SRGB),
//   plain or Zstandard — read as Vulkan samples them: missing green and blue are 0,
//   missing alpha 255.
// Refused with a message saying so: ZLIB supercompression, cube maps, arrays, 3D and 1D
// textures, other vkFormats.
//
// Every size, offset and length is checked against the file and Limits before anything is
// allocated (the decoded RGBA of every level, and a Zstandard level's inflated blocks,
// count against max_decoded_bytes). Errors are std::runtime_error with one line starting
// with the file's name: "tex.ktx2: level 1: its data (bytes 400 to 90400) lies past the
// end of the file (4000 bytes)".
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/image/load.h"

namespace softpbr::image {

// What a KTX2 file's header and data format descriptor say.
struct Ktx2Info {
  std::string format;            // "UASTC", "ETC1S", "R8G8B8A8_SRGB", … ("vkFormat N" if unknown)
  std::string supercompression;  // "none", "BasisLZ", "Zstandard", "ZLIB"
  int width = 0, height = 0;
  int levels = 0;                // levels in the file (a levelCount of 0 counts as 1)
  bool srgb = false;             // the DFD's transfer function is sRGB
};

// Level 0 first, each max(1, width >> l) × max(1, height >> l), rows top down.
struct Ktx2Image {
  Ktx2Info info;
  std::vector<Image8> levels;
};

Ktx2Image load_ktx2(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});
Ktx2Image load_ktx2(const std::filesystem::path& path, const Limits& limits = {});

// How a caller lends its threads to the decoder: calls task(0) … task(count − 1), each once,
// in any order and on any threads, and returns when all are done; when a task throws (only
// std::bad_alloc), rethrows one such exception after the others finish. A
// raster::ThreadPool's parallel_for is one:
//   [&pool](std::size_t n, const std::function<void(std::size_t)>& f) { pool.parallel_for(n, f); }
// Empty: everything on the calling thread.
using ParallelFor = std::function<void(std::size_t count, const std::function<void(std::size_t)>& task)>;

// As above, level 0's buffer reserved to capacity(width, height) bytes (load.h's Capacity:
// raster::Texture::rgba8_chain_bytes, so that a Texture made from it with the other levels
// keeps the buffer), and a level's blocks decoded on `parallel`'s threads: UASTC blocks
// and the expansion of ETC1S blocks to texels in ranges of block rows, an ETC1S level's
// colour and alpha slices (each read sequentially: Huffman codes) side by side. The ranges
// do not depend on the threads: the bytes are the same however the tasks run, and so is
// the error a bad file gives (the first bad block in row order).
Ktx2Image load_ktx2(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity,
                    const ParallelFor& parallel = {});

// Whether `bytes` begin with KTX 2.0's identifier.
bool is_ktx2(std::span<const std::uint8_t> bytes);

// The header's description without decoding or checking anything beyond it ("" fields
// where the bytes are not a KTX2 header). For `softpbr info`.
Ktx2Info read_ktx2_info(std::span<const std::uint8_t> bytes);

}  // namespace softpbr::image
