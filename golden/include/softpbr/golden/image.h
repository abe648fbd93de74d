// softpbr/golden/image.h — images for golden tests: the image library's types, loaders and
// .hdr writer under golden's names, what RGBE storage does to float values, and the
// conversions between render targets, float and 8-bit images.
//
// Two pixel types, both RGBA, row-major, row 0 at the top (softpbr/image/image.h):
//   Image8 — 8-bit codes, what a PNG holds (sRGB-encoded colour, linear alpha);
//   ImageF — 32-bit floats, linear, what a Target or an .hdr file holds.
// Errors throw std::runtime_error whose text starts with the file's path.
#pragma once

#include "softpbr/image/image.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/raster/target.h"

namespace softpbr::golden {

using image::Image8;
using image::ImageF;

// Golden images are PNG (load_png) or Radiance .hdr (load_hdr), written with write_png and
// write_hdr; see softpbr/image/load.h and write.h for what each accepts and refuses.
using image::load_hdr;
using image::load_png;
using image::write_hdr;
using image::write_png;

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
