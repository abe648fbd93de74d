// EXT_meshopt_compression (gltfpack's output): the compressed bufferViews of a glTF,
// decoded before any accessor is read. Private to gltf.cpp (docs/design.md, "glTF").
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

// The JSON text of a .gltf (the whole file), or of a .glb's JSON chunk (empty when that
// chunk is malformed or runs past the file).
std::string_view json_text(std::span<const std::uint8_t> bytes);

// Two things tinygltf 2.7 refuses that these extensions write, rewritten in the file's
// JSON before tinygltf sees it (`bytes` is returned unchanged when neither occurs, or when
// the JSON cannot be read here: tinygltf then reports the problem; else the rewritten file
// is in `storage`):
// - EXT_meshopt_compression's "fallback" buffers, which have no URI (their bytes exist
//   only compressed): tinygltf reads no buffer without one but a .glb's first. When
//   extensionsUsed names the extension, each is replaced by a one-byte data URI, and
//   `declared` receives its byteLength.
// - KHR_draco_mesh_compression's primitives, whose indices accessor has no bufferView
//   (the triangles are in the Draco data): tinygltf refuses such an accessor as indices.
//   When extensionsUsed names the extension, a Draco primitive's "indices" is removed, and
//   `draco_indices` receives it, keyed by (mesh, primitive).
std::span<const std::uint8_t> prepare_for_tinygltf(std::span<const std::uint8_t> bytes, std::vector<std::uint8_t>& storage,
                                                   std::map<int, std::uint64_t>& declared,
                                                   std::map<std::pair<std::size_t, std::size_t>, int>& draco_indices);

// A message of tinygltf's own checks (made while it parses, so without a JSON pointer) as
// softpbr's `/json/pointer: message`, found again in the file's JSON: an indices accessor
// out of range or without a valid bufferView, a bufferView's invalid byteStride. Empty when
// `err` is none of those or the value cannot be found.
std::string tinygltf_error_with_pointer(std::span<const std::uint8_t> bytes, const std::string& err);

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
