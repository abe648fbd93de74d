// softpbr/image/load.h — loading PNG, JPEG, WebP, AVIF, Radiance .hdr and OpenEXR images, from a file
// or from a memory buffer (an image embedded in a .glb buffer or a data URI).
//
// Every loader checks the file before its decoder runs: the signature (first bytes), the
// size in the header against Limits (each side at most max_side, decoded bytes at most
// max_decoded_bytes), and that the data the decoder will read is all there — walks written
// for stb_image's and tinyexr's weaknesses on hostile files (src/png_scan.h, jpeg_scan.h,
// hdr_scan.h, the header checks in exr.cpp). Decoders: libspng (PNG), stb_image (JPEG, .hdr) from
// Debian's libstb, tinyexr (.exr) from libtinyexr-dev, libwebp (WebP), libavif (AVIF).
//
// Errors throw std::runtime_error with one line that starts with the file's path (or the
// buffer's name) and a colon, then what is wrong: "tex.png: image size 20000x4 is outside
// 1x1 .. 16384x16384".
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"

namespace softpbr::image {

// The whole of a regular file of at most limits.max_file_bytes, as the path overloads below
// read it: read_whole_file (read_file.h), which never blocks on a pipe or a device. Throws
// std::runtime_error "<path>: no such file", "<path>: is a named pipe (FIFO), not a
// regular file" and the like.
std::vector<std::uint8_t> read_file(const std::filesystem::path& path, const Limits& limits = {});

// PNG as RGBA: grey and RGB get alpha 255, grey is replicated, 16-bit samples are reduced
// to 8 bits, palettes expanded. Refuses every other format by its first bytes (.hdr: stb
// would tone map it; TGA/BMP/PSD/PNM: stb's decoders read on past the end of such files).
Image8 load_png(const std::filesystem::path& path, const Limits& limits = {});
Image8 load_png(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// PNG at 16 bits a sample, for comparing 16-bit images exactly (`softpbr diff`): RGBA
// samples as 16-bit codes 0-65535, each held exactly in an ImageF's float (codes, not
// linear values). Lower depths are widened as PNG scales them (8-bit 255 → 65535, i.e.
// × 257), palettes and grey expanded, tRNS applied. The decoded size counted against
// limits.max_decoded_bytes is 24 bytes a pixel (the 16-bit samples and the floats).
ImageF load_png16(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// JPEG (baseline, extended or progressive, 8-bit, grey, YCbCr or CMYK/YCCK as stb_image
// reads them) as RGBA with alpha 255.
Image8 load_jpeg(const std::filesystem::path& path, const Limits& limits = {});
Image8 load_jpeg(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// WebP (EXT_texture_webp): lossless images as stored; lossy ones (VP8, with or without an
// alpha plane) from their 4:2:0 BT.601 narrow-range planes, converted to RGB by softpbr in
// integer arithmetic (the same bits on every CPU; chroma upsampled bilinearly, centred).
// The RIFF header's size is checked against the file (a cut file: "truncated: the RIFF
// header says N bytes, the file has M") and the bitstream's size against the limits before
// decoding. Animated files are refused. Decoded size counted: 11 bytes a pixel.
Image8 load_webp(const std::filesystem::path& path, const Limits& limits = {});
Image8 load_webp(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// AVIF (EXT_texture_avif): the first image of the file, 8, 10 or 12 bits, 4:4:4, 4:2:2,
// 4:2:0 or 4:0:0, with or without alpha, converted to RGBA8 by softpbr in integer
// arithmetic by the image's matrix coefficients (identity, BT.709, BT.601 — also for
// "unspecified" —, BT.2020) and range (full or narrow); others are refused. The container's
// size is checked against the limits before any AV1 data is decoded. Transformations
// (rotation, mirror, clean aperture) and colour profiles are not applied: glTF textures are
// sRGB or linear data as stored. Decoded size counted: 12 bytes a pixel (20 above 8 bits).
Image8 load_avif(const std::filesystem::path& path, const Limits& limits = {});
Image8 load_avif(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// PNG, JPEG, KTX2, WebP or AVIF, whichever the first bytes say (glTF textures are one of
// these). A KTX2 file gives its level 0 (ktx2.h; load_ktx2 reads every level).
Image8 load_image8(const std::filesystem::path& path, const Limits& limits = {});
Image8 load_image8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// The capacity in bytes to reserve for the pixels of a decoded width × height RGBA8 image
// (used only when above width × height × 4).
using Capacity = std::size_t (*)(int width, int height);
// As load_image8, the pixels' buffer reserved to capacity(width, height) bytes: room to
// grow without a copy. raster::Texture::rgba8_chain_bytes is such a function; a Texture
// made from the moved image then keeps its buffer and writes the mip chain after it.
Image8 load_image8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits, Capacity capacity);

// Radiance .hdr (RGBE, flat or run-length encoded) as linear float RGBA with alpha 1.
// Refuses 8-bit files (stb would invent a gamma curve for them; use load_png).
ImageF load_hdr(const std::filesystem::path& path, const Limits& limits = {});
ImageF load_hdr(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// OpenEXR's R, G, B(, A) channels as linear float RGBA (alpha 1 when absent; a file with a
// single channel, e.g. Y, reads as grey): single-part scan-line files, half or float,
// uncompressed, RLE, ZIPS or ZIP. PIZ is refused (tinyexr 1.0.1's PIZ decoder reads out of
// bounds on damaged files), as are PXR24, B44 and DWA (tinyexr does not decode them),
// tiled, deep and multi-part files, subsampled and integer channels.
ImageF load_exr(const std::filesystem::path& path, const Limits& limits = {});
ImageF load_exr(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// .hdr or .exr, whichever the first bytes say (environment maps are one or the other).
ImageF load_imagef(const std::filesystem::path& path, const Limits& limits = {});
ImageF load_imagef(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits = {});

// What an image's header says, read without decoding it (`softpbr info` lists a glTF
// file's images this way, however large): the format by the first bytes, and for PNG the
// IHDR chunk's size, for JPEG the frame header's (found by the same marker walk the loader
// runs first), for KTX2 the header's and its data format descriptor's (ktx2.h), for WebP
// its VP8/VP8L/VP8X header's, for AVIF its container's (libavif parses it). width and
// height are 0 when the header does not give them (a truncated file, .hdr/.exr: not read);
// nothing is checked against Limits.
struct ImageHeader {
  std::string format;  // "png", "jpeg", "hdr", "exr", "ktx2", "webp", "avif", or "" for anything else
  int width = 0, height = 0;
  // KTX2 only: its block or texel format, supercompression and levels, e.g.
  // "UASTC, Zstandard, 10 levels, sRGB"; "" for other formats.
  std::string detail;
};
ImageHeader read_image_header(std::span<const std::uint8_t> bytes);

}  // namespace softpbr::image
