// texture_cache.h — image files as textures, for scene files and MTL maps (private to
// loaders/src): a TextureCache decodes and mip-maps each file once per colour space, and an
// image whose texels would pass a memory bound is refused from its header, before decoding.
//
// Scene files (scene_file/textures.cpp) and OBJ models (mtl_textures.cpp) share one cache
// per scene load, so a file named by several materials, slots or MTL maps is one Texture.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "softpbr/image/image.h"
#include "softpbr/raster/texture.h"

namespace softpbr::pbr::detail {

// The pixels of an image file read for a texture: 8-bit (PNG or JPEG) or float (.hdr or .exr).
struct TextureImage {
  bool is_float = false;
  image::Image8 image8;
  std::vector<image::Image8> more_levels;  // a KTX2 file's levels after image8, used as stored
  image::ImageF imagef;

  int width() const { return is_float ? imagef.width : image8.width; }
  int height() const { return is_float ? imagef.height : image8.height; }
};

// Whether `path` names a float image: its extension is .hdr or .exr (any case). Other files
// are read as 8-bit images; within each kind the image library tells the format (PNG or
// JPEG, .hdr or .exr) by the first bytes.
bool is_float_image_path(const std::filesystem::path& path);

// Reads `path` for a texture whose texels, mip levels included, may take at most
// `max_bytes`. The image library checks the header before decoding against a decoded-bytes
// limit of 3/4 of `max_bytes` (a square mip chain adds a third to its base level), so an
// image too large for what is left is refused undecoded. Throws std::runtime_error: the
// image library's one line, starting with the path.
TextureImage read_texture_image(const std::filesystem::path& path, std::uint64_t max_bytes);

// The texture of `image`: 8-bit images with their colour channels read in `space`, float
// ones as stored (linear, whatever the space). Throws std::runtime_error "<name>: …" when
// the texture refuses the pixels (a float texel that is not finite).
std::shared_ptr<const raster::Texture> make_texture(const TextureImage& image, raster::ColorSpace space,
                                                    const std::string& name);
// The same, keeping an 8-bit image's pixel buffer (read_texture_image leaves room for the
// mip chain in it).
std::shared_ptr<const raster::Texture> make_texture(TextureImage&& image, raster::ColorSpace space,
                                                    const std::string& name);

// "" when `roots` is empty or `path`, with symbolic links and ".." resolved, lies inside
// one of them (each root itself resolved); else the problem, "outside the folders …".
std::string outside_roots(const std::filesystem::path& path, const std::vector<std::filesystem::path>& roots);

class TextureCache {
 public:
  // The folders images may be read from (see outside_roots); empty: anywhere.
  void set_roots(std::vector<std::filesystem::path> roots) { roots_ = std::move(roots); }
  const std::vector<std::filesystem::path>& roots() const { return roots_; }
  // read_texture_image, after checking `path` against the roots (std::runtime_error).
  TextureImage read(const std::filesystem::path& path, std::uint64_t max_bytes) const;

  // A key naming an image file — its canonical path when it exists — and how it is read:
  // "srgb", "linear", "float", or the tag of a texture combined from several files.
  static std::string key(const std::filesystem::path& path, std::string_view how);

  // The texture stored under `key`, or make()'s, stored first. A null result is stored
  // too (a file found not to be a texture of that kind: a height map given as a bump map).
  template <class Make>
  std::shared_ptr<const raster::Texture> get(const std::string& key, Make&& make) {
    if (const auto it = textures_.find(key); it != textures_.end()) return it->second;
    std::shared_ptr<const raster::Texture> texture = make();
    if (texture && counted_.insert(texture.get()).second) bytes_ += texture->texel_bytes();
    textures_.emplace(key, texture);
    return texture;
  }

  // `path`'s image as a texture read in `space` (float images are one texture for every
  // space), read within `max_bytes` as read_texture_image.
  std::shared_ptr<const raster::Texture> load(const std::filesystem::path& path, raster::ColorSpace space,
                                              std::uint64_t max_bytes);

  // Texels of every texture made, each once.
  std::uint64_t bytes() const { return bytes_; }
  // The image files named by the keys so far (canonical paths), for a caller that must
  // not overwrite its inputs.
  std::vector<std::string> files() const;

 private:
  std::map<std::string, std::shared_ptr<const raster::Texture>> textures_;
  std::set<const raster::Texture*> counted_;  // a texture stored under two keys counts once
  std::uint64_t bytes_ = 0;
  std::vector<std::filesystem::path> roots_;
};

}  // namespace softpbr::pbr::detail
