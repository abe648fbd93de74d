// What inspect_gltf lists (gltf_info.h) of a model tinygltf has parsed: shared by
// inspect_gltf's own parse and by load_and_inspect_gltf, which describes the model
// load_gltf parsed. Private to the glTF reader (docs/design.md, "glTF").
#pragma once

#include <cstddef>
#include <map>
#include <string>

#include "gltf/tinygltf.h"
#include "softpbr/image/load.h"
#include "softpbr/loaders/gltf_info.h"

namespace softpbr::pbr::gltf {

// `warn`: tinygltf's warnings; `headers` and `sizes`: by image index, those of the images
// whose bytes tinygltf handed to its image callback (the external images' are read here,
// within options.max_file_bytes and options.roots, a warning for each that cannot be).
GltfInfo describe(const tinygltf::Model& m, const std::string& file, const std::string& base_dir, const std::string& warn,
                  std::map<int, image::ImageHeader> headers, std::map<int, std::size_t> sizes, const GltfOptions& options);

}  // namespace softpbr::pbr::gltf
