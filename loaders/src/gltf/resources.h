// The glTF reader's resources (as Filament's gltfio keeps them in its ResourceLoader):
// buffers and their views (EXT_meshopt_compression's decoded first), accessors read as the
// specification says, Draco-compressed attributes, and images, read and decoded into
// textures. Private to the glTF reader (docs/design.md, "glTF").
#pragma once

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "gltf/draco.h"
#include "gltf/reader.h"
#include "softpbr/raster/texture.h"

namespace softpbr::pbr::gltf {

// The extensions that give a texture another image than its core "source", in the order
// one is chosen when a texture has several (all are decoded: any of them will do):
// KHR_texture_basisu (KTX2), EXT_texture_webp, EXT_texture_avif.
inline constexpr const char* kTextureSourceExtensions[] = {"KHR_texture_basisu", "EXT_texture_webp", "EXT_texture_avif"};

// A texture whose extension (kTextureSourceExtensions) names an image takes that image as
// its source: softpbr decodes all three formats, so the core "source" — the PNG or JPEG
// fallback the specifications ask for when the extension is optional, absent when it is
// required — is then not read. Run on the model tinygltf built, before anything reads a
// texture's source; the schema check (schema.cpp) has made the extension's source an image
// index in range.
void use_texture_extension_sources(tg::Model& model);

class Resources : public Context {
 public:
  // `fallback`: the buffers without data (EXT_meshopt_compression's placeholders, see
  // document.h), by index, with their byteLength. External files resolve against `base_dir`.
  Resources(const Context& context, std::string base_dir, std::map<int, std::uint64_t> fallback)
      : Context(context), base_dir_(std::move(base_dir)), fallback_(std::move(fallback)) {}

  // EXT_meshopt_compression: every compressed view decoded, before any accessor is read.
  void decode_compressed_views();

  // The accessor's elements as floats, `components` per element (which must match).
  std::vector<float> read_floats(int index, const std::string& referrer, std::initializer_list<int> allowed,
                                 int* components_out = nullptr) const;
  // An indices accessor's values, each below `vertex_count`.
  std::vector<std::uint32_t> read_indices(int index, std::size_t vertex_count, const std::string& referrer) const;

  // A Draco primitive's indices (the decoded triangles), held to the rules of read_indices'
  // accessor: `index` must describe them (SCALAR, unsigned, their count, a type that holds
  // each).
  std::vector<std::uint32_t> draco_indices(const DracoMesh& d, int index, const std::string& referrer) const;

  // A primitive's KHR_draco_mesh_compression object, decoded.
  DracoMesh draco_mesh(const tg::Value& x, const std::string& ep) const;
  // A Draco attribute's values as the accessor `a` describes them (its type and count must
  // match; integers normalized when the accessor says so).
  std::vector<float> draco_values(const DracoMesh& d, const std::string& name, int a, const std::string& referrer,
                                  std::initializer_list<int> allowed, int* components_out) const;

  // The textures of `jobs` (image index, colour space), in their order: every external
  // image's path joins GltfScene::files, the images the jobs use are read (in parallel on
  // the pool), their memory checked from their headers, then each decoded (on the pool).
  std::vector<std::shared_ptr<const raster::Texture>> textures(const std::vector<std::pair<int, raster::ColorSpace>>& jobs);

 private:
  struct Elements {
    const std::uint8_t* base = nullptr;  // null: no bufferView (zeros, then sparse values)
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
    int components = 0;
    bool normalized = false;
  };

  static std::size_t component_size(int type);
  static float component(const std::uint8_t* p, int type, bool normalized);
  static std::uint32_t index_value(const std::uint8_t* p, int type);
  std::pair<const std::uint8_t*, std::size_t> view_bytes(int view, const std::string& referrer) const;
  Elements elements(int index, const std::string& referrer) const;
  Elements index_elements(int index, const std::string& referrer) const;

  void check_texture_memory(const std::vector<std::pair<int, raster::ColorSpace>>& jobs) const;
  void for_each_job(std::size_t count, const std::function<void(std::size_t)>& fn) const;
  std::span<const std::uint8_t> encoded(int index) const;
  void read_images(const std::vector<std::pair<int, raster::ColorSpace>>& jobs);

  std::string base_dir_;
  std::map<int, std::uint64_t> fallback_;             // buffers without data: their byteLength
  std::map<int, std::vector<std::uint8_t>> decoded_;  // EXT_meshopt_compression views
  // The encoded bytes of the external images the materials use, by image index (tinygltf
  // reads none: TINYGLTF_NO_EXTERNAL_IMAGE), read on the pool by read_images().
  std::vector<std::vector<unsigned char>> external_;
  std::vector<bool> missing_;  // by image: its file cannot be read and MissingImages::Warn left it out
};

}  // namespace softpbr::pbr::gltf
