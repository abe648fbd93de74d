// mtl_textures.h — MTL texture maps onto a Material's texture slots (private to loaders/src):
// obj.cpp reads the MTL text and notes where each map statement is; mtl_textures.cpp
// loads, combines and checks the images (the mapping is documented in obj.h).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <tiny_obj_loader.h>

#include "softpbr/loaders/obj.h"
#include "texture_cache.h"

namespace softpbr::pbr::detail {

// The MTL map statements that become texture slots.
enum MtlMap : std::size_t { kMapKd, kMapKe, kMapPr, kMapPm, kMapNs, kMapNorm, kMapBump, kMapD, kMtlMapCount };

// What the MTL text says about one material beyond tinyobjloader's values.
struct MtlInfo {
  std::filesystem::path file;
  bool has_pr = false;  // "Pr" present (tinyobjloader's default 0 is indistinguishable)
  bool has_ns = false;  // "Ns" present (tinyobjloader's default is 1)
  bool has_pm = false;
  bool has_kd = false;  // (tinyobjloader sets Kd to 0.6 for a map_Kd without Kd)
  bool has_ke = false;
  // The line and keyword of each map statement — the last one, which tinyobjloader
  // keeps; line 0 when there is none (or the text and tinyobjloader disagree).
  std::array<std::size_t, kMtlMapCount> line{};
  std::array<std::string, kMtlMapCount> keyword{};
};

// Where a model's maps load: the cache (a scene file's, or the model's own) and the bound
// on the bytes the model may add to it.
struct MtlTextures {
  TextureCache& cache;
  std::uint64_t limit;
  std::uint64_t start;  // cache.bytes() when the model began
  std::vector<std::string>& warnings;
  MissingImages missing_images = MissingImages::Error;

  std::uint64_t left() const {
    const std::uint64_t used = cache.bytes() - start;
    return used < limit ? limit - used : 0;
  }
};

// Sets `material`'s texture slots from `m`'s maps, and the factors a map without its
// constant implies. Throws LoadError "FILE.mtl:LINE: KEYWORD: …".
void map_textures(const tinyobj::material_t& m, const MtlInfo& info, Material& material, MtlTextures& textures);

// load_obj with its textures in `cache` (a scene file's, shared with its materials); the
// model's texture_bytes and ObjOptions::texture_memory_limit count what it adds to the cache.
ObjModel load_obj(const std::filesystem::path& path, const ObjOptions& options, TextureCache& cache);

}  // namespace softpbr::pbr::detail
