// The glTF 2.0 schema's structural rules, before tinygltf (see schema.h).
#include "gltf/schema.h"

#include <cmath>
#include <initializer_list>
#include <span>

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

// An integer ≥ `lo` (indices: ≥ 0).
void integer(const Json& o, const std::string& p, const char* key, long long lo, bool needed = false) {
  const Json* v = needed ? &required(o, p, key) : member(o, key);
  if (v == nullptr) return;
  if (!is_integer(*v) || v->get<double>() < static_cast<double>(lo))
    fail(key_pointer(p, key), (lo == 0 ? "must be an index (an integer >= 0), got " : "must be an integer >= " +
                                                                                          std::to_string(lo) + ", got ") +
                                  got(*v));
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
  for (std::size_t i = 0; i < v->size(); ++i)
    if (!is_integer((*v)[i]) || (*v)[i].get<double>() < 0)
      fail(kp + "/" + std::to_string(i), "must be an index (an integer >= 0), got " + got((*v)[i]));
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

void check(const Json& root) {
  const Json& asset = required(root, "", "asset");
  object(asset, "/asset");
  string(asset, "/asset", "version", true);
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
    integer(b, p, "byteLength", 1, true);
    string(b, p, "uri");
    data_uri(b, p);
  });
  each(root, "bufferViews", [](const Json& v, const std::string& p) {
    integer(v, p, "buffer", 0, true);
    integer(v, p, "byteLength", 1, true);
    integer(v, p, "byteOffset", 0);
    integer(v, p, "byteStride", 4);
    integer(v, p, "target", 0);
  });
  each(root, "accessors", [](const Json& a, const std::string& p) {
    integer(a, p, "bufferView", 0);
    integer(a, p, "byteOffset", 0);
    one_of(a, p, "componentType", {5120, 5121, 5122, 5123, 5125, 5126}, true);
    boolean(a, p, "normalized");
    integer(a, p, "count", 1, true);
    one_of(a, p, "type", {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"}, true);
    numbers(a, p, "min", 0);
    numbers(a, p, "max", 0);
    if (const Json* s = member(a, "sparse")) {
      const std::string sp = p + "/sparse";
      object(*s, sp);
      integer(*s, sp, "count", 1, true);
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
      for (auto it = attributes.begin(); it != attributes.end(); ++it)
        if (!is_integer(it.value()) || it.value().get<double>() < 0)
          fail(kp + "/attributes/" + json_reader::escape_token(it.key()), "must be an accessor index (an integer >= 0), got " + got(it.value()));
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
  each(root, "skins", [](const Json& s, const std::string& p) { indices(s, p, "joints"); });
  each(root, "animations", [](const Json&, const std::string&) {});
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
