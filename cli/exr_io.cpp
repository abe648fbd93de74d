// OpenEXR through tinyexr (see exr_io.h).
#include "exr_io.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <tinyexr.h>

#include "softpbr/dmath/dmath.h"

namespace softpbr::cli {

namespace {
// tinyexr reports errors as strings it allocated.
std::string take_error(const char* err) {
  std::string s = err ? err : "unknown error";
  if (err) FreeEXRErrorMessage(err);
  return s;
}
}  // namespace

void write_exr(const std::filesystem::path& path, const raster::Target& target, float exposure) {
  if (!std::isfinite(exposure)) throw std::invalid_argument("exposure: must be a finite number of stops");
  const float scale = static_cast<float>(dmath::exp2(exposure));  // as pbr::write_hdr
  const std::size_t n = target.colors().size();
  // Channels in the alphabetical order most readers expect: A, B, G, R.
  std::vector<float> planes[4];
  for (auto& p : planes) p.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const glm::vec4& c = target.colors()[i];
    auto keep = [](float x) { return std::isfinite(x) ? x : 0.0f; };
    planes[0][i] = keep(c.a);
    planes[1][i] = keep(c.b * scale);
    planes[2][i] = keep(c.g * scale);
    planes[3][i] = keep(c.r * scale);
  }
  unsigned char* images[4] = {reinterpret_cast<unsigned char*>(planes[0].data()),
                              reinterpret_cast<unsigned char*>(planes[1].data()),
                              reinterpret_cast<unsigned char*>(planes[2].data()),
                              reinterpret_cast<unsigned char*>(planes[3].data())};
  EXRImage image;
  InitEXRImage(&image);
  image.images = images;
  image.width = target.width();
  image.height = target.height();
  image.num_channels = 4;

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
  const std::size_t size = SaveEXRImageToMemory(&image, &header, &memory, &err);
  if (size == 0) throw std::runtime_error(path.string() + ": OpenEXR encoding failed: " + take_error(err));
  const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
  raster::write_file_atomic(path, {memory, size});
}

golden::ImageF load_exr(const std::filesystem::path& path) {
  // Only regular files of a sane size: a device or a pipe would be read without end.
  constexpr std::uintmax_t kMaxExrBytes = std::uintmax_t{1} << 30;
  const std::string where = path.string() + ": ";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(where + "cannot open: not a regular file");
  if (std::filesystem::file_size(path, ec) > kMaxExrBytes) throw std::runtime_error(where + "over 1 GiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(where + "cannot open");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  // The steps of tinyexr's LoadEXRFromMemory, done here so that (a) the header is checked
  // before any pixel is decoded — Debian's tinyexr 1.0.1 computes data_window.max − min in
  // int and overflows for windows near ±2^31 (fuzz/findings/exr-ub-data-window) — and (b)
  // header and image are freed on every path (LoadEXRFromMemory leaks the header when
  // the pixel data fails to decode: fuzz/findings/exr-leak-header).
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS)
    throw std::runtime_error(where + "not a readable OpenEXR file: bad magic number or version");
  if (version.multipart || version.non_image)
    throw std::runtime_error(where + "multi-part and deep OpenEXR files are not supported");
  if (version.tiled) throw std::runtime_error(where + "tiled OpenEXR files are not supported (write scan lines)");

  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  if (ParseEXRHeaderFromMemory(&header, &version, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS) {
    FreeEXRHeader(&header);
    throw std::runtime_error(where + "not a readable OpenEXR file: " + take_error(err));
  }
  const std::unique_ptr<EXRHeader, int (*)(EXRHeader*)> header_owner(&header, &FreeEXRHeader);

  // The data window in 64 bits, bounded like a render target.
  const EXRBox2i& dw = header.data_window;
  const std::int64_t w = std::int64_t{dw.max_x} - dw.min_x + 1, h = std::int64_t{dw.max_y} - dw.min_y + 1;
  constexpr std::int64_t kMaxCoordinate = std::int64_t{1} << 30;
  const auto out_of_range = [&](std::int64_t v) { return v < -kMaxCoordinate || v > kMaxCoordinate; };
  if (out_of_range(dw.min_x) || out_of_range(dw.max_x) || out_of_range(dw.min_y) || out_of_range(dw.max_y) || w < 1 ||
      h < 1 || w > raster::kMaxTargetSize || h > raster::kMaxTargetSize)
    throw std::runtime_error(where + "data window (" + std::to_string(dw.min_x) + ", " + std::to_string(dw.min_y) + ") - (" +
                             std::to_string(dw.max_x) + ", " + std::to_string(dw.max_y) + ") is not 1 to " +
                             std::to_string(raster::kMaxTargetSize) + " pixels on each side");

  // Compression: none, RLE, ZIP and ZIPS only. tinyexr 1.0.1's PIZ decoder (Debian 12)
  // trusts the chunk: its bitmap range, Huffman length and table are read without bounds
  // checks (heap over-reads found by fuzz_exr, fuzz/findings/exr-piz-*), so a damaged PIZ
  // file could crash the command or read other memory. PXR24, B44 and DWA tinyexr does not
  // decode at all.
  switch (header.compression_type) {
    case TINYEXR_COMPRESSIONTYPE_NONE:
    case TINYEXR_COMPRESSIONTYPE_RLE:
    case TINYEXR_COMPRESSIONTYPE_ZIPS:
    case TINYEXR_COMPRESSIONTYPE_ZIP:
      break;
    case TINYEXR_COMPRESSIONTYPE_PIZ:
      throw std::runtime_error(where + "PIZ-compressed OpenEXR files are not supported (the decoder is not safe "
                                       "against damaged files); save it with ZIP, RLE or no compression");
    default:
      throw std::runtime_error(where + "OpenEXR compression " + std::to_string(header.compression_type) +
                               " is not supported (expected none, RLE, ZIPS or ZIP)");
  }

  // R, G, B and optional A, full resolution, HALF or FLOAT (HALF decoded as FLOAT); a
  // single channel (e.g. Y) is read as grey.
  int index[4] = {-1, -1, -1, -1};
  for (int c = 0; c < header.num_channels; ++c) {
    const EXRChannelInfo& info = header.channels[c];
    if (info.x_sampling != 1 || info.y_sampling != 1)
      throw std::runtime_error(where + "channel " + info.name + " is subsampled: not supported");
    if (header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT)
      throw std::runtime_error(where + "channel " + info.name + " holds integers: expected half or float colour");
    header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
    const std::string name = info.name;
    for (int k = 0; k < 4; ++k)
      if (name == std::string(1, "RGBA"[k])) index[k] = c;
  }
  if (header.num_channels == 1) index[0] = index[1] = index[2] = 0;
  if (index[0] < 0 || index[1] < 0 || index[2] < 0)
    throw std::runtime_error(where + "no R, G and B channels (and not a single grey channel)");

  EXRImage image;
  InitEXRImage(&image);
  // On failure tinyexr has already called FreeEXRImage (which leaves dangling pointers, so
  // it must not run twice). Known leak inside tinyexr 1.0.1: it does so before setting
  // image.num_channels, so the channel planes of a file whose pixel data fails to decode
  // (w·h·4 bytes each) are never freed; the command exits right after the error.
  if (LoadEXRImageFromMemory(&image, &header, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS) {
    throw std::runtime_error(where + "not a readable OpenEXR file: " + take_error(err));
  }
  const std::unique_ptr<EXRImage, int (*)(EXRImage*)> image_owner(&image, &FreeEXRImage);
  if (image.images == nullptr || image.width != w || image.height != h)
    throw std::runtime_error(where + "not a readable OpenEXR file: no scan-line pixel data");

  golden::ImageF result{image.width, image.height, {}};
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  result.rgba.resize(n * 4);
  for (int k = 0; k < 4; ++k) {
    const float* plane = index[k] < 0 ? nullptr : reinterpret_cast<const float*>(image.images[index[k]]);
    for (std::size_t i = 0; i < n; ++i) result.rgba[i * 4 + k] = plane ? plane[i] : 1.0f;
  }
  return result;
}

}  // namespace softpbr::cli
