// External files of a .gltf: see files.h.
#include "gltf/files.h"

#include <sys/stat.h>

#include <utility>

#include "softpbr/image/read_file.h"
#include "texture_cache.h"

namespace softpbr::pbr::gltf {

namespace {
int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
}  // namespace

std::string uri_path(const std::string& base_dir, const std::string& uri) {
  std::string decoded;
  decoded.reserve(uri.size());
  for (std::size_t i = 0; i < uri.size(); ++i) {
    const int hi = uri[i] == '%' && i + 2 < uri.size() ? hex_digit(uri[i + 1]) : -1;
    const int lo = hi >= 0 ? hex_digit(uri[i + 2]) : -1;
    if (lo >= 0) {
      decoded += static_cast<char>(hi * 16 + lo);
      i += 2;
    } else {
      decoded += uri[i];
    }
  }
  if (base_dir.empty()) return decoded;
  return base_dir.back() == '/' ? base_dir + decoded : base_dir + "/" + decoded;
}

bool is_external_uri(const std::string& uri) { return !uri.empty() && uri.rfind("data:", 0) != 0; }

std::string read_external(const std::string& path, std::uint64_t limit, const std::vector<std::filesystem::path>& roots,
                          std::vector<unsigned char>& out, bool* unreadable) {
  if (unreadable != nullptr) *unreadable = false;
  // "%00" decodes to a NUL, where the system's calls would end the path early.
  if (const std::size_t nul = path.find('\0'); nul != std::string::npos)
    return path.substr(0, nul) + "…: a NUL character in the file name";
  if (const std::string problem = detail::outside_roots(path, roots); !problem.empty()) return path + ": " + problem;
  std::vector<std::uint8_t> bytes;
  const image::FileProblem p = image::read_whole_file(path, limit, bytes);
  if (p.too_large) return path + ": " + std::to_string(p.size) + " bytes is over the limit of " + std::to_string(limit);
  if (p) {
    if (unreadable != nullptr) *unreadable = true;
    return path + ": " + p.reason;
  }
  out = std::move(bytes);
  return "";
}

bool file_exists(const std::string& path, void*) {
  struct stat st {};
  return path.find('\0') == std::string::npos && ::lstat(path.c_str(), &st) == 0;
}

}  // namespace softpbr::pbr::gltf
