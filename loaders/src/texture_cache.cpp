// Image files as textures, loaded once per colour space (see texture_cache.h).
#include "texture_cache.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <stdexcept>
#include <system_error>

#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"
#include "softpbr/loaders/format_bytes.h"

namespace softpbr::pbr::detail {

namespace fs = std::filesystem;

bool is_float_image_path(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".hdr" || ext == ".exr";
}

TextureImage read_texture_image(const fs::path& path, std::uint64_t max_bytes) {
  image::Limits limits;
  // The base level's share of the bound: levels 1, 2, … of a square chain add 1/4 + 1/16 +
  // … < 1/3 of it (an elongated one up to 1 more: its exact size is charged once built).
  const std::uint64_t base = max_bytes / 4 * 3;
  const bool bounded = base < limits.max_decoded_bytes;
  if (bounded) limits.max_decoded_bytes = base;
  TextureImage out;
  out.is_float = is_float_image_path(path);
  try {
    if (out.is_float) out.imagef = image::load_imagef(path, limits);
    else {
      // With room for the mip chain: make_texture(TextureImage&&) keeps the buffer. A KTX2
      // file's own levels are kept to be used as stored.
      const std::vector<std::uint8_t> bytes = image::read_file(path, limits);
      if (image::is_ktx2(bytes)) {
        image::Ktx2Image k = image::load_ktx2(bytes, path.string(), limits, &raster::Texture::rgba8_chain_bytes);
        out.image8 = std::move(k.levels[0]);
        out.more_levels.assign(std::make_move_iterator(k.levels.begin() + 1), std::make_move_iterator(k.levels.end()));
      } else {
        out.image8 = image::load_image8(bytes, path.string(), limits, &raster::Texture::rgba8_chain_bytes);
      }
    }
  } catch (const std::runtime_error& e) {
    // The library's "… needs N bytes decoded, over the limit of M": say where M comes from.
    const std::string what = e.what();
    if (bounded && what.ends_with("over the limit of " + std::to_string(base)))
      throw std::runtime_error(what + " (the memory limit leaves " + format_bytes(max_bytes) +
                               " for this texture, and its mip levels add a third to the image)");
    throw;
  }
  return out;
}

std::shared_ptr<const raster::Texture> make_texture(TextureImage&& image, raster::ColorSpace space,
                                                    const std::string& name) {
  if (image.is_float) return make_texture(static_cast<const TextureImage&>(image), space, name);
  try {
    return std::make_shared<const raster::Texture>(std::move(image.image8), image.more_levels, space);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
}

std::shared_ptr<const raster::Texture> make_texture(const TextureImage& image, raster::ColorSpace space,
                                                    const std::string& name) {
  try {
    if (image.is_float) return std::make_shared<const raster::Texture>(image::ImageViewF(image.imagef));
    if (!image.more_levels.empty()) {  // the levels as stored: a copy of the base to move in
      image::Image8 base = image.image8;
      return std::make_shared<const raster::Texture>(std::move(base), image.more_levels, space);
    }
    return std::make_shared<const raster::Texture>(image::ImageView8(image.image8), space);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
}

std::string TextureCache::key(const fs::path& path, std::string_view how) {
  std::error_code ec;
  fs::path canonical = fs::canonical(path, ec);
  if (ec) canonical = path.lexically_normal();  // a missing file fails when it is read
  std::string key = canonical.string();
  key += '\0';  // no path holds a NUL
  key += how;
  return key;
}

std::string outside_roots(const fs::path& path, const std::vector<fs::path>& roots) {
  if (roots.empty()) return {};
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (!ec)
    for (const fs::path& root : roots) {
      std::error_code rc;
      const fs::path r = fs::weakly_canonical(fs::absolute(root, rc), rc);
      if (rc) continue;
      const auto [end, unused] = std::mismatch(r.begin(), r.end(), resolved.begin(), resolved.end());
      if (end == r.end() || (std::next(end) == r.end() && end->empty())) return {};  // a trailing "/" is an empty element
    }
  std::string list;
  for (const fs::path& root : roots) list += (list.empty() ? "" : ", ") + root.string();
  return "outside the folders the scene may read (" + list + ")";
}

TextureImage TextureCache::read(const fs::path& path, std::uint64_t max_bytes) const {
  if (const std::string problem = outside_roots(path, roots_); !problem.empty())
    throw std::runtime_error(path.string() + ": " + problem);
  return read_texture_image(path, max_bytes);
}

std::vector<std::string> TextureCache::files() const {
  std::vector<std::string> out;
  for (const auto& [key, texture] : textures_)  // NUL-separated paths and tags
    for (std::size_t at = 0; at < key.size();) {
      const std::size_t end = std::min(key.find('\0', at), key.size());
      if (key[at] == '/') out.push_back(key.substr(at, end - at));
      at = end + 1;
    }
  return out;
}

std::shared_ptr<const raster::Texture> TextureCache::load(const fs::path& path, raster::ColorSpace space,
                                                          std::uint64_t max_bytes) {
  const bool is_float = is_float_image_path(path);
  const char* how = is_float ? "float" : space == raster::ColorSpace::Srgb ? "srgb" : "linear";
  return get(key(path, how), [&] { return make_texture(read(path, max_bytes), space, path.string()); });
}

}  // namespace softpbr::pbr::detail
