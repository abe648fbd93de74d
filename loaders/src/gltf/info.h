// What inspect_gltf lists (gltf_info.h) of a model tinygltf has parsed: shared by
// inspect_gltf's own parse and by load_and_inspect_gltf, which describes the model
// load_gltf parsed. Private to the glTF reader (docs/design.md, "glTF").
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

#include "gltf/tinygltf.h"
#include "softpbr/image/load.h"
#include "softpbr/loaders/gltf_info.h"

namespace softpbr::pbr::gltf {

// `warn`: tinygltf's warnings; `headers` and `sizes`: by image index, those of the images
// whose bytes tinygltf handed to its image callback (the external images' are read here,
// within options.max_file_bytes and options.roots, a warning for each that cannot be).
GltfInfo describe(const tinygltf::Model& m, const std::string& file, const std::string& base_dir, const std::string& warn,
                  std::map<int, image::ImageHeader> headers, std::map<int, std::size_t> sizes, const GltfOptions& options);

// Puts back into `info`, the listing of a model the pre-pass rewrote for tinygltf
// (prepare_for_tinygltf, document.h), what the file says: the Draco primitives' indices
// (`draco_indices`: (mesh, primitive) → the accessor, -1 for one out of range), so they
// list as indexed with their triangles, and EXT_meshopt_compression's placeholder
// buffers (`placeholders`: by index), of which nothing is read (0 bytes).
void restore_prepass(GltfInfo& info, const tinygltf::Model& m,
                     const std::map<std::pair<std::size_t, std::size_t>, int>& draco_indices,
                     const std::map<int, std::uint64_t>& placeholders);

}  // namespace softpbr::pbr::gltf
