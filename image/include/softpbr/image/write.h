// softpbr/image/write.h — writing PNG, Radiance .hdr and OpenEXR images, atomically: each
// file is written under a temporary name in its folder and renamed over the destination,
// so a reader (or a crash) sees the old file or the whole new one, never a partial one.
//
// The encode_* functions return the file's bytes instead (for a .glb buffer, a test, or
// hdr_round_trip). Errors: std::invalid_argument when the image's size and pixel data
// disagree (nothing is written), std::runtime_error starting with the path (or the name)
// when encoding or writing fails.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"

namespace softpbr::image {

// 8-bit RGBA PNG through stb_image_write.
std::vector<std::uint8_t> encode_png(const ImageView8& image, std::string_view name);
void write_png(const std::filesystem::path& path, const ImageView8& image);

// The RGB of `image` × `scale` as Radiance RGBE through stb_image_write (alpha dropped;
// values negative or not finite, before or after scaling, are stored as 0). `scale` is an
// exposure (pbr::write_hdr passes 2^stops) applied while encoding, so a render target's
// colour buffer is written without a scaled copy of it.
std::vector<std::uint8_t> encode_hdr(const ImageViewF& image, std::string_view name, float scale = 1.0f);
void write_hdr(const std::filesystem::path& path, const ImageViewF& image, float scale = 1.0f);

// 32-bit float R, G, B × `scale` and A as OpenEXR channels (A, B, G, R, the order most
// readers expect), ZIP compressed, through tinyexr. Values are kept exactly, negatives
// included; non-finite ones become 0.
std::vector<std::uint8_t> encode_exr(const ImageViewF& image, std::string_view name, float scale = 1.0f);
void write_exr(const std::filesystem::path& path, const ImageViewF& image, float scale = 1.0f);

// Writes `bytes` to a temporary file in the destination folder (".NAME.tmpNNN"), then
// renames it over `path`. Throws std::runtime_error naming the path on failure, after
// removing the temporary file; an existing file at `path` is then left as it was.
void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes);

}  // namespace softpbr::image
