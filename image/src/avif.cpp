// AVIF through libavif (Debian's libavif-dev, AV1 decoded by dav1d or libaom): the
// container parsed and the image's size checked against the limits (libavif's own size
// limits set to them too) before any AV1 data is decoded, then the decoded Y'CbCr planes
// converted by yuv.h — never by libavif's avifImageYUVToRGB, which may run libyuv's SIMD
// paths (docs/design.md, "WebP and AVIF").
#include <algorithm>
#include <memory>
#include <string>

#include <avif/avif.h>

#include "formats.h"
#include "softpbr/image/load.h"
#include "yuv.h"

namespace softpbr::image {

namespace {
using Decoder = std::unique_ptr<avifDecoder, decltype(&avifDecoderDestroy)>;

// libavif's result and its diagnostic, on one line.
std::string why(avifResult r, const avifDecoder& d) {
  std::string s = avifResultToString(r);
  std::string detail(d.diag.error);
  std::replace(detail.begin(), detail.end(), '\n', ' ');
  if (!detail.empty()) s += ": " + detail;
  return s;
}

// A decoder over `bytes` with the container parsed (no AV1 data decoded yet); r is
// libavif's result. libavif's side limit is off and its pixel-count limit its default
// (16384²) here, so that an image over the caller's limits gets check_size's message; the
// caller's limits are set before anything is decoded (limit_to).
Decoder parse(std::span<const std::uint8_t> bytes, avifResult& r) {
  Decoder d(avifDecoderCreate(), &avifDecoderDestroy);
  if (!d) {
    r = AVIF_RESULT_OUT_OF_MEMORY;
    return d;
  }
  d->maxThreads = 1;
  d->ignoreExif = AVIF_TRUE;
  d->ignoreXMP = AVIF_TRUE;
  d->imageDimensionLimit = 0;
  r = avifDecoderSetIOMemory(d.get(), bytes.data(), bytes.size());
  if (r == AVIF_RESULT_OK) r = avifDecoderParse(d.get());
  return d;
}

// libavif's limits (its AV1 decoder's frame size too) as the caller's.
void limit_to(avifDecoder& d, int max_side) {
  const std::uint64_t side = static_cast<std::uint64_t>(std::clamp(max_side, 1, kMaxSide));
  d.imageDimensionLimit = static_cast<std::uint32_t>(side);
  d.imageSizeLimit = static_cast<std::uint32_t>(std::min<std::uint64_t>(AVIF_DEFAULT_IMAGE_SIZE_LIMIT, side * side));
}
}  // namespace

Image8 load_avif(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  return detail::avif_rgba8(bytes, name, limits, nullptr);
}

Image8 load_avif(const std::filesystem::path& path, const Limits& limits) {
  return load_avif(detail::read_file(path, limits), path.string(), limits);
}

Image8 detail::avif_rgba8(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits,
                          Capacity capacity) {
  detail::expect_format(bytes, name, detail::Format::Avif);
  avifResult r = AVIF_RESULT_OK;
  Decoder d = parse(bytes, r);
  if (r != AVIF_RESULT_OK) detail::fail(name, "cannot decode (" + (d ? why(r, *d) : std::string("out of memory")) + ")");
  const avifImage& header = *d->image;
  const std::uint64_t sample_bytes = header.depth > 8 ? 2 : 1;
  // Counted: the RGBA result, libavif's Y'CbCr and alpha planes and the AV1 decoder's
  // picture (at most 4 samples a pixel each).
  detail::check_size(name, header.width, header.height, 4 + 2 * 4 * sample_bytes, limits);
  const std::uint32_t width = header.width, height = header.height;
  limit_to(*d, limits.max_side);
  r = avifDecoderNextImage(d.get());
  if (r != AVIF_RESULT_OK) detail::fail(name, "cannot decode (" + why(r, *d) + ")");
  const avifImage& im = *d->image;
  if (im.width != width || im.height != height)
    detail::fail(name, "not a readable image (its AV1 data is " + std::to_string(im.width) + "x" + std::to_string(im.height) +
                           ", its container says " + std::to_string(width) + "x" + std::to_string(height) + ")");
  if (im.depth != 8 && im.depth != 10 && im.depth != 12)
    detail::fail(name, "cannot decode (" + std::to_string(im.depth) + "-bit samples; AVIF has 8, 10 or 12)");
  detail::YuvPlanes p;
  p.width = static_cast<int>(im.width);
  p.height = static_cast<int>(im.height);
  p.depth = static_cast<int>(im.depth);
  switch (im.yuvFormat) {
    case AVIF_PIXEL_FORMAT_YUV444: break;
    case AVIF_PIXEL_FORMAT_YUV422: p.chroma_shift_x = 1; break;
    case AVIF_PIXEL_FORMAT_YUV420: p.chroma_shift_x = p.chroma_shift_y = 1; break;
    case AVIF_PIXEL_FORMAT_YUV400: p.monochrome = true; break;
    default: detail::fail(name, "cannot decode (no Y'CbCr format)");
  }
  switch (im.matrixCoefficients) {
    case AVIF_MATRIX_COEFFICIENTS_IDENTITY: p.matrix = detail::YuvMatrix::Identity; break;
    case AVIF_MATRIX_COEFFICIENTS_BT709: p.matrix = detail::YuvMatrix::Bt709; break;
    case AVIF_MATRIX_COEFFICIENTS_UNSPECIFIED:
    case AVIF_MATRIX_COEFFICIENTS_BT470BG:
    case AVIF_MATRIX_COEFFICIENTS_BT601: p.matrix = detail::YuvMatrix::Bt601; break;
    case AVIF_MATRIX_COEFFICIENTS_BT2020_NCL: p.matrix = detail::YuvMatrix::Bt2020; break;
    default:
      if (!p.monochrome)
        detail::fail(name, "matrix coefficients " + std::to_string(im.matrixCoefficients) +
                               " are not supported (0 identity, 1 BT.709, 2 unspecified, 5 and 6 BT.601, 9 BT.2020)");
  }
  if (p.matrix == detail::YuvMatrix::Identity && !p.monochrome && (p.chroma_shift_x != 0 || p.chroma_shift_y != 0))
    detail::fail(name, "not a readable image (identity matrix coefficients with subsampled chroma)");
  p.full_range = im.yuvRange == AVIF_RANGE_FULL;
  for (int k = 0; k < (p.monochrome ? 1 : 3); ++k) {
    if (im.yuvPlanes[k] == nullptr) detail::fail(name, "cannot decode (a missing Y'CbCr plane)");
    p.plane[k] = im.yuvPlanes[k];
    p.row_bytes[k] = im.yuvRowBytes[k];
  }
  p.alpha = im.alphaPlane;
  p.alpha_row_bytes = im.alphaRowBytes;
  p.alpha_premultiplied = im.alphaPlane != nullptr && im.alphaPremultiplied;
  Image8 image;
  image.width = p.width;
  image.height = p.height;
  const std::size_t size = static_cast<std::size_t>(p.width) * static_cast<std::size_t>(p.height) * 4;
  try {
    if (capacity != nullptr) image.rgba.reserve(std::max(size, capacity(p.width, p.height)));
    image.rgba.resize(size);
  } catch (const std::bad_alloc&) {
    detail::fail(name, "cannot decode (out of memory for " + std::to_string(size) + " bytes of pixels)");
  }
  detail::yuv_to_rgba8(p, image.rgba.data());
  return image;
}

bool detail::avif_size(std::span<const std::uint8_t> bytes, int& width, int& height) {
  avifResult r = AVIF_RESULT_OK;
  const Decoder d = parse(bytes, r);
  if (r != AVIF_RESULT_OK || d->image->width == 0 || d->image->height == 0 ||
      d->image->width > static_cast<std::uint32_t>(kMaxSide) || d->image->height > static_cast<std::uint32_t>(kMaxSide))
    return false;
  width = static_cast<int>(d->image->width);
  height = static_cast<int>(d->image->height);
  return true;
}

}  // namespace softpbr::image
