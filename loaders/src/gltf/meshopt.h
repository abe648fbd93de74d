// EXT_meshopt_compression (gltfpack's output): the compressed bufferViews of a glTF,
// decoded before any accessor is read (the pre-pass that lets tinygltf read such a file is
// document.h's). Private to the glTF reader (docs/design.md, "glTF").
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gltf/tinygltf.h"

namespace softpbr::pbr::gltf {

inline constexpr const char* kMeshopt = "EXT_meshopt_compression";

// Decodes every bufferView with the extension into `decoded` (view index → its bytes,
// byteLength of them), validating the extension object per its specification. `fail`
// throws with the JSON pointer and message. `max_bytes` bounds the decoded views together.
void decode_meshopt_views(const tinygltf::Model& model, const std::map<int, std::uint64_t>& fallback,
                          std::uint64_t max_bytes, std::map<int, std::vector<std::uint8_t>>& decoded,
                          const std::function<void(const std::string&, const std::string&)>& fail);

// The extension's filters (its Appendix B), on `count` elements of `stride` bytes in
// place. softpbr's own code rather than meshoptimizer's: those use approximate reciprocal
// square roots (SSE rsqrtps, NEON vrsqrte), whose bits differ between CPUs; these are IEEE
// operations in a fixed order, so a decoded normal has the same bits everywhere.
void filter_octahedral(std::uint8_t* data, std::size_t count, std::size_t stride);
void filter_quaternion(std::uint8_t* data, std::size_t count);
void filter_exponential(std::uint8_t* data, std::size_t count, std::size_t stride);

}  // namespace softpbr::pbr::gltf
