// OpenEXR through tinyexr (Debian's libtinyexr-dev 1.0.1): loading with the header checked
// before any pixel is decoded, and ZIP-compressed float output.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tinyexr.h>

#include "formats.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

namespace softpbr::image {

namespace {
// tinyexr reports errors as strings it allocated, some ending in a newline: one line here.
std::string take_error(const char* err) {
  std::string s = err ? err : "unknown error";
  if (err) FreeEXRErrorMessage(err);
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}
}  // namespace

ImageF load_exr(std::span<const std::uint8_t> bytes, std::string_view name, const Limits& limits) {
  using detail::fail;
  if (const detail::Format f = detail::sniff(bytes); f != detail::Format::Exr && f != detail::Format::Unknown)
    detail::expect_format(bytes, name, detail::Format::Exr);  // says what the file is instead

  // The steps of tinyexr's LoadEXRFromMemory, done here so that (a) the header is checked
  // before any pixel is decoded — Debian's tinyexr 1.0.1 computes data_window.max − min in
  // int and overflows for windows near ±2^31 (fuzz/findings/exr-ub-data-window) — and (b)
  // header and image are freed on every path (LoadEXRFromMemory leaks the header when
  // the pixel data fails to decode: fuzz/findings/exr-leak-header).
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS)
    fail(name, "not a readable OpenEXR file: bad magic number or version");
  if (version.multipart || version.non_image) fail(name, "multi-part and deep OpenEXR files are not supported");
  if (version.tiled) fail(name, "tiled OpenEXR files are not supported (write scan lines)");

  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  if (ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS) {
    FreeEXRHeader(&header);
    fail(name, "not a readable OpenEXR file: " + take_error(err));
  }
  const std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> header_owner(&header, &FreeEXRHeader);

  // The data window in 64 bits, bounded like any image.
  const EXRBox2i& dw = header.data_window;
  const std::int64_t w = std::int64_t{dw.max_x} - dw.min_x + 1, h = std::int64_t{dw.max_y} - dw.min_y + 1;
  constexpr std::int64_t kMaxCoordinate = std::int64_t{1} << 30;
  const int side = std::clamp(limits.max_side, 1, kMaxSide);
  const auto out_of_range = [&](std::int64_t v) { return v < -kMaxCoordinate || v > kMaxCoordinate; };
  if (out_of_range(dw.min_x) || out_of_range(dw.max_x) || out_of_range(dw.min_y) || out_of_range(dw.max_y) || w < 1 ||
      h < 1 || w > side || h > side)
    fail(name, "data window (" + std::to_string(dw.min_x) + ", " + std::to_string(dw.min_y) + ") - (" +
                   std::to_string(dw.max_x) + ", " + std::to_string(dw.max_y) + ") is not 1 to " + std::to_string(side) +
                   " pixels on each side");
  // The result and tinyexr's float plane per channel.
  if (header.num_channels < 1) fail(name, "not a readable OpenEXR file: no channels");
  detail::check_size(name, w, h, 16, limits,
                     static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) * 4 *
                         static_cast<std::uint64_t>(header.num_channels));

  // Compression: none, RLE, ZIP and ZIPS only. tinyexr 1.0.1's PIZ decoder (Debian 12)
  // trusts the chunk: its bitmap range, Huffman length and table are read without bounds
  // checks (heap over-reads found by fuzz_exr, fuzz/findings/exr-piz-*), so a damaged PIZ
  // file could crash the program or read other memory. PXR24, B44 and DWA tinyexr does not
  // decode at all.
  switch (header.compression_type) {
    case TINYEXR_COMPRESSIONTYPE_NONE:
    case TINYEXR_COMPRESSIONTYPE_RLE:
    case TINYEXR_COMPRESSIONTYPE_ZIPS:
    case TINYEXR_COMPRESSIONTYPE_ZIP:
      break;
    case TINYEXR_COMPRESSIONTYPE_PIZ:
      fail(name, "PIZ-compressed OpenEXR files are not supported (the decoder is not safe against damaged files); "
                 "save it with ZIP, RLE or no compression");
    default:
      fail(name, "OpenEXR compression " + std::to_string(header.compression_type) +
                     " is not supported (expected none, RLE, ZIPS or ZIP)");
  }

  // R, G, B and optional A, full resolution, HALF or FLOAT (HALF decoded as FLOAT); a
  // single channel (e.g. Y) is read as grey.
  int index[4] = {-1, -1, -1, -1};
  for (int c = 0; c < header.num_channels; ++c) {
    const EXRChannelInfo& info = header.channels[c];
    if (info.x_sampling != 1 || info.y_sampling != 1) fail(name, std::string("channel ") + info.name + " is subsampled: not supported");
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT)
      fail(name, std::string("channel ") + info.name + " holds integers: expected half or float colour");
    header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
    const std::string channel = info.name;
    for (int k = 0; k < 4; ++k)
      if (channel == std::string(1, "RGBA"[k])) index[k] = c;
  }
  if (header.num_channels == 1) index[0] = index[1] = index[2] = 0;
  if (index[0] < 0 || index[1] < 0 || index[2] < 0) fail(name, "no R, G and B channels (and not a single grey channel)");

  EXRImage image;
  InitEXRImage(&image);
  // On failure tinyexr has already called FreeEXRImage (which leaves dangling pointers, so
  // it must not run twice). tinyexr 1.0.1 does so before it records the channel count, so
  // FreeEXRImage would skip the channel planes it allocated (w·h·4 bytes each) and leak
  // them (fuzz/README.md, Findings): the count is set here first, so that it frees them.
  // (The planes are allocated all at once, one per header channel; before that `images`
  // is null and FreeEXRImage frees nothing.)
  image.num_channels = header.num_channels;
  if (LoadEXRImageFromMemory(&image, &header, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS)
    fail(name, "not a readable OpenEXR file: " + take_error(err));
  const std::unique_ptr<EXRImage, int (*)(EXRImage*)> image_owner(&image, &FreeEXRImage);
  if (image.images == nullptr || image.width != w || image.height != h)
    fail(name, "not a readable OpenEXR file: no scan-line pixel data");

  ImageF result{image.width, image.height, {}};
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  result.rgba.resize(n * 4);
  for (int k = 0; k < 4; ++k) {
    const float* plane = index[k] < 0 ? nullptr : reinterpret_cast<const float*>(image.images[index[k]]);
    for (std::size_t i = 0; i < n; ++i) result.rgba[i * 4 + k] = plane ? plane[i] : 1.0f;
  }
  return result;
}

ImageF load_exr(const std::filesystem::path& path, const Limits& limits) {
  return load_exr(detail::read_file(path, limits), path.string(), limits);
}

namespace {
// Encodes `image` and hands the file's bytes to `use` while tinyexr's buffer lives, so that
// write_exr writes them without a copy (a float image compresses little: the copy could be
// as large as the image).
template <class Use>
void encode_exr_into(const ImageViewF& image, std::string_view name, float scale, Use use) {
  detail::check_writable(image, name);
  const std::size_t n = image.rgba.size() / 4;
  // Channels in the alphabetical order most readers expect: A, B, G, R.
  std::vector<float> planes[4];
  for (auto& p : planes) p.resize(n);
  const auto keep = [](float x) { return std::isfinite(x) ? x : 0.0f; };
  for (std::size_t i = 0; i < n; ++i) {
    const float* c = image.rgba.data() + 4 * i;
    planes[0][i] = keep(c[3]);
    planes[1][i] = keep(c[2] * scale);
    planes[2][i] = keep(c[1] * scale);
    planes[3][i] = keep(c[0] * scale);
  }
  unsigned char* images[4] = {reinterpret_cast<unsigned char*>(planes[0].data()),
                              reinterpret_cast<unsigned char*>(planes[1].data()),
                              reinterpret_cast<unsigned char*>(planes[2].data()),
                              reinterpret_cast<unsigned char*>(planes[3].data())};
  EXRImage exr;
  InitEXRImage(&exr);
  exr.images = images;
  exr.width = image.width;
  exr.height = image.height;
  exr.num_channels = 4;

  EXRHeader header;
  InitEXRHeader(&header);
  EXRChannelInfo channels[4] = {};
  const char* names[4] = {"A", "B", "G", "R"};
  int types[4] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  for (int c = 0; c < 4; ++c) channels[c].name[0] = names[c][0];
  header.num_channels = 4;
  header.channels = channels;
  header.pixel_types = types;
  header.requested_pixel_types = types;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

  unsigned char* memory = nullptr;
  const char* err = nullptr;
  const std::size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
  if (size == 0) detail::fail(name, "OpenEXR encoding failed: " + take_error(err));
  const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
  use(std::span<const std::uint8_t>(memory, size));
}
}  // namespace

std::vector<std::uint8_t> encode_exr(const ImageViewF& image, std::string_view name, float scale) {
  std::vector<std::uint8_t> bytes;
  encode_exr_into(image, name, scale, [&](std::span<const std::uint8_t> b) { bytes.assign(b.begin(), b.end()); });
  return bytes;
}

void write_exr(const std::filesystem::path& path, const ImageViewF& image, float scale) {
  encode_exr_into(image, path.string(), scale, [&](std::span<const std::uint8_t> b) { write_file_atomic(path, b); });
}

}  // namespace softpbr::image
