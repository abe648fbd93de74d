// The glTF document before tinygltf reads it (docs/design.md, "glTF"): the .glb container,
// the JSON's streaming check, its one DOM, the schema check on that DOM (schema.h), the
// pre-pass that rewrites what tinygltf 2.7 refuses, and what the error path needs of the
// DOM once tinygltf has failed. Private to the glTF reader (gltf.cpp, info.cpp).
//
// The JSON is parsed once into a DOM here (plus tinygltf's own parse of the text it is
// given): a streaming pass (json_reader's SAX, which builds nothing) checks the limits and
// estimates the memory first, since those must hold before any DOM is built.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace softpbr::pbr::gltf {

// A .gltf, or a .glb (glTF 2.0 §4.4: a 12-byte header — magic "glTF", version, length —
// then chunks of an 8-byte header — length, type — and data: JSON first, then BIN).
struct Container {
  bool binary = false;    // starts with the magic "glTF": tinygltf reads it as a .glb
  // The JSON text: a .gltf's whole file, a .glb's JSON chunk (empty when the .glb is
  // shorter than its headers, its first chunk is not JSON or runs past the file).
  std::string_view json;
  std::span<const std::uint8_t> after_json;  // a .glb's bytes after its JSON chunk (the BIN chunk)
  // A .glb's binary chunk must lie inside the file (the header's length, at most the
  // file's): tinygltf 2.7 leaves the chunk's 8-byte header out of its check and then
  // copies up to 8 bytes from past the end (fuzz_gltf). What is wrong, else "".
  std::string bin_problem;
  // A .glb header's version other than 2, else "".
  std::string version_problem;
};

Container read_container(std::span<const std::uint8_t> bytes);

// The JSON's limits, checked in one streaming pass (json_reader's) before any DOM is built:
// keys unique within each object, nesting, numbers within double's range, the number of
// values; then the memory of what parsing builds, estimated from the pass's counts, against
// `memory_limit`. Throws LoadError ("file: /pointer: message").
void check_json(const Container& container, const std::string& file, std::uint64_t memory_limit);

// The one DOM of the JSON text (discarded — is_discarded() — when it is not JSON: tinygltf
// then says what is wrong).
nlohmann::json parse_json(std::string_view json);

// Two things tinygltf 2.7 refuses that these extensions write, rewritten in the DOM and
// written out as the file tinygltf parses (`bytes` is returned unchanged when neither
// occurs, or when the JSON cannot be read here: tinygltf then reports the problem; else the
// rewritten file is in `storage`, and `dom` is what it holds):
// - EXT_meshopt_compression's "fallback" buffers, which have no URI (their bytes exist
//   only compressed): tinygltf reads no buffer without one but a .glb's first. When
//   extensionsUsed names the extension, each is replaced by a one-byte data URI, and
//   `declared` receives its byteLength.
// - KHR_draco_mesh_compression's primitives, whose indices accessor has no bufferView
//   (the triangles are in the Draco data): tinygltf refuses such an accessor as indices.
//   When extensionsUsed names the extension, a Draco primitive's "indices" is removed, and
//   `draco_indices` receives it, keyed by (mesh, primitive).
std::span<const std::uint8_t> prepare_for_tinygltf(std::span<const std::uint8_t> bytes, const Container& container,
                                                   nlohmann::json& dom, std::vector<std::uint8_t>& storage,
                                                   std::map<int, std::uint64_t>& declared,
                                                   std::map<std::pair<std::size_t, std::size_t>, int>& draco_indices);

// What tinygltf_error_with_pointer needs of the DOM (as prepare_for_tinygltf left it: what
// tinygltf parsed), taken from it before tinygltf runs so that the DOM is freed first, as
// the schema check's and the pre-pass's documents were before (check_json's estimate is of
// what tinygltf builds). Each message is the first such problem's, "" when there is none.
struct ErrorHints {
  struct Uri {
    std::size_t buffer = 0;
    std::string text;       // the uri, when at most kKept bytes
    std::size_t size = 0;   // else its size and hash (a long data URI is not kept twice)
    std::size_t hash = 0;
  };
  static constexpr std::size_t kKept = 256;
  std::vector<Uri> buffer_uris;   // the buffers whose uri is a string, in order
  std::string stride;             // a bufferView's invalid byteStride
  std::string indices_range;      // a primitive's indices accessor that does not exist
  std::string indices_view;       // an indices accessor without a valid bufferView
};
ErrorHints error_hints(const nlohmann::json& dom);

// A message of tinygltf's own checks (made while it parses, so without a JSON pointer) as
// softpbr's `/json/pointer: message`, found again in the document: an indices accessor
// out of range or without a valid bufferView, a bufferView's invalid byteStride, a buffer's
// file that does not exist, a buffer's data URI that does not decode to byteLength bytes
// (URIs quoted to 40 bytes; those two without a pointer when the buffer is not found).
// Empty when `err` is none of those or the value is not found.
std::string tinygltf_error_with_pointer(const ErrorHints& hints, const std::string& err);

// The JSON pointer of the buffer whose file is `path` followed by ": ", or "" when no
// buffer's URI (joined to base_dir as gltf::uri_path joins it, as tinygltf reads it) names
// it: for a buffer's file that could not be read.
std::string buffer_pointer(const ErrorHints& hints, const std::string& base_dir, const std::string& path);

// The document steps load_gltf and inspect_gltf both take, in order: the container (its BIN
// problem thrown), check_json, the one DOM, with `schema` the schema check (load_gltf's),
// the pre-pass and the error hints; the DOM is freed before this returns, so that it is
// gone before tinygltf builds its own. Throws LoadError ("file: ...").
struct Document {
  Container container;
  std::span<const std::uint8_t> bytes;  // what tinygltf parses: the file, or the rewrite
  std::vector<std::uint8_t> storage;    // the rewrite, when there is one
  std::map<int, std::uint64_t> placeholders;  // prepare_for_tinygltf's `declared`
  std::map<std::pair<std::size_t, std::size_t>, int> draco_indices;
  ErrorHints hints;
  bool rewritten() const { return !storage.empty(); }
};
Document read_document(std::span<const std::uint8_t> bytes, const std::string& file, std::uint64_t memory_limit,
                       bool schema);

}  // namespace softpbr::pbr::gltf
