// The glTF 2.0 schema's structural rules, before tinygltf (see schema.h).
#include "gltf/schema.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "json_reader.h"

namespace softpbr::pbr::gltf {

namespace {

using Json = nlohmann::json;

struct Found {
  std::string text;
};

// A value for "got …": its JSON text, shortened (large arrays and objects summarised).
std::string got(const Json& v) { return json_reader::show(v); }

[[noreturn]] void fail(const std::string& pointer, const std::string& message) {
  throw Found{pointer.empty() ? message : pointer + ": " + message};
}

bool is_integer(const Json& v) {
  if (v.is_number_integer()) return true;
  // JSON Schema's "integer" includes numbers with a zero fraction (1.0).
  return v.is_number_float() && std::isfinite(v.get<double>()) && std::floor(v.get<double>()) == v.get<double>() &&
         std::fabs(v.get<double>()) < 9.0e15;
}

std::string key_pointer(const std::string& p, const char* key) { return p + "/" + key; }

const Json* member(const Json& o, const char* key) {
  const auto it = o.find(key);
  return it == o.end() ? nullptr : &*it;
}

void object(const Json& v, const std::string& p) {
  if (!v.is_object()) fail(p, "must be a JSON object, got " + got(v));
}

const Json& required(const Json& o, const std::string& p, const char* key) {
  const Json* v = member(o, key);
  if (v == nullptr) fail(p, std::string("missing required property \"") + key + "\"");
  return *v;
}

// The largest integer tinygltf 2.7 keeps in an `int` (indices, componentType, mode, …,
// and every integer inside "extensions", which its Value holds as an int): anything larger
// it would read modulo 2^32 (2^32 + 1 became 1), so such a value is refused here, read as
// the exact number it is (nlohmann keeps 64-bit integers; a larger one is a double).
constexpr long long kIntMax = 2147483647;
// The largest size tinygltf keeps in a size_t (byteLength, byteOffset, count): the
// largest integer a double holds exactly, which is_integer allows.
constexpr long long kSizeMax = 9000000000000000;
// The most elements the reader takes from one accessor (reader.h's kMaxElements, 2^28).
constexpr long long kMaxAccessorCount = 268435456;

// An integer in [`lo`, `hi`] (indices: ≥ 0).
void integer(const Json& o, const std::string& p, const char* key, long long lo, bool needed = false,
             long long hi = kIntMax) {
  const Json* v = needed ? &required(o, p, key) : member(o, key);
  if (v == nullptr) return;
  if (!is_integer(*v) || v->get<double>() < static_cast<double>(lo))
    fail(key_pointer(p, key), (lo == 0 ? "must be an index (an integer >= 0), got " : "must be an integer >= " +
                                                                                          std::to_string(lo) + ", got ") +
                                  got(*v));
  if (v->get<double>() > static_cast<double>(hi))
    fail(key_pointer(p, key), "must be at most " + std::to_string(hi) + ", got " + got(*v));
}

void number(const Json& o, const std::string& p, const char* key) {
  const Json* v = member(o, key);
  if (v != nullptr && !v->is_number()) fail(key_pointer(p, key), "must be a number, got " + got(*v));
}

void boolean(const Json& o, const std::string& p, const char* key) {
  const Json* v = member(o, key);
  if (v != nullptr && !v->is_boolean()) fail(key_pointer(p, key), "must be true or false, got " + got(*v));
}

void string(const Json& o, const std::string& p, const char* key, bool needed = false) {
  const Json* v = needed ? &required(o, p, key) : member(o, key);
  if (v != nullptr && !v->is_string()) fail(key_pointer(p, key), "must be a string, got " + got(*v));
}

// An array of `n` numbers (n == 0: of any length).
void numbers(const Json& o, const std::string& p, const char* key, std::size_t n) {
  const Json* v = member(o, key);
  if (v == nullptr) return;
  const std::string kp = key_pointer(p, key);
  if (!v->is_array() || (n != 0 && v->size() != n))
    fail(kp, (n != 0 ? "must be an array of " + std::to_string(n) + " numbers" : std::string("must be an array of numbers")) +
                 ", got " + got(*v));
  for (std::size_t i = 0; i < v->size(); ++i)
    if (!(*v)[i].is_number()) fail(kp + "/" + std::to_string(i), "must be a number, got " + got((*v)[i]));
}

void indices(const Json& o, const std::string& p, const char* key) {
  const Json* v = member(o, key);
  if (v == nullptr) return;
  const std::string kp = key_pointer(p, key);
  if (!v->is_array()) fail(kp, "must be an array of indices, got " + got(*v));
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (!is_integer((*v)[i]) || (*v)[i].get<double>() < 0)
      fail(kp + "/" + std::to_string(i), "must be an index (an integer >= 0), got " + got((*v)[i]));
    if ((*v)[i].get<double>() > static_cast<double>(kIntMax))
      fail(kp + "/" + std::to_string(i), "must be at most " + std::to_string(kIntMax) + ", got " + got((*v)[i]));
  }
}

void one_of(const Json& o, const std::string& p, const char* key, std::initializer_list<long long> values,
            bool needed = false) {
  const Json* v = needed ? &required(o, p, key) : member(o, key);
  if (v == nullptr) return;
  if (is_integer(*v))
    for (const long long x : values)
      if (v->get<double>() == static_cast<double>(x)) return;
  std::string list;
  for (const long long x : values) list += (list.empty() ? "" : ", ") + std::to_string(x);
  fail(key_pointer(p, key), "must be one of " + list + ", got " + got(*v));
}

void one_of(const Json& o, const std::string& p, const char* key, std::initializer_list<const char*> values,
            bool needed = false) {
  const Json* v = needed ? &required(o, p, key) : member(o, key);
  if (v == nullptr) return;
  if (v->is_string())
    for (const char* x : values)
      if (v->get<std::string>() == x) return;
  std::string list;
  for (const char* x : values) list += (list.empty() ? "" : ", ") + std::string(x);
  fail(key_pointer(p, key), "must be one of " + list + ", got " + got(*v));
}

// A "uri" that is a data URI (RFC 2397) must carry base64 data (glTF 2.0 §3.9.1): the
// characters A–Z, a–z, 0–9, + and /, then at most two '=' at the end. tinygltf said only
// "Failed to decode 'uri'".
void data_uri(const Json& o, const std::string& p) {
  const Json* v = member(o, "uri");
  if (v == nullptr || !v->is_string()) return;
  const std::string& uri = v->get_ref<const std::string&>();
  if (uri.rfind("data:", 0) != 0) return;
  const std::size_t comma = uri.find(',');
  const std::string head = uri.substr(0, comma);
  if (comma == std::string::npos || head.size() < 7 || head.compare(head.size() - 7, 7, ";base64") != 0)
    fail(p + "/uri", "a data URI must be base64 (\"data:<type>;base64,<data>\")");
  std::size_t pad = 0;
  for (std::size_t i = comma + 1; i < uri.size(); ++i) {
    const char ch = uri[i];
    const bool base64 = (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '+' || ch == '/';
    if (ch == '=' && ++pad <= 2) continue;
    if (!base64 || pad > 0)
      fail(p + "/uri", "the data URI's base64 data has a character that is not base64 at byte " + std::to_string(i) +
                           " of the URI");
  }
}

// A textureInfo (§5.22), a normalTextureInfo or an occlusionTextureInfo.
void texture_info(const Json& o, const std::string& p, const char* key) {
  const Json* v = member(o, key);
  if (v == nullptr) return;
  const std::string kp = key_pointer(p, key);
  object(*v, kp);
  integer(*v, kp, "index", 0, true);
  integer(*v, kp, "texCoord", 0);
  number(*v, kp, "scale");
  number(*v, kp, "strength");
}

// Each element of the top-level array `key` (when present) must be an object; `check`
// looks at each.
template <class F>
void each(const Json& root, const char* key, F check) {
  const Json* v = member(root, key);
  if (v == nullptr) return;
  const std::string p = std::string("/") + key;
  if (!v->is_array()) fail(p, "must be an array, got " + got(*v));
  for (std::size_t i = 0; i < v->size(); ++i) {
    const std::string ep = p + "/" + std::to_string(i);
    object((*v)[i], ep);
    check((*v)[i], ep);
  }
}

// ---- glTF 2.0's MUST rules beyond the schema's types ---------------------------------

// The number of elements of the top-level array `key` (0 when absent; its type is checked
// by `each`).
std::size_t count_of(const Json& root, const char* key) {
  const Json* v = member(root, key);
  return v != nullptr && v->is_array() ? v->size() : 0;
}

// "3 nodes", "1 node".
std::string how_many(std::size_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

// "<major>.<minor>" (asset.schema.json's pattern ^[0-9]+\.[0-9]+$); the numbers saturate
// at 10^9 (only their comparison with 2 and 0 matters).
bool parse_version(const std::string& text, long long& major, long long& minor) {
  const std::size_t dot = text.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) return false;
  long long* parts[2] = {&major, &minor};
  for (int k = 0; k < 2; ++k) {
    const std::size_t from = k == 0 ? 0 : dot + 1, to = k == 0 ? dot : text.size();
    *parts[k] = 0;
    for (std::size_t i = from; i < to; ++i) {
      if (text[i] < '0' || text[i] > '9') return false;
      *parts[k] = std::min<long long>(*parts[k] * 10 + (text[i] - '0'), 1000000000);
    }
  }
  return true;
}

// glTF 2.0 §3.2 (asset): "version" is the glTF version of the file; a 2.0 reader loads any
// 2.x file (ignoring what it does not know) and no other major version; "minVersion", when
// present, is the least version a reader must implement (not above "version"): above 2.0,
// this reader (which implements 2.0) must refuse it. The Khronos Asset Generator's
// Compatibility set: version 2.1 loads, minVersion 2.1 does not.
void check_version(const Json& asset) {
  long long major = 0, minor = 0;
  const std::string version = asset["version"].get<std::string>();
  if (!parse_version(version, major, minor))
    fail("/asset/version", "must be \"<major>.<minor>\" (such as \"2.0\"), got " + got(asset["version"]));
  if (major != 2)
    fail("/asset/version", "glTF " + version + " is not glTF 2: this reader reads glTF 2.x files only");
  const Json* min = member(asset, "minVersion");
  if (min == nullptr) return;
  if (!min->is_string()) fail("/asset/minVersion", "must be a string, got " + got(*min));
  long long min_major = 0, min_minor = 0;
  const std::string min_version = min->get<std::string>();
  if (!parse_version(min_version, min_major, min_minor))
    fail("/asset/minVersion", "must be \"<major>.<minor>\" (such as \"2.0\"), got " + got(*min));
  if (min_major > major || (min_major == major && min_minor > minor))
    fail("/asset/minVersion", min_version + " is newer than the file's version " + version);
  if (min_major != 2 || min_minor > 0)
    fail("/asset/minVersion", "the file needs a reader of glTF " + min_version + "; this one implements glTF 2.0");
}

// glTF 2.0 §5.25 (node): "matrix" and TRS exclude each other, and a matrix MUST be
// decomposable to TRS: an affine transform, whose last row (elements 3, 7, 11 and 15 of
// the column-major array) is 0, 0, 0, 1.
void check_node_transform(const Json& n, const std::string& p) {
  const Json* matrix = member(n, "matrix");
  if (matrix == nullptr) return;
  for (const char* trs : {"translation", "rotation", "scale"})
    if (member(n, trs) != nullptr)
      fail(p + "/matrix", std::string("a node with a matrix must not have ") + trs +
                              " too (glTF 2.0 §5.25: a matrix or TRS properties)");
  const Json& m = *matrix;
  if (m[3].get<double>() != 0 || m[7].get<double>() != 0 || m[11].get<double>() != 0 || m[15].get<double>() != 1)
    fail(p + "/matrix", "must be an affine transform (last row 0, 0, 0, 1: elements 3, 7, 11, 15 of the array), got " +
                            got(m[3]) + ", " + got(m[7]) + ", " + got(m[11]) + ", " + got(m[15]));
}

// glTF 2.0 §3.5.1-2: the nodes form disjoint strict trees: a node has at most one parent
// (so no array of children names a node twice), and a scene lists root nodes, each once.
// (Cycles are found while the scene is visited: scene_graph.cpp.)
void check_hierarchy(const Json& root) {
  const std::size_t nodes = count_of(root, "nodes");
  std::vector<long long> parent(nodes, -1);
  for (std::size_t i = 0; i < nodes; ++i) {
    const Json* children = member(root["nodes"][i], "children");
    if (children == nullptr) continue;
    for (std::size_t k = 0; k < children->size(); ++k) {
      const std::string cp = "/nodes/" + std::to_string(i) + "/children/" + std::to_string(k);
      const auto c = static_cast<std::size_t>((*children)[k].get<double>());
      if (c >= nodes) fail(cp, "node " + std::to_string(c) + " does not exist (" + how_many(nodes, "node") + ")");
      if (parent[c] == static_cast<long long>(i)) fail(cp, "node " + std::to_string(c) + " is listed twice");
      if (parent[c] >= 0)
        fail(cp, "node " + std::to_string(c) + " is already a child of node " + std::to_string(parent[c]) +
                     " (a node has one parent at most, glTF 2.0 §3.5.1)");
      parent[c] = static_cast<long long>(i);
    }
  }
  // A cycle: each node has one parent at most, so following parents from any node either
  // reaches a root or comes back round (each node's walk stops at one already known).
  std::vector<char> state(nodes, 0);  // 0 not seen, 1 on the current walk, 2 leads to a root
  std::vector<std::size_t> walk;
  for (std::size_t i = 0; i < nodes; ++i) {
    walk.clear();
    long long n = static_cast<long long>(i);
    while (n >= 0 && state[static_cast<std::size_t>(n)] == 0) {
      state[static_cast<std::size_t>(n)] = 1;
      walk.push_back(static_cast<std::size_t>(n));
      n = parent[static_cast<std::size_t>(n)];
    }
    if (n >= 0 && state[static_cast<std::size_t>(n)] == 1)
      fail("/nodes/" + std::to_string(n), "is its own ancestor (the node hierarchy has a cycle)");
    for (const std::size_t w : walk) state[w] = 2;
  }
  const std::size_t scenes = count_of(root, "scenes");
  for (std::size_t s = 0; s < scenes; ++s) {
    const Json* list = member(root["scenes"][s], "nodes");
    if (list == nullptr) continue;
    std::vector<bool> listed(nodes, false);
    for (std::size_t k = 0; k < list->size(); ++k) {
      const std::string np = "/scenes/" + std::to_string(s) + "/nodes/" + std::to_string(k);
      const auto n = static_cast<std::size_t>((*list)[k].get<double>());
      if (n >= nodes) fail(np, "node " + std::to_string(n) + " does not exist (" + how_many(nodes, "node") + ")");
      if (listed[n]) fail(np, "node " + std::to_string(n) + " is listed twice");
      listed[n] = true;
      if (parent[n] >= 0)
        fail(np, "node " + std::to_string(n) + " is a child of node " + std::to_string(parent[n]) +
                     ", not a root node (glTF 2.0 §3.5.2)");
    }
  }
}

// An index property `key` of `o` (already checked to be an index) names one of `count`
// elements of the top-level array `array`.
void reference(const Json& o, const std::string& p, const char* key, std::size_t count, const char* array) {
  const Json* v = member(o, key);
  if (v == nullptr) return;
  const auto i = static_cast<std::size_t>(v->get<double>());
  if (i >= count)
    fail(key_pointer(p, key), std::string(array) + " " + std::to_string(i) + " does not exist (" + how_many(count, array) + ")");
}

// glTF 2.0 §3.7.3.1 / §3.8 (vertex attributes): the component types an attribute may
// have; KHR_mesh_quantization (when used) adds the integer types it lists. UNSIGNED_INT is
// never a vertex attribute's type.
void check_attribute_types(const Json& root, const Json& attributes, const std::string& ap, bool quantized) {
  enum : int { B = 5120, UB = 5121, S = 5122, US = 5123, F = 5126 };
  struct Rule {
    const char* prefix;
    std::initializer_list<int> any;         // allowed normalized or not
    std::initializer_list<int> normalized;  // allowed when normalized
  };
  static const Rule kCore[] = {{"POSITION", {F}, {}},       {"NORMAL", {F}, {}},          {"TANGENT", {F}, {}},
                               {"TEXCOORD_", {F}, {UB, US}}, {"COLOR_", {F}, {UB, US}}};
  static const Rule kQuantized[] = {{"POSITION", {F, B, UB, S, US}, {}}, {"NORMAL", {F}, {B, S}},
                                    {"TANGENT", {F}, {B, S}},            {"TEXCOORD_", {F, B, UB, S, US}, {}},
                                    {"COLOR_", {F}, {UB, US}}};
  const std::size_t accessors = count_of(root, "accessors");
  for (auto it = attributes.begin(); it != attributes.end(); ++it) {
    const auto a = static_cast<std::size_t>(it.value().get<double>());
    const std::string p = ap + "/" + json_reader::escape_token(it.key());
    if (a >= accessors)
      fail(p, "accessor " + std::to_string(a) + " does not exist");  // (the loader's words, which callers match)
    for (const Rule& r : quantized ? std::span<const Rule>(kQuantized) : std::span<const Rule>(kCore)) {
      const std::string prefix = r.prefix;
      if (prefix.back() == '_' ? it.key().rfind(prefix, 0) != 0 : it.key() != prefix) continue;
      const Json& accessor = root["accessors"][a];
      const int type = static_cast<int>(accessor["componentType"].get<double>());
      const Json* n = member(accessor, "normalized");
      const bool normalized = n != nullptr && n->get<bool>();
      bool ok = std::find(r.any.begin(), r.any.end(), type) != r.any.end() ||
                (normalized && std::find(r.normalized.begin(), r.normalized.end(), type) != r.normalized.end());
      if (!ok)
        fail("/accessors/" + std::to_string(a) + "/componentType",
             "component type " + std::to_string(type) + (normalized ? " (normalized)" : "") + " is not allowed for " +
                 it.key() + " (" + p + ")" +
                 (quantized ? " even with KHR_mesh_quantization"
                            : ": integer attributes need KHR_mesh_quantization in extensionsUsed"));
    }
  }
}

// Every integer inside an "extensions" object, at any depth: tinygltf 2.7 holds them in
// its Value as an int (read modulo 2^32: an EXT_meshopt_compression byteOffset of 2^33
// became 0), so one beyond int is refused here, where it is still exact. `extras` are not
// read by softpbr and not walked.
void check_extension_integers(const Json& v, const std::string& p, bool inside) {
  if (v.is_object()) {
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (it.key() == "extras") continue;
      if (!inside && it.key() != "extensions" && !it.value().is_structured()) continue;
      check_extension_integers(it.value(), p + "/" + json_reader::escape_token(it.key()),
                               inside || it.key() == "extensions");
    }
  } else if (v.is_array()) {
    for (std::size_t i = 0; i < v.size(); ++i)
      if (inside || v[i].is_structured()) check_extension_integers(v[i], p + "/" + std::to_string(i), inside);
  } else if (inside && (v.is_number_integer() || v.is_number_unsigned())) {
    const double x = v.get<double>();
    if (x > static_cast<double>(kIntMax) || x < -static_cast<double>(kIntMax) - 1)
      fail(p, "is beyond the integers an extension's values may hold here (-2147483648 … 2147483647), got " + got(v));
  }
}

// The extensions' references softpbr follows, as integers in range: a node's
// KHR_lights_punctual light, a primitive's Draco bufferView and attribute ids, a
// bufferView's EXT_meshopt_compression buffer, a texture's KHR_texture_basisu,
// EXT_texture_webp or EXT_texture_avif image.
// The object `name` of an element's `extensions`, or null when there is none.
const Json* extension(const Json& element, const char* name) {
  const Json* e = member(element, "extensions");
  if (e == nullptr || !e->is_object()) return nullptr;
  const Json* x = member(*e, name);
  return x != nullptr && x->is_object() ? x : nullptr;
}

void check_extension_references(const Json& root) {
  const Json* ext = member(root, "extensions");
  std::size_t lights = 0;
  if (ext != nullptr && ext->is_object())
    if (const Json* punctual = member(*ext, "KHR_lights_punctual"); punctual != nullptr && punctual->is_object())
      if (const Json* l = member(*punctual, "lights"); l != nullptr && l->is_array()) lights = l->size();
  for (std::size_t i = 0; i < count_of(root, "nodes"); ++i) {
    const Json* light = extension(root["nodes"][i], "KHR_lights_punctual");
    if (light == nullptr) continue;
    const std::string p = "/nodes/" + std::to_string(i) + "/extensions/KHR_lights_punctual";
    integer(*light, p, "light", 0, true);
    reference(*light, p, "light", lights, "light");
  }
  for (std::size_t m = 0; m < count_of(root, "meshes"); ++m) {
    const Json& primitives = root["meshes"][m]["primitives"];
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      const Json* draco = extension(primitives[k], "KHR_draco_mesh_compression");
      if (draco == nullptr) continue;
      const std::string p = "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k) +
                            "/extensions/KHR_draco_mesh_compression";
      integer(*draco, p, "bufferView", 0, true);
      reference(*draco, p, "bufferView", count_of(root, "bufferViews"), "bufferView");
      const Json& attributes = required(*draco, p, "attributes");
      object(attributes, p + "/attributes");
      for (auto it = attributes.begin(); it != attributes.end(); ++it)
        if (!is_integer(it.value()) || it.value().get<double>() < 0 || it.value().get<double>() > kIntMax)
          fail(p + "/attributes/" + json_reader::escape_token(it.key()),
               "must be a Draco attribute id (an integer in 0 … " + std::to_string(kIntMax) + "), got " + got(it.value()));
    }
  }
  for (std::size_t t = 0; t < count_of(root, "textures"); ++t)
    for (const char* name : {"KHR_texture_basisu", "EXT_texture_webp", "EXT_texture_avif"}) {
      const Json* source = extension(root["textures"][t], name);
      if (source == nullptr) continue;
      const std::string p = "/textures/" + std::to_string(t) + "/extensions/" + name;
      integer(*source, p, "source", 0, true);
      reference(*source, p, "source", count_of(root, "images"), "image");
    }
  // KHR_materials_variants: the root's variants (objects with a name), and each
  // primitive's mappings of variants to a material.
  std::size_t variants = 0;
  if (const Json* kv = extension(root, "KHR_materials_variants")) {
    const std::string p = "/extensions/KHR_materials_variants";
    const Json& list = required(*kv, p, "variants");
    if (!list.is_array()) fail(p + "/variants", "must be an array of variants, got " + got(list));
    for (std::size_t i = 0; i < list.size(); ++i) {
      object(list[i], p + "/variants/" + std::to_string(i));
      string(list[i], p + "/variants/" + std::to_string(i), "name", true);
    }
    variants = list.size();
  }
  for (std::size_t m = 0; m < count_of(root, "meshes"); ++m) {
    const Json& primitives = root["meshes"][m]["primitives"];
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      const Json* kv = extension(primitives[k], "KHR_materials_variants");
      if (kv == nullptr) continue;
      const std::string p = "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k) +
                            "/extensions/KHR_materials_variants";
      const Json& mappings = required(*kv, p, "mappings");
      if (!mappings.is_array()) fail(p + "/mappings", "must be an array of mappings, got " + got(mappings));
      for (std::size_t i = 0; i < mappings.size(); ++i) {
        const std::string mp = p + "/mappings/" + std::to_string(i);
        object(mappings[i], mp);
        integer(mappings[i], mp, "material", 0, true);
        reference(mappings[i], mp, "material", count_of(root, "materials"), "material");
        const Json& used = required(mappings[i], mp, "variants");
        if (!used.is_array()) fail(mp + "/variants", "must be an array of variant indices, got " + got(used));
        for (std::size_t j = 0; j < used.size(); ++j) {
          const std::string vp = mp + "/variants/" + std::to_string(j);
          if (!is_integer(used[j]) || used[j].get<double>() < 0) fail(vp, "must be an index (an integer >= 0), got " + got(used[j]));
          if (used[j].get<double>() >= static_cast<double>(variants))
            fail(vp, "variant " + got(used[j]) + " does not exist (" + how_many(variants, "variant") + " in /extensions/KHR_materials_variants)");
        }
      }
    }
  }
  for (std::size_t v = 0; v < count_of(root, "bufferViews"); ++v) {
    const Json* meshopt = extension(root["bufferViews"][v], "EXT_meshopt_compression");
    if (meshopt == nullptr) continue;
    const std::string p = "/bufferViews/" + std::to_string(v) + "/extensions/EXT_meshopt_compression";
    integer(*meshopt, p, "buffer", 0, true);
    reference(*meshopt, p, "buffer", count_of(root, "buffers"), "buffer");
    integer(*meshopt, p, "byteOffset", 0);
    integer(*meshopt, p, "byteLength", 0, true);
    integer(*meshopt, p, "byteStride", 0, true);
    integer(*meshopt, p, "count", 0, true);
  }
}

// Skins (§5.28) and animations (§5.4-5.7): every index they hold names something that
// exists (a node's skin, a joint, inverseBindMatrices, skeleton, a channel's sampler and
// target node, a sampler's input and output accessors).
void check_skins_and_animations(const Json& root) {
  const std::size_t nodes = count_of(root, "nodes"), accessors = count_of(root, "accessors");
  for (std::size_t i = 0; i < nodes; ++i)
    reference(root["nodes"][i], "/nodes/" + std::to_string(i), "skin", count_of(root, "skins"), "skin");
  for (std::size_t s = 0; s < count_of(root, "skins"); ++s) {
    const Json& skin = root["skins"][s];
    const std::string p = "/skins/" + std::to_string(s);
    const Json& joints = required(skin, p, "joints");
    if (joints.empty()) fail(p + "/joints", "must list at least one joint");
    for (std::size_t k = 0; k < joints.size(); ++k)
      if (static_cast<std::size_t>(joints[k].get<double>()) >= nodes)
        fail(p + "/joints/" + std::to_string(k), "node " + got(joints[k]) + " does not exist (" + how_many(nodes, "node") + ")");
    reference(skin, p, "inverseBindMatrices", accessors, "accessor");
    reference(skin, p, "skeleton", nodes, "node");
  }
  for (std::size_t a = 0; a < count_of(root, "animations"); ++a) {
    const Json& animation = root["animations"][a];
    const std::string p = "/animations/" + std::to_string(a);
    const std::size_t samplers = [&] {
      const Json& list = required(animation, p, "samplers");
      if (!list.is_array()) fail(p + "/samplers", "must be an array, got " + got(list));
      for (std::size_t k = 0; k < list.size(); ++k) {
        const std::string sp = p + "/samplers/" + std::to_string(k);
        object(list[k], sp);
        for (const char* key : {"input", "output"}) {
          integer(list[k], sp, key, 0, true);
          reference(list[k], sp, key, accessors, "accessor");
        }
        string(list[k], sp, "interpolation");
      }
      return list.size();
    }();
    const Json& channels = required(animation, p, "channels");
    if (!channels.is_array() || channels.empty())
      fail(p + "/channels", "must be an array of at least one channel, got " + got(channels));
    for (std::size_t k = 0; k < channels.size(); ++k) {
      const std::string cp = p + "/channels/" + std::to_string(k);
      object(channels[k], cp);
      integer(channels[k], cp, "sampler", 0, true);
      if (static_cast<std::size_t>(channels[k]["sampler"].get<double>()) >= samplers)
        fail(cp + "/sampler", "sampler " + got(channels[k]["sampler"]) + " does not exist (" + how_many(samplers, "sampler") +
                                  " in " + p + ")");
      const Json& target = required(channels[k], cp, "target");
      object(target, cp + "/target");
      integer(target, cp + "/target", "node", 0);
      reference(target, cp + "/target", "node", nodes, "node");
      string(target, cp + "/target", "path", true);
    }
  }
}

void check(const Json& root) {
  const Json& asset = required(root, "", "asset");
  object(asset, "/asset");
  string(asset, "/asset", "version", true);
  check_version(asset);
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    const Json* v = member(root, key);
    if (v == nullptr) continue;
    const std::string p = std::string("/") + key;
    if (!v->is_array()) fail(p, "must be an array of strings, got " + got(*v));
    for (std::size_t i = 0; i < v->size(); ++i)
      if (!(*v)[i].is_string()) fail(p + "/" + std::to_string(i), "must be a string, got " + got((*v)[i]));
  }
  integer(root, "", "scene", 0);
  each(root, "buffers", [](const Json& b, const std::string& p) {
    integer(b, p, "byteLength", 1, true, kSizeMax);
    string(b, p, "uri");
    data_uri(b, p);
  });
  each(root, "bufferViews", [](const Json& v, const std::string& p) {
    integer(v, p, "buffer", 0, true);
    integer(v, p, "byteLength", 1, true, kSizeMax);
    integer(v, p, "byteOffset", 0, false, kSizeMax);
    integer(v, p, "byteStride", 4);
    integer(v, p, "target", 0);
  });
  each(root, "accessors", [](const Json& a, const std::string& p) {
    integer(a, p, "bufferView", 0);
    integer(a, p, "byteOffset", 0, false, kSizeMax);
    one_of(a, p, "componentType", {5120, 5121, 5122, 5123, 5125, 5126}, true);
    boolean(a, p, "normalized");
    // glTF 2.0 §5.1.4: "normalized MUST NOT be set to true for accessors with FLOAT or
    // UNSIGNED_INT component type".
    if (const Json* n = member(a, "normalized"); n != nullptr && n->is_boolean() && n->get<bool>()) {
      const double type = a["componentType"].get<double>();
      if (type == 5126 || type == 5125)
        fail(p + "/normalized", std::string("must not be true for ") + (type == 5126 ? "FLOAT" : "UNSIGNED_INT") +
                                    " components (glTF 2.0 §5.1.4)");
    }
    // softpbr reads at most kMaxElements (reader.h: 2^28) elements from one accessor.
    integer(a, p, "count", 1, true, kMaxAccessorCount);
    one_of(a, p, "type", {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"}, true);
    numbers(a, p, "min", 0);
    numbers(a, p, "max", 0);
    if (const Json* s = member(a, "sparse")) {
      const std::string sp = p + "/sparse";
      object(*s, sp);
      integer(*s, sp, "count", 1, true, kMaxAccessorCount);
      for (const char* part : {"indices", "values"}) {
        const Json& q = required(*s, sp, part);
        const std::string qp = sp + "/" + part;
        object(q, qp);
        integer(q, qp, "bufferView", 0, true);
        integer(q, qp, "byteOffset", 0);
      }
      one_of(required(*s, sp, "indices"), sp + "/indices", "componentType", {5121, 5123, 5125}, true);
    }
  });
  each(root, "images", [](const Json& im, const std::string& p) {
    string(im, p, "uri");
    data_uri(im, p);
    integer(im, p, "bufferView", 0);
    string(im, p, "mimeType");
  });
  each(root, "samplers", [](const Json& s, const std::string& p) {
    one_of(s, p, "magFilter", {9728, 9729});
    one_of(s, p, "minFilter", {9728, 9729, 9984, 9985, 9986, 9987});
    one_of(s, p, "wrapS", {33071, 33648, 10497});
    one_of(s, p, "wrapT", {33071, 33648, 10497});
  });
  each(root, "textures", [](const Json& t, const std::string& p) {
    integer(t, p, "source", 0);
    integer(t, p, "sampler", 0);
  });
  each(root, "materials", [](const Json& m, const std::string& p) {
    if (const Json* pbr = member(m, "pbrMetallicRoughness")) {
      const std::string pp = p + "/pbrMetallicRoughness";
      object(*pbr, pp);
      numbers(*pbr, pp, "baseColorFactor", 4);
      texture_info(*pbr, pp, "baseColorTexture");
      number(*pbr, pp, "metallicFactor");
      number(*pbr, pp, "roughnessFactor");
      texture_info(*pbr, pp, "metallicRoughnessTexture");
    }
    texture_info(m, p, "normalTexture");
    texture_info(m, p, "occlusionTexture");
    texture_info(m, p, "emissiveTexture");
    numbers(m, p, "emissiveFactor", 3);
    one_of(m, p, "alphaMode", {"OPAQUE", "MASK", "BLEND"});
    number(m, p, "alphaCutoff");
    boolean(m, p, "doubleSided");
  });
  each(root, "meshes", [](const Json& mesh, const std::string& p) {
    const Json& primitives = required(mesh, p, "primitives");
    const std::string pp = p + "/primitives";
    if (!primitives.is_array() || primitives.empty())
      fail(pp, "must be an array of at least one primitive, got " + got(primitives));
    for (std::size_t k = 0; k < primitives.size(); ++k) {
      const Json& prim = primitives[k];
      const std::string kp = pp + "/" + std::to_string(k);
      object(prim, kp);
      const Json& attributes = required(prim, kp, "attributes");
      object(attributes, kp + "/attributes");
      for (auto it = attributes.begin(); it != attributes.end(); ++it) {
        const std::string ap = kp + "/attributes/" + json_reader::escape_token(it.key());
        if (!is_integer(it.value()) || it.value().get<double>() < 0)
          fail(ap, "must be an accessor index (an integer >= 0), got " + got(it.value()));
        if (it.value().get<double>() > kIntMax)
          fail(ap, "must be at most " + std::to_string(kIntMax) + ", got " + got(it.value()));
      }
      integer(prim, kp, "indices", 0);
      integer(prim, kp, "material", 0);
      one_of(prim, kp, "mode", {0, 1, 2, 3, 4, 5, 6});
    }
    numbers(mesh, p, "weights", 0);
  });
  each(root, "nodes", [](const Json& n, const std::string& p) {
    indices(n, p, "children");
    integer(n, p, "mesh", 0);
    integer(n, p, "camera", 0);
    integer(n, p, "skin", 0);
    numbers(n, p, "matrix", 16);
    numbers(n, p, "translation", 3);
    numbers(n, p, "rotation", 4);
    numbers(n, p, "scale", 3);
    numbers(n, p, "weights", 0);
    check_node_transform(n, p);
  });
  each(root, "scenes", [](const Json& s, const std::string& p) { indices(s, p, "nodes"); });
  each(root, "cameras", [](const Json& c, const std::string& p) {
    one_of(c, p, "type", {"perspective", "orthographic"}, true);
    const std::string type = c["type"].get<std::string>();
    const Json& projection = required(c, p, type.c_str());
    const std::string tp = p + "/" + type;
    object(projection, tp);
    static constexpr const char* kPerspective[] = {"yfov", "znear"};
    static constexpr const char* kOrthographic[] = {"xmag", "ymag", "zfar", "znear"};
    const std::span<const char* const> keys =
        type == "perspective" ? std::span<const char* const>(kPerspective) : std::span<const char* const>(kOrthographic);
    for (const char* key : keys) {
      required(projection, tp, key);
      number(projection, tp, key);
    }
    number(projection, tp, "aspectRatio");
    number(projection, tp, "zfar");
  });
  each(root, "skins", [](const Json& s, const std::string& p) {
    integer(s, p, "inverseBindMatrices", 0);
    integer(s, p, "skeleton", 0);
    indices(s, p, "joints");
  });
  each(root, "animations", [](const Json&, const std::string&) {});
  // The rules across properties, now that each property's type is known.
  check_hierarchy(root);
  const bool quantized = [&] {
    const Json* used = member(root, "extensionsUsed");
    return used != nullptr && std::find(used->begin(), used->end(), "KHR_mesh_quantization") != used->end();
  }();
  for (std::size_t m = 0; m < count_of(root, "meshes"); ++m) {
    const Json& primitives = root["meshes"][m]["primitives"];
    for (std::size_t k = 0; k < primitives.size(); ++k)
      check_attribute_types(root, primitives[k]["attributes"],
                            "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k) + "/attributes", quantized);
  }
  check_skins_and_animations(root);
  check_extension_references(root);
  check_extension_integers(root, "", false);
}

}  // namespace

std::optional<std::string> check_schema(const Json& root) {
  if (root.is_discarded() || !root.is_object()) return std::nullopt;
  try {
    check(root);
  } catch (const Found& f) {
    return f.text;
  }
  return std::nullopt;
}

}  // namespace softpbr::pbr::gltf
