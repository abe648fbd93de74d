// Internal to softpbr_image: what the format files (png.cpp, jpeg.cpp, hdr.cpp, exr.cpp)
// share — one-line errors naming the file, the formats' signatures, the size and
// decoded-bytes limits, reading a file into memory, and stb_image_write's output callback.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/image/load.h"

namespace softpbr::image::detail {

// load_png and load_jpeg with the pixels' buffer reserved to capacity(width, height) bytes
// (nullptr: exactly the pixels).
Image8 png_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity);
Image8 jpeg_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity);
// A KTX2 file's level 0 (ktx2.h), the same way.
Image8 ktx2_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity);
// load_webp and load_avif, the same way.
Image8 webp_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity);
Image8 avif_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity);
// A WebP's or an AVIF's size from its headers (no pixel decoded); false when they do not
// give one.
bool webp_size(std::span<const std::uint8_t> bytes, int& width, int& height);
bool avif_size(std::span<const std::uint8_t> bytes, int& width, int& height);

// Throws std::runtime_error("<name>: <what>").
[[noreturn]] void fail(std::string_view name, std::string_view what);

// A file's format by its first bytes: the PNG signature (ISO/IEC 15948 §5.2), JPEG's SOI
// marker followed by another marker (ITU-T T.81 B.1.1.3), Radiance's "#?RADIANCE\n" or
// "#?RGBE\n" line (the two stb_image accepts), OpenEXR's magic number 20000630, KTX 2.0's
// 12-byte identifier, WebP's "RIFF" … "WEBP" header, and AVIF's ISOBMFF "ftyp" box with
// the brand "avif" or "avis" (major or compatible).
enum class Format { Unknown, Png, Jpeg, Hdr, Exr, Ktx2, Webp, Avif };
Format sniff(std::span<const std::uint8_t> bytes);

// Throws unless `bytes` has the signature of `wanted`; the message says what the file is
// and which loader reads it, or that it has no such signature ("not a readable image (no
// PNG signature)").
void expect_format(std::span<const std::uint8_t> bytes, std::string_view name, Format wanted);

// Throws unless 1 <= width, height <= the limit's side and width × height ×
// bytes_per_pixel (+ extra_bytes) <= max_decoded_bytes.
void check_size(std::string_view name, std::int64_t width, std::int64_t height, std::uint64_t bytes_per_pixel,
                const Limits& limits, std::uint64_t extra_bytes = 0);

// The size of a buffer as stb_image takes it (an int); throws when it is larger.
int stb_size(std::span<const std::uint8_t> bytes, std::string_view name);

// The whole of a regular file of at most limits.max_file_bytes (read_whole_file: never
// blocks on a pipe or a device). Throws "<path>: no such file" and the like.
std::vector<std::uint8_t> read_file(const std::filesystem::path& path, const Limits& limits);

// What an encoder accepts: check_pixels, and at least 1×1 (std::invalid_argument otherwise).
void check_writable(const ImageView8& image, std::string_view name);
void check_writable(const ImageViewF& image, std::string_view name);

// stb_image_write's output callback: appends to the std::vector<std::uint8_t> `context`.
void append_bytes(void* context, void* data, int size);

}  // namespace softpbr::image::detail
