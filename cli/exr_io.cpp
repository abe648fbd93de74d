// OpenEXR through tinyexr (see exr_io.h).
#include "exr_io.h"

#include <cmath>
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

#include "softpbr/raster/dmath.h"

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
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw std::runtime_error(path.string() + ": cannot open: not a regular file");
  if (std::filesystem::file_size(path, ec) > kMaxExrBytes) throw std::runtime_error(path.string() + ": over 1 GiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  float* rgba = nullptr;
  int w = 0, h = 0;
  const char* err = nullptr;
  if (LoadEXRFromMemory(&rgba, &w, &h, bytes.data(), bytes.size(), &err) != TINYEXR_SUCCESS)
    throw std::runtime_error(path.string() + ": not a readable OpenEXR file: " + take_error(err));
  const std::unique_ptr<float, decltype(&std::free)> owned(rgba, &std::free);
  golden::ImageF image{w, h, {}};
  image.rgba.assign(rgba, rgba + static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  return image;
}

}  // namespace softpbr::cli
