// softpbr/loaders/gltf_info.h — what a glTF 2.0 file holds, as `softpbr info model.glb` lists
// it: counts of scenes, nodes, meshes, primitives and triangles, the materials and their
// textures, the images with their sizes read from their headers (never decoded), the
// extensions used and required, cameras, lights, skins and animations.
//
//   pbr::GltfInfo info = pbr::inspect_gltf("model.glb");
//
// inspect_gltf parses the JSON and reads the buffers and image files (with the options'
// file-size limit and roots) but validates nothing beyond what it reads: load_gltf is the
// validator, and `softpbr info` runs it first (load_and_inspect_gltf) so a bad file gets
// load_gltf's error.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "softpbr/loaders/gltf.h"

namespace softpbr::pbr {

struct GltfPrimitiveInfo {
  int mode = 4;                         // glTF's: 0 points … 4 triangles, 5 strip, 6 fan
  std::size_t triangles = 0;            // by its index (or POSITION) count and mode
  int material = -1;                    // -1: the default material
  bool indexed = false;
  std::vector<std::string> attributes;  // POSITION, NORMAL, … in the file's order (sorted)
  std::vector<std::string> extensions;  // KHR_draco_mesh_compression, …
};

struct GltfMeshInfo {
  std::string name;
  std::vector<GltfPrimitiveInfo> primitives;
  std::size_t triangles = 0;            // the primitives' sum
  std::size_t morph_targets = 0;        // the most any primitive has
};

struct GltfMaterialInfo {
  std::string name;
  std::string alpha_mode = "OPAQUE";
  bool double_sided = false;
  // The textured slots: ("base_color", texture index), in the order base_color,
  // metallic_roughness, normal, occlusion, emissive.
  std::vector<std::pair<std::string, int>> textures;
  std::vector<std::string> extensions;  // the material's own (KHR_materials_unlit, …)
};

struct GltfTextureInfo {
  std::string name;
  int source = -1;   // the image (-1: none glTF core can read, e.g. only an EXT_texture_webp source)
  int sampler = -1;  // -1: the default sampler
};

struct GltfImageInfo {
  std::string name;
  std::string location;   // the file's URI, "data URI" or "bufferView N"
  std::string mime_type;  // as the file says ("" when it does not)
  std::string format;     // by the first bytes: "png", "jpeg", … ("" unknown or unread)
  int width = 0, height = 0;  // from the header; 0 when it could not be read
  std::size_t bytes = 0;      // encoded
  std::string detail;         // KTX2: "UASTC, Zstandard, 1 level, sRGB" (image::ImageHeader::detail)
};

struct GltfNamedInfo {
  std::string name;
  std::string type;  // cameras: perspective, orthographic; lights: point, spot, directional
};

struct GltfInfo {
  std::string version, generator, copyright;  // the asset's
  std::size_t scenes = 0;
  int default_scene = -1;                     // "scene", -1 when absent
  std::vector<std::string> scene_names;       // each scene's name ("" when it has none), in order
  std::size_t nodes = 0, accessors = 0, buffer_views = 0, buffers = 0, samplers = 0, skins = 0, animations = 0;
  std::uint64_t buffer_bytes = 0;             // the buffers' sizes, as read
  std::vector<GltfMeshInfo> meshes;
  std::vector<GltfMaterialInfo> materials;
  std::vector<GltfTextureInfo> textures;
  std::vector<GltfImageInfo> images;
  std::vector<GltfNamedInfo> cameras, lights;
  std::vector<std::string> extensions_used, extensions_required;
  std::vector<std::string> variants;          // KHR_materials_variants' names, in their order
  std::vector<std::string> parser_warnings;   // tinygltf's, one per line, prefixed by the file
  std::size_t primitives() const;
  std::size_t triangles() const;              // in the meshes, each counted once
};

// Throws LoadError (load_error.h) with one line starting with the file when it cannot be read or
// parsed as glTF. Only options.max_file_bytes, options.roots and options.memory_limit (the
// JSON's estimate, as load_gltf checks it) are used.
GltfInfo inspect_gltf(const std::filesystem::path& path, const GltfOptions& options = {});

// load_gltf and inspect_gltf of one file, as `softpbr info` shows it: the same scene and
// the same listing as the two calls, with the file read and its JSON parsed once for both
// (inspect_gltf's listing comes from the model load_gltf parsed; a file with
// EXT_meshopt_compression or Draco, which both rewrite for tinygltf — docs/design.md,
// "glTF" —, is listed as written).
struct GltfModelInfo {
  GltfScene scene;
  GltfInfo info;
};
GltfModelInfo load_and_inspect_gltf(const std::filesystem::path& path, const GltfOptions& options = {});

}  // namespace softpbr::pbr
