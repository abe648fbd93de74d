// The glTF document before tinygltf reads it (see document.h).
#include "gltf/document.h"

#include <algorithm>
#include <climits>
#include <cstring>
#include <functional>

#include "gltf/draco.h"
#include "gltf/files.h"
#include "gltf/meshopt.h"
#include "gltf/schema.h"
#include "json_reader.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/load_error.h"

namespace softpbr::pbr::gltf {

namespace {

constexpr std::uint32_t kJsonChunk = 0x4E4F534Au;  // "JSON"

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

void put_le32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// glTF's JSON before tinygltf parses it, in one streaming pass (json_reader's): keys
// unique within each object (glTF 2.0 §3.2: "names (keys) within JSON objects MUST be
// unique"; nlohmann would keep the last silently), nesting at most kJsonLimits.max_depth
// (tinygltf converts extras and extensions recursively: 200000 nested arrays overflowed
// the stack), at most so many values; then the memory of what tinygltf builds, from the
// pass's counts, against the limit — before any of it is allocated. The estimate is
// nlohmann's document plus tinygltf's copies of it (its Value is ~150 bytes): 192 bytes
// a value, 128 a container, 160 a key (its string and map node, twice), and the text; it
// came out 1.0–1.4× the measured peak on files of 5 M numbers, 300 k nodes and 1 M keys.
// (This reader's own DOM, parse_json's, is freed before tinygltf runs.) A file with
// EXT_meshopt_compression or Draco is written out again for tinygltf first: its estimate
// has that copy too.
constexpr json_reader::StructureLimits kJsonLimits{.max_depth = 256,
                                                   .max_values = std::size_t{1} << 27,
                                                   .max_containers = std::size_t{1} << 25};

}  // namespace

Container read_container(std::span<const std::uint8_t> bytes) {
  Container c;
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  c.binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (!c.binary) {
    c.json = text;
    return c;
  }
  // glTF 2.0 §4.4.3.1: a glTF 2 binary file's header says version 2 (glTF 1.0's binary
  // extension wrote 1, with another layout).
  if (bytes.size() >= 8 && le32(bytes.data() + 4) != 2)
    c.version_problem = "the .glb header's version is " + std::to_string(le32(bytes.data() + 4)) +
                        ": glTF 2.0 binary files are version 2";
  if (bytes.size() < 20) return c;
  // The binary chunk follows the JSON chunk (whatever its type), within the header's length.
  const std::uint64_t end = std::min<std::uint64_t>(le32(bytes.data() + 8), bytes.size());
  const std::uint64_t bin = 20 + std::uint64_t{le32(bytes.data() + 12)};
  if (bin + 8 <= end && bin + 8 + le32(bytes.data() + bin) > end)
    c.bin_problem = "the .glb's binary chunk (" + std::to_string(le32(bytes.data() + bin)) + " bytes at byte " +
                    std::to_string(bin + 8) + ") runs past the end of the file (" + std::to_string(end) + " bytes)";
  const std::uint32_t length = le32(bytes.data() + 12);
  if (le32(bytes.data() + 16) != kJsonChunk || length > bytes.size() - 20) return c;
  c.json = text.substr(20, length);
  c.after_json = bytes.subspan(20 + std::size_t{length});
  return c;
}

void check_json(const Container& container, const std::string& file, std::uint64_t memory_limit) {
  const std::string_view text = container.json;
  json_reader::Counts counts;
  if (const auto problem = json_reader::find_structure_problem(text, &counts, kJsonLimits)) {
    // A pointer 256 levels deep is shortened: one line stays readable.
    const std::string& p = problem->pointer;
    std::string where = p;
    if (p.size() > 120) {  // cut at token boundaries: /a/b/…/y/z
      const std::size_t head = p.rfind('/', 60), tail = p.find('/', p.size() - 40);
      where = p.substr(0, head) + "/…" + p.substr(tail);
    }
    throw LoadError(file + ": " + (where.empty() ? std::string() : where + ": ") + problem->message);
  }
  std::uint64_t estimate = 192 * std::uint64_t{counts.values} + 128 * std::uint64_t{counts.containers} +
                           160 * std::uint64_t{counts.keys} + text.size();
  if (text.find(kMeshopt) != std::string_view::npos || text.find(kDraco) != std::string_view::npos)
    estimate += 32 * std::uint64_t{counts.values} + 64 * std::uint64_t{counts.containers} + 80 * std::uint64_t{counts.keys};
  if (estimate > memory_limit)
    throw LoadError(file + ": parsing its JSON (" + std::to_string(counts.values) + " values) needs an estimated " +
                    format_bytes(estimate) + ", over the memory limit of " + format_bytes(memory_limit));
}

nlohmann::json parse_json(std::string_view json) { return nlohmann::json::parse(json, nullptr, false); }

std::span<const std::uint8_t> prepare_for_tinygltf(std::span<const std::uint8_t> bytes, const Container& container,
                                                   nlohmann::json& doc, std::vector<std::uint8_t>& storage,
                                                   std::map<int, std::uint64_t>& declared,
                                                   std::map<std::pair<std::size_t, std::size_t>, int>& draco_indices) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (text.find(kMeshopt) == std::string_view::npos && text.find(kDraco) == std::string_view::npos) return bytes;
  const bool glb = container.binary;
  if (glb && container.json.empty()) return bytes;
  if (doc.is_discarded() || !doc.is_object()) return bytes;
  const auto used = doc.find("extensionsUsed");
  if (used == doc.end() || !used->is_array()) return bytes;
  const bool meshopt = std::find(used->begin(), used->end(), kMeshopt) != used->end();
  const bool draco = std::find(used->begin(), used->end(), kDraco) != used->end();
  // What was changed, to put back should the rewritten file not be written (`doc` is then
  // the file's JSON again, as tinygltf reads it).
  std::vector<std::pair<nlohmann::json*, nlohmann::json>> erased_indices, replaced_buffers;
  const auto meshes = doc.find("meshes");
  if (draco && meshes != doc.end() && meshes->is_array())
    for (std::size_t m = 0; m < meshes->size(); ++m) {
      nlohmann::json& mesh = (*meshes)[m];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      nlohmann::json& primitives = mesh["primitives"];
      for (std::size_t k = 0; k < primitives.size(); ++k) {
        nlohmann::json& p = primitives[k];
        if (!p.is_object() || !p.contains("indices") || !p.contains("extensions") || !p["extensions"].is_object() ||
            !p["extensions"].contains(kDraco) || !p["indices"].is_number_integer())
          continue;
        const auto index = p["indices"].get<std::int64_t>();
        draco_indices[{m, k}] = index >= 0 && index <= INT_MAX ? static_cast<int>(index) : -1;
        erased_indices.emplace_back(&p, std::move(p["indices"]));
        p.erase("indices");
      }
    }
  const auto buffers = doc.find("buffers");
  if (meshopt && buffers != doc.end() && buffers->is_array())
    for (std::size_t i = 0; i < buffers->size() && i <= static_cast<std::size_t>(INT_MAX); ++i) {
      nlohmann::json& b = (*buffers)[i];
      if (!b.is_object() || b.contains("uri") || (glb && i == 0)) continue;
      const auto length = b.find("byteLength");
      if (length == b.end() || !length->is_number_integer() || length->get<std::int64_t>() < 1) continue;
      declared[static_cast<int>(i)] = length->get<std::uint64_t>();
      replaced_buffers.emplace_back(&b, std::move(b));
      b = nlohmann::json{{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
    }
  if (erased_indices.empty() && replaced_buffers.empty()) return bytes;
  std::string out = doc.dump();
  if (!glb) {
    storage.assign(out.begin(), out.end());
    return storage;
  }
  while (out.size() % 4 != 0) out.push_back(' ');
  const std::size_t rest = container.after_json.size();
  if (out.size() > UINT32_MAX - 20 - rest) {
    for (auto& [p, indices] : erased_indices) (*p)["indices"] = std::move(indices);
    for (auto& [b, original] : replaced_buffers) *b = std::move(original);
    return bytes;
  }
  storage.resize(20 + out.size() + rest);
  std::memcpy(storage.data(), bytes.data(), 12);  // magic and version
  put_le32(storage.data() + 8, static_cast<std::uint32_t>(storage.size()));
  put_le32(storage.data() + 12, static_cast<std::uint32_t>(out.size()));
  put_le32(storage.data() + 16, kJsonChunk);
  std::memcpy(storage.data() + 20, out.data(), out.size());
  if (rest > 0) std::memcpy(storage.data() + 20 + out.size(), container.after_json.data(), rest);
  return storage;
}

ErrorHints error_hints(const nlohmann::json& doc) {
  ErrorHints hints;
  if (doc.is_discarded() || !doc.is_object()) return hints;
  auto array = [&](const char* key) -> const nlohmann::json* {
    const auto it = doc.find(key);
    return it != doc.end() && it->is_array() ? &*it : nullptr;
  };
  const nlohmann::json* accessors = array("accessors");
  const nlohmann::json* views = array("bufferViews");
  const std::size_t accessor_count = accessors != nullptr ? accessors->size() : 0;
  const std::size_t view_count = views != nullptr ? views->size() : 0;
  // A buffer's file that tinygltf looked for: the buffer whose uri it is.
  const nlohmann::json* buffers = array("buffers");
  for (std::size_t b = 0; buffers != nullptr && b < buffers->size(); ++b) {
    const nlohmann::json& buffer = (*buffers)[b];
    if (!buffer.is_object() || !buffer.contains("uri") || !buffer["uri"].is_string()) continue;
    const std::string& uri = buffer["uri"].get_ref<const std::string&>();
    ErrorHints::Uri u;
    u.buffer = b;
    if (uri.size() <= ErrorHints::kKept) u.text = uri;
    else u.size = uri.size(), u.hash = std::hash<std::string_view>{}(uri);
    hints.buffer_uris.push_back(std::move(u));
  }
  // The first bufferView whose byteStride tinygltf refuses.
  for (std::size_t v = 0; v < view_count; ++v) {
    const nlohmann::json& view = (*views)[v];
    if (!view.is_object() || !view.contains("byteStride") || !view["byteStride"].is_number_integer()) continue;
    const auto s = view["byteStride"].get<std::int64_t>();
    if (s > 252 || s % 4 != 0 || (s != 0 && s < 4)) {
      hints.stride = "/bufferViews/" + std::to_string(v) + "/byteStride: must be a multiple of 4 in [4, 252], got " +
                     std::to_string(s);
      break;
    }
  }
  // The first primitive whose indices accessor does not exist, and the first whose
  // accessor (which exists) has no valid bufferView.
  const nlohmann::json* meshes = array("meshes");
  for (std::size_t m = 0; meshes != nullptr && m < meshes->size(); ++m) {
    const nlohmann::json& mesh = (*meshes)[m];
    if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
    const nlohmann::json& primitives = mesh["primitives"];
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      const nlohmann::json& p = primitives[k];
      if (!p.is_object() || !p.contains("indices") || !p["indices"].is_number_integer()) continue;
      const auto a = p["indices"].get<std::int64_t>();
      if (a < 0) continue;
      auto pointer = [&] {
        return "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k) + "/indices";
      };
      if (static_cast<std::uint64_t>(a) >= accessor_count) {
        if (hints.indices_range.empty()) hints.indices_range = pointer() + ": accessor " + std::to_string(a) + " does not exist";
        continue;
      }
      if (!hints.indices_view.empty()) continue;
      const nlohmann::json& accessor = (*accessors)[static_cast<std::size_t>(a)];
      auto ap = [&] { return "/accessors/" + std::to_string(a); };
      if (!accessor.is_object() || !accessor.contains("bufferView")) {
        hints.indices_view = ap() + ": has no bufferView, which indices need (" + pointer() + ")";
        continue;
      }
      const nlohmann::json& view = accessor["bufferView"];
      if (!view.is_number_integer() || view.get<std::int64_t>() < 0 ||
          static_cast<std::uint64_t>(view.get<std::int64_t>()) >= view_count)
        hints.indices_view = ap() + "/bufferView: bufferView " + view.dump() + " does not exist";
    }
  }
  return hints;
}

namespace {
// A URI as a message quotes it: at most 40 bytes, then "…" (a data URI can be megabytes).
std::string shown_uri(const std::string& uri) {
  constexpr std::size_t kShown = 40;
  return uri.size() <= kShown ? uri : uri.substr(0, kShown) + "…";
}

// The buffer whose uri is `uri` (found by its text, or its percent-decoded text as tinygltf
// names a file it looked for, or for a long one by its size and hash).
const ErrorHints::Uri* buffer_of(const ErrorHints& hints, const std::string& uri) {
  const std::size_t hash = uri.size() > ErrorHints::kKept ? std::hash<std::string_view>{}(uri) : 0;
  for (const ErrorHints::Uri& u : hints.buffer_uris)
    if (uri.size() <= ErrorHints::kKept ? u.size == 0 && (u.text == uri || uri_path("", u.text) == uri)
                                        : u.size == uri.size() && u.hash == hash)
      return &u;
  return nullptr;
}
}  // namespace

std::string tinygltf_error_with_pointer(const ErrorHints& hints, const std::string& err) {
  const std::string line = err.substr(0, err.find('\n'));
  if (line.rfind("File not found : ", 0) == 0) {
    // tinygltf looks for a buffer's file before reading it.
    const std::string uri = line.substr(17);
    if (const ErrorHints::Uri* u = buffer_of(hints, uri))
      return "/buffers/" + std::to_string(u->buffer) + "/uri: " + shown_uri(uri) + ": no such file";
    return shown_uri(uri) + ": no such file (a buffer's file)";
  }
  // A data URI whose decoded bytes are not byteLength bytes (tinygltf quotes the whole URI).
  const std::string decode = "Failed to decode 'uri' : ", in_buffer = " in Buffer";
  if (line.rfind(decode, 0) == 0 && line.size() >= decode.size() + in_buffer.size() && line.ends_with(in_buffer)) {
    const std::string uri = line.substr(decode.size(), line.size() - decode.size() - in_buffer.size());
    if (const ErrorHints::Uri* u = buffer_of(hints, uri))
      return "/buffers/" + std::to_string(u->buffer) + "/uri: the data URI \"" + shown_uri(uri) + "\" (" +
             std::to_string(uri.size()) + " bytes) does not decode to the buffer's byteLength bytes";
    return "a buffer's data URI \"" + shown_uri(uri) + "\" (" + std::to_string(uri.size()) +
           " bytes) does not decode to its byteLength bytes";
  }
  if (err.rfind("Invalid `byteStride' value.", 0) == 0) return hints.stride;
  if (err.rfind("primitive indices accessor out of bounds", 0) == 0) return hints.indices_range;
  if (err.rfind("accessor[", 0) == 0 && err.find("] invalid bufferView") != std::string::npos) return hints.indices_view;
  return {};
}

std::string buffer_pointer(const ErrorHints& hints, const std::string& base_dir, const std::string& path) {
  for (const ErrorHints::Uri& u : hints.buffer_uris)
    if (u.size == 0 && uri_path(base_dir, u.text) == path) return "/buffers/" + std::to_string(u.buffer) + "/uri: ";
  return {};
}

Document read_document(std::span<const std::uint8_t> bytes, const std::string& file, std::uint64_t memory_limit,
                       bool schema) {
  Document d;
  d.container = read_container(bytes);
  if (!d.container.version_problem.empty()) throw LoadError(file + ": " + d.container.version_problem);
  if (!d.container.bin_problem.empty()) throw LoadError(file + ": " + d.container.bin_problem);
  check_json(d.container, file, memory_limit);
  nlohmann::json dom = parse_json(d.container.json);
  if (schema)
    if (const auto problem = check_schema(dom)) throw LoadError(file + ": " + *problem);
  d.bytes = prepare_for_tinygltf(bytes, d.container, dom, d.storage, d.placeholders, d.draco_indices);
  d.hints = error_hints(dom);
  return d;
}

}  // namespace softpbr::pbr::gltf
