// softpbr/golden/image.h — images for golden tests: 8-bit PNGs and float Radiance .hdr files,
// loaded through stb_image, and the conversions between them and render targets.
//
// Two pixel types, both RGBA, row-major, row 0 at the top:
//   raster::Image8 — 8-bit codes, what a PNG holds (sRGB-encoded colour, linear alpha);
//   golden::ImageF — 32-bit floats, linear, what a Target or an .hdr file holds.
// Errors throw std::runtime_error whose text starts with the file's path.
#pragma once

#include <filesystem>
#include <vector>

#include "softpbr/raster/target.h"

namespace softpbr::golden {

using raster::Image8;

// A linear float RGBA image.
struct ImageF {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;  // width * height * 4 floats
};

// Loads a PNG image as RGBA: grey and RGB files get alpha 255, 16-bit files are reduced to
// 8 bits. Refuses .hdr files (stb would tone map them; use load_hdr) and every other format
// (stb_image's TGA/BMP/PSD/PNM decoders read on past the end of truncated files).
Image8 load_png(const std::filesystem::path& path);

// Loads a Radiance .hdr file as linear float RGBA with alpha 1. Refuses 8-bit files (stb
// would invent a gamma curve for them; use load_png).
ImageF load_hdr(const std::filesystem::path& path);

// Writes the RGB of `image` as a Radiance .hdr file (stb_image_write's RGBE encoding,
// alpha dropped, negative and non-finite values stored as 0), atomically — byte for byte
// what pbr::write_hdr writes for the same pixels at exposure 0.
void write_hdr(const std::filesystem::path& path, const ImageF& image);

// What `image` becomes when written with write_hdr and read back with load_hdr: RGBE keeps
// 8 bits of mantissa per channel. A float render compared with an .hdr golden goes
// through this first, so equal renders compare equal.
ImageF hdr_round_trip(const ImageF& image);

// The colour buffer of a target, as it is.
ImageF to_image(const raster::Target& target);

// 8-bit codes as floats: code / 255 per channel (no sRGB decoding), for looking at
// 8-bit and float images side by side.
ImageF to_float(const Image8& image);

// Float → 8-bit for PNG output and for looking: the exact sRGB curve for colour and
// rounding for alpha, clamped to [0, 1], NaN → 0 — the same bits as raster::resolve_srgb8.
Image8 to_srgb8(const ImageF& image);

}  // namespace softpbr::golden
