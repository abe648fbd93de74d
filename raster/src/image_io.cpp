// PNG output through stb_image_write; every file is written to a temporary name and renamed.
#include <cstdio>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <stb_image_write.h>

#include "softpbr/raster/target.h"

namespace softpbr::raster {

namespace {
void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* bytes = static_cast<const unsigned char*>(data);
  out->insert(out->end(), bytes, bytes + size);
}
}  // namespace

void write_png(const std::filesystem::path& path, const Image8& image) {
  if (image.width < 1 || image.height < 1 ||
      image.rgba.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 4)
    throw std::invalid_argument(path.string() + ": image size and pixel data disagree");
  std::vector<unsigned char> png;
  if (!stbi_write_png_to_func(append_bytes, &png, image.width, image.height, 4, image.rgba.data(), image.width * 4))
    throw std::runtime_error(path.string() + ": PNG encoding failed");

  write_file_atomic(path, png);
}

void write_file_atomic(const std::filesystem::path& path, std::span<const unsigned char> bytes) {
  // A unique temporary name in the destination folder, so rename() is atomic.
  std::random_device rd;
  std::string name = path.filename().string();
  name.insert(name.begin(), '.');
  name.append(".tmp").append(std::to_string(rd()));
  const std::filesystem::path tmp = path.parent_path() / name;
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error(path.string() + ": cannot create " + tmp.string());
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    f.close();
    if (!f) {
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw std::runtime_error(path.string() + ": write failed (disk full?)");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error(path.string() + ": cannot rename the temporary file: " + ec.message());
  }
}

}  // namespace softpbr::raster
