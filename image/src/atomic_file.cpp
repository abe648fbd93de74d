// Atomic file replacement: a temporary file in the destination folder, then rename (see
// write.h). rename() within one file system replaces the destination in one step (POSIX).
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

#include "softpbr/image/write.h"

namespace softpbr::image {

void write_file_atomic(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
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

}  // namespace softpbr::image
