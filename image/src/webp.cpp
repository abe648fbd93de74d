// WebP through libwebp (Debian's libwebp-dev): the RIFF header's size against the file,
// the bitstream's size against the limits, then lossless (VP8L) decoded to RGBA as it is
// stored, lossy (VP8, with or without an alpha plane) decoded to its Y'CbCr planes and
// converted by yuv.h, bit-exact on every CPU (docs/design.md, "WebP and AVIF").
#include <algorithm>
#include <new>
#include <string>
#include <vector>

#include <webp/decode.h>

#include "formats.h"
#include "softpbr/image/load.h"
#include "yuv.h"

namespace softpbr::image {

namespace {
const char* status_text(VP8StatusCode s) {
  switch (s) {
    case VP8_STATUS_OUT_OF_MEMORY: return "out of memory";
    case VP8_STATUS_INVALID_PARAM: return "invalid parameter";
    case VP8_STATUS_BITSTREAM_ERROR: return "bitstream error";
    case VP8_STATUS_UNSUPPORTED_FEATURE: return "unsupported feature";
    case VP8_STATUS_NOT_ENOUGH_DATA: return "truncated: the bitstream ends early";
    case VP8_STATUS_SUSPENDED: return "truncated: the bitstream ends early";
    case VP8_STATUS_USER_ABORT: return "aborted";
    default: return "decoder error";
  }
}

std::uint32_t le32(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint32_t{b[at]} | (std::uint32_t{b[at + 1]} << 8) | (std::uint32_t{b[at + 2]} << 16) |
         (std::uint32_t{b[at + 3]} << 24);
}

// The file as far as its RIFF header says it goes (bytes after it are ignored, as libwebp
// does), or the error for a file shorter than that.
std::span<const std::uint8_t> riff_payload(std::span<const std::uint8_t> bytes, std::string_view name) {
  // RIFF (WebP container specification): "RIFF", the size of what follows these 8 bytes
  // (even, at least "WEBP" and one chunk header), "WEBP".
  const std::uint64_t riff = le32(bytes, 4);
  if (riff < 12) detail::fail(name, "not a readable image (its RIFF size " + std::to_string(riff) + " holds no WebP chunk)");
  if (riff + 8 > bytes.size())
    detail::fail(name, "truncated: the RIFF header says " + std::to_string(riff + 8) + " bytes, the file has " +
                           std::to_string(bytes.size()));
  return bytes.first(static_cast<std::size_t>(riff + 8));
}

template <class Vector>
void allocate(Vector& v, std::size_t n, std::string_view name) {
  try {
    v.resize(n);
  } catch (const std::bad_alloc&) {
    detail::fail(name, "cannot decode (out of memory for " + std::to_string(n) + " bytes of pixels)");
  }
}
}  // namespace

Image8 load_webp(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  return detail::webp_rgba8(bytes, name, limits, nullptr);
}

Image8 load_webp(const std::filesystem::path& path, const Limits& limits) {
  return load_webp(detail::read_file(path, limits), path.string(), limits);
}

Image8 detail::webp_rgba8(std::span<const std::uint8_t> file, std::string_view name, const Limits& limits,
                          Capacity capacity) {
  detail::expect_format(file, name, detail::Format::Webp);  // so at least the 12 bytes of the RIFF header
  WebPDecoderConfig config;
  if (!WebPInitDecoderConfig(&config)) detail::fail(name, "cannot decode (libwebp's version does not match its header)");
  // The size from the VP8, VP8L or VP8X header, before anything is decoded; then the
  // file's length against its RIFF header (the size first: the more useful message for a
  // file that claims too much and also lacks the data).
  const VP8StatusCode header = WebPGetFeatures(file.data(), file.size(), &config.input);
  const WebPBitstreamFeatures& f = config.input;
  // Counted: the RGBA result, libwebp's own ARGB copy of a lossless image (4 bytes a
  // pixel, with its transforms' small planes), and the Y'CbCr and alpha planes of a lossy
  // one (2.5 bytes a pixel at most).
  if (header == VP8_STATUS_OK) detail::check_size(name, f.width, f.height, 4 + 4 + 3, limits);
  const std::span<const std::uint8_t> bytes = riff_payload(file, name);
  if (header != VP8_STATUS_OK) detail::fail(name, std::string("cannot decode (") + status_text(header) + ")");
  if (f.has_animation) detail::fail(name, "is an animated WebP; a texture is one still image");
  const int w = f.width, h = f.height;
  Image8 image;
  image.width = w;
  image.height = h;
  const std::size_t pixels = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  try {
    if (capacity != nullptr) image.rgba.reserve(std::max(pixels * 4, capacity(w, h)));
  } catch (const std::bad_alloc&) {
    detail::fail(name, "cannot decode (out of memory for " + std::to_string(pixels * 4) + " bytes of pixels)");
  }
  allocate(image.rgba, pixels * 4, name);
  config.output.is_external_memory = 1;
  if (f.format == 2) {
    // Lossless: the ARGB samples as coded (no conversion, the same on every CPU).
    config.output.colorspace = MODE_RGBA;
    config.output.u.RGBA.rgba = image.rgba.data();
    config.output.u.RGBA.stride = w * 4;
    config.output.u.RGBA.size = image.rgba.size();
    const VP8StatusCode s = WebPDecode(bytes.data(), bytes.size(), &config);
    WebPFreeDecBuffer(&config.output);
    if (s != VP8_STATUS_OK) detail::fail(name, std::string("cannot decode (") + status_text(s) + ")");
    return image;
  }
  // Lossy: VP8's 4:2:0 planes (BT.601, narrow range: RFC 6386 §2 and libwebp's reading of
  // it) and the alpha plane (255 when the file has none).
  const int cw = (w + 1) / 2, ch = (h + 1) / 2;
  const std::size_t chroma = static_cast<std::size_t>(cw) * static_cast<std::size_t>(ch);
  std::vector<std::uint8_t> planes;
  allocate(planes, pixels * 2 + chroma * 2, name);
  std::uint8_t* y = planes.data();
  std::uint8_t* u = y + pixels;
  std::uint8_t* v = u + chroma;
  std::uint8_t* a = v + chroma;
  std::fill(a, a + pixels, std::uint8_t{255});
  config.output.colorspace = MODE_YUVA;
  WebPYUVABuffer& out = config.output.u.YUVA;
  out.y = y, out.y_stride = w, out.y_size = pixels;
  out.u = u, out.u_stride = cw, out.u_size = chroma;
  out.v = v, out.v_stride = cw, out.v_size = chroma;
  out.a = a, out.a_stride = w, out.a_size = pixels;
  const VP8StatusCode s = WebPDecode(bytes.data(), bytes.size(), &config);
  WebPFreeDecBuffer(&config.output);
  if (s != VP8_STATUS_OK) detail::fail(name, std::string("cannot decode (") + status_text(s) + ")");
  detail::YuvPlanes p;
  p.width = w, p.height = h, p.depth = 8;
  p.chroma_shift_x = p.chroma_shift_y = 1;
  p.full_range = false;
  p.matrix = detail::YuvMatrix::Bt601;
  p.plane[0] = y, p.row_bytes[0] = static_cast<std::size_t>(w);
  p.plane[1] = u, p.row_bytes[1] = static_cast<std::size_t>(cw);
  p.plane[2] = v, p.row_bytes[2] = static_cast<std::size_t>(cw);
  p.alpha = a, p.alpha_row_bytes = static_cast<std::size_t>(w);
  detail::yuv_to_rgba8(p, image.rgba.data());
  return image;
}

bool detail::webp_size(std::span<const std::uint8_t> bytes, int& width, int& height) {
  int w = 0, h = 0;
  if (!WebPGetInfo(bytes.data(), bytes.size(), &w, &h)) return false;
  width = w, height = h;
  return true;
}

}  // namespace softpbr::image
