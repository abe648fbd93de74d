// EXT_meshopt_compression (see meshopt.h): meshoptimizer's lossless byte codecs (Debian's
// libmeshoptimizer) for the attribute and index streams, softpbr's filters after them.
#include "gltf/meshopt.h"

#include "gltf/draco.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

namespace softpbr::pbr::gltf {

namespace tg = tinygltf;

namespace {

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

void put_le32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// A filter's output component: round(v) (halves away from zero) within [−max, max]; NaN
// (only from invalid input, which the specification leaves unspecified) gives 0.
template <class T>
T to_snorm(float v, float max) {
  if (!(v == v)) return 0;
  return static_cast<T>(std::round(std::clamp(v, -max, max)));
}

template <class T>
void octahedral(std::uint8_t* data, std::size_t count, std::size_t stride) {
  constexpr float kMax = static_cast<float>(std::numeric_limits<T>::max());
  for (std::size_t i = 0; i < count; ++i) {
    T e[4];
    std::memcpy(e, data + i * stride, sizeof e);
    // e[2] encodes 1.0 in the element's K bits.
    const float one = static_cast<float>(e[2]);
    float x = static_cast<float>(e[0]) / one;
    float y = static_cast<float>(e[1]) / one;
    const float z = 1.0f - std::fabs(x) - std::fabs(y);
    // The negative hemisphere folded back.
    const float t = std::min(z, 0.0f);
    x -= std::copysign(t, x);
    y -= std::copysign(t, y);
    const float len = std::sqrt(x * x + y * y + z * z);
    e[0] = to_snorm<T>(x / len * kMax, kMax);
    e[1] = to_snorm<T>(y / len * kMax, kMax);
    e[2] = to_snorm<T>(z / len * kMax, kMax);
    std::memcpy(data + i * stride, e, sizeof e);
  }
}

}  // namespace

std::span<const std::uint8_t> prepare_for_tinygltf(std::span<const std::uint8_t> bytes, std::vector<std::uint8_t>& storage,
                                                   std::map<int, std::uint64_t>& declared,
                                                   std::map<std::pair<std::size_t, std::size_t>, int>& draco_indices) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (text.find(kMeshopt) == std::string_view::npos && text.find(kDraco) == std::string_view::npos) return bytes;
  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const std::string_view json = json_text(bytes);
  if (glb && json.empty()) return bytes;
  const std::size_t json_end = glb ? 20 + json.size() : bytes.size();
  nlohmann::json doc = nlohmann::json::parse(json, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return bytes;
  const auto used = doc.find("extensionsUsed");
  if (used == doc.end() || !used->is_array()) return bytes;
  const bool meshopt = std::find(used->begin(), used->end(), kMeshopt) != used->end();
  const bool draco = std::find(used->begin(), used->end(), kDraco) != used->end();
  bool changed = false;
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
        p.erase("indices");
        changed = true;
      }
    }
  const auto buffers = doc.find("buffers");
  if (!meshopt || buffers == doc.end() || !buffers->is_array()) {
    if (!changed) return bytes;
  } else {
    for (std::size_t i = 0; i < buffers->size() && i <= static_cast<std::size_t>(INT_MAX); ++i) {
      nlohmann::json& b = (*buffers)[i];
      if (!b.is_object() || b.contains("uri") || (glb && i == 0)) continue;
      const auto length = b.find("byteLength");
      if (length == b.end() || !length->is_number_integer() || length->get<std::int64_t>() < 1) continue;
      declared[static_cast<int>(i)] = length->get<std::uint64_t>();
      b = nlohmann::json{{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
      changed = true;
    }
  }
  if (!changed) return bytes;
  std::string out = doc.dump();
  if (!glb) {
    storage.assign(out.begin(), out.end());
    return storage;
  }
  while (out.size() % 4 != 0) out.push_back(' ');
  const std::size_t rest = bytes.size() - json_end;
  if (out.size() > UINT32_MAX - 20 - rest) return bytes;
  storage.resize(20 + out.size() + rest);
  std::memcpy(storage.data(), bytes.data(), 12);  // magic and version
  put_le32(storage.data() + 8, static_cast<std::uint32_t>(storage.size()));
  put_le32(storage.data() + 12, static_cast<std::uint32_t>(out.size()));
  put_le32(storage.data() + 16, 0x4E4F534Au);
  std::memcpy(storage.data() + 20, out.data(), out.size());
  if (rest > 0) std::memcpy(storage.data() + 20 + out.size(), bytes.data() + json_end, rest);
  return storage;
}

namespace {

}  // namespace

std::string_view json_text(std::span<const std::uint8_t> bytes) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  if (!(bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0)) return text;
  if (bytes.size() < 20) return {};
  const std::uint32_t length = le32(bytes.data() + 12);
  if (le32(bytes.data() + 16) != 0x4E4F534Au || length > bytes.size() - 20) return {};
  return text.substr(20, length);
}

std::string tinygltf_error_with_pointer(std::span<const std::uint8_t> bytes, const std::string& err) {
  const bool indices_range = err.rfind("primitive indices accessor out of bounds", 0) == 0;
  const bool indices_view = err.rfind("accessor[", 0) == 0 && err.find("] invalid bufferView") != std::string::npos;
  const bool stride = err.rfind("Invalid `byteStride' value.", 0) == 0;
  const bool missing = err.rfind("File not found : ", 0) == 0;
  if (!indices_range && !indices_view && !stride && !missing) return {};
  const nlohmann::json doc = nlohmann::json::parse(json_text(bytes), nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return {};
  auto array = [&](const char* key) -> const nlohmann::json* {
    const auto it = doc.find(key);
    return it != doc.end() && it->is_array() ? &*it : nullptr;
  };
  const nlohmann::json* accessors = array("accessors");
  const nlohmann::json* views = array("bufferViews");
  const std::size_t accessor_count = accessors != nullptr ? accessors->size() : 0;
  const std::size_t view_count = views != nullptr ? views->size() : 0;
  if (missing) {
    // tinygltf looks for a buffer's file before reading it: the buffer whose uri it is.
    std::string uri = err.substr(17);
    if (const std::size_t nl = uri.find('\n'); nl != std::string::npos) uri.resize(nl);
    const nlohmann::json* buffers = array("buffers");
    for (std::size_t b = 0; buffers != nullptr && b < buffers->size(); ++b) {
      const nlohmann::json& buffer = (*buffers)[b];
      if (buffer.is_object() && buffer.contains("uri") && buffer["uri"].is_string() && buffer["uri"].get<std::string>() == uri)
        return "/buffers/" + std::to_string(b) + "/uri: " + uri + ": no such file";
    }
    return {};
  }
  if (stride) {
    for (std::size_t v = 0; v < view_count; ++v) {
      const nlohmann::json& view = (*views)[v];
      if (!view.is_object() || !view.contains("byteStride") || !view["byteStride"].is_number_integer()) continue;
      const auto s = view["byteStride"].get<std::int64_t>();
      if (s > 252 || s % 4 != 0 || (s != 0 && s < 4))
        return "/bufferViews/" + std::to_string(v) + "/byteStride: must be a multiple of 4 in [4, 252], got " +
               std::to_string(s);
    }
    return {};
  }
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
      const std::string pointer = "/meshes/" + std::to_string(m) + "/primitives/" + std::to_string(k) + "/indices";
      if (static_cast<std::uint64_t>(a) >= accessor_count) {
        if (indices_range) return pointer + ": accessor " + std::to_string(a) + " does not exist";
        continue;
      }
      if (!indices_view) continue;
      const nlohmann::json& accessor = (*accessors)[static_cast<std::size_t>(a)];
      const std::string ap = "/accessors/" + std::to_string(a);
      if (!accessor.is_object() || !accessor.contains("bufferView"))
        return ap + ": has no bufferView, which indices need (" + pointer + ")";
      const nlohmann::json& view = accessor["bufferView"];
      if (!view.is_number_integer() || view.get<std::int64_t>() < 0 ||
          static_cast<std::uint64_t>(view.get<std::int64_t>()) >= view_count)
        return ap + "/bufferView: bufferView " + view.dump() + " does not exist";
    }
  }
  return {};
}

void filter_octahedral(std::uint8_t* data, std::size_t count, std::size_t stride) {
  if (stride == 4) octahedral<std::int8_t>(data, count, stride);
  else octahedral<std::int16_t>(data, count, stride);
}

void filter_quaternion(std::uint8_t* data, std::size_t count) {
  // 1/√2 in float: the components are stored scaled by √2.
  const float range = 0.70710678118654752f;
  for (std::size_t i = 0; i < count; ++i) {
    std::int16_t e[4];
    std::memcpy(e, data + i * 8, sizeof e);
    // e[3] encodes 1.0 in the element's K bits, but for its two low bits: the index of the
    // largest component, left out of the encoding (and positive).
    const float one = static_cast<float>(e[3] | 3);
    const float x = static_cast<float>(e[0]) / one * range;
    const float y = static_cast<float>(e[1]) / one * range;
    const float z = static_cast<float>(e[2]) / one * range;
    const float w = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y - z * z));
    const int largest = e[3] & 3;
    std::int16_t out[4];
    out[(largest + 1) % 4] = to_snorm<std::int16_t>(x * 32767.0f, 32767.0f);
    out[(largest + 2) % 4] = to_snorm<std::int16_t>(y * 32767.0f, 32767.0f);
    out[(largest + 3) % 4] = to_snorm<std::int16_t>(z * 32767.0f, 32767.0f);
    out[largest] = to_snorm<std::int16_t>(w * 32767.0f, 32767.0f);
    std::memcpy(data + i * 8, out, sizeof out);
  }
}

void filter_exponential(std::uint8_t* data, std::size_t count, std::size_t stride) {
  const std::size_t words = count * (stride / 4);
  for (std::size_t i = 0; i < words; ++i) {
    std::uint32_t u;
    std::memcpy(&u, data + i * 4, 4);
    // 8 bits of signed exponent, 24 of signed mantissa: 2^e · m, exact in float for the
    // valid exponents [−100, 100] (ldexp is IEEE scaleB, correctly rounded beyond them).
    const int e = static_cast<std::int32_t>(u) >> 24;
    const std::int32_t m = static_cast<std::int32_t>(u << 8) >> 8;
    const float f = std::ldexp(static_cast<float>(m), e);
    std::memcpy(data + i * 4, &f, 4);
  }
}

void decode_meshopt_views(const tg::Model& model, const std::map<int, std::uint64_t>& fallback, std::uint64_t max_bytes,
                          std::map<int, std::vector<std::uint8_t>>& decoded,
                          const std::function<void(const std::string&, const std::string&)>& fail_at) {
  auto fail = [&](const std::string& pointer, const std::string& what) {
    fail_at(pointer, what);
    throw std::logic_error("fail_at returned");  // (it throws)
  };
  std::uint64_t total = 0;
  for (std::size_t v = 0; v < model.bufferViews.size(); ++v) {
    const tg::BufferView& view = model.bufferViews[v];
    const auto it = view.extensions.find(kMeshopt);
    if (it == view.extensions.end()) continue;
    const std::string p = "/bufferViews/" + std::to_string(v) + "/extensions/" + kMeshopt;
    const tg::Value& x = it->second;
    if (!x.IsObject()) fail(p, "must be an object");
    constexpr double kMaxInteger = 9007199254740992.0;  // 2^53
    auto integer = [&](const char* key, bool required, double fallback_value) -> std::uint64_t {
      if (!x.Has(key)) {
        if (required) fail(p, std::string("has no ") + key + " (required)");
        return static_cast<std::uint64_t>(fallback_value);
      }
      const tg::Value& n = x.Get(key);
      const double d = n.IsNumber() ? n.GetNumberAsDouble() : -1.0;
      if (!(d >= 0.0 && d <= kMaxInteger) || d != std::floor(d)) fail(p + "/" + key, "must be an integer ≥ 0");
      return static_cast<std::uint64_t>(d);
    };
    auto word = [&](const char* key, const char* fallback_value) -> std::string {
      if (!x.Has(key)) {
        if (fallback_value == nullptr) fail(p, std::string("has no ") + key + " (required)");
        return fallback_value;
      }
      const tg::Value& s = x.Get(key);
      if (!s.IsString()) fail(p + "/" + key, "must be a string");
      return s.Get<std::string>();
    };
    const std::uint64_t buffer = integer("buffer", true, 0);
    if (buffer >= model.buffers.size())
      fail(p + "/buffer", "buffer " + std::to_string(buffer) + " does not exist");
    if (fallback.count(static_cast<int>(buffer)) != 0)
      fail(p + "/buffer", "buffer " + std::to_string(buffer) + " has no data (it has no uri): compressed data must be in a buffer that has");
    const std::uint64_t offset = integer("byteOffset", false, 0);
    const std::uint64_t length = integer("byteLength", true, 0);
    const std::vector<unsigned char>& data = model.buffers[buffer].data;
    if (offset > data.size() || length > data.size() - offset)
      fail(p, std::to_string(length) + " bytes at offset " + std::to_string(offset) + " run past buffer " +
                  std::to_string(buffer) + " (" + std::to_string(data.size()) + " bytes)");
    const std::uint64_t stride = integer("byteStride", true, 0);
    const std::uint64_t count = integer("count", true, 0);
    const std::string mode = word("mode", nullptr);
    const std::string filter = word("filter", "NONE");
    if (mode != "ATTRIBUTES" && mode != "TRIANGLES" && mode != "INDICES")
      fail(p + "/mode", "must be ATTRIBUTES, TRIANGLES or INDICES");
    if (filter != "NONE" && filter != "OCTAHEDRAL" && filter != "QUATERNION" && filter != "EXPONENTIAL")
      fail(p + "/filter", "must be NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    if (view.byteStride != 0 && view.byteStride != stride)
      fail(p + "/byteStride", "is " + std::to_string(stride) + ", but the bufferView's byteStride is " +
                                  std::to_string(view.byteStride));
    if (count < 1) fail(p + "/count", "must be at least 1");
    if (mode == "ATTRIBUTES" && (stride < 4 || stride > 256 || stride % 4 != 0))
      fail(p + "/byteStride", "must be a multiple of 4 in [4, 256] for ATTRIBUTES, got " + std::to_string(stride));
    if (mode != "ATTRIBUTES") {
      if (stride != 2 && stride != 4)
        fail(p + "/byteStride", "must be 2 or 4 for " + mode + ", got " + std::to_string(stride));
      if (filter != "NONE") fail(p + "/filter", "must be NONE for " + mode + ", got " + filter);
    }
    if (mode == "TRIANGLES" && count % 3 != 0)
      fail(p + "/count", "must be a multiple of 3 for TRIANGLES, got " + std::to_string(count));
    if (filter == "OCTAHEDRAL" && stride != 4 && stride != 8)
      fail(p + "/byteStride", "must be 4 or 8 for the OCTAHEDRAL filter, got " + std::to_string(stride));
    if (filter == "QUATERNION" && stride != 8)
      fail(p + "/byteStride", "must be 8 for the QUATERNION filter, got " + std::to_string(stride));
    // (EXPONENTIAL's multiple of 4 is ATTRIBUTES' own rule.)
    const std::uint64_t size = stride * count;  // both below 2^53, stride ≤ 256: no overflow
    if (count > max_bytes || size != view.byteLength)
      fail(p + "/count", std::to_string(count) + " elements of " + std::to_string(stride) + " bytes are " +
                             std::to_string(size) + " bytes, but the bufferView's byteLength is " +
                             std::to_string(view.byteLength));
    total += size;
    if (total > max_bytes)
      fail(p, "decoded, the compressed bufferViews reach " + std::to_string(total) + " bytes, over the limit of " +
                  std::to_string(max_bytes));
    std::vector<std::uint8_t> out(static_cast<std::size_t>(size));
    const unsigned char* src = data.data() + offset;
    const auto n = static_cast<std::size_t>(count), s = static_cast<std::size_t>(stride),
               l = static_cast<std::size_t>(length);
    const int rc = mode == "ATTRIBUTES"  ? meshopt_decodeVertexBuffer(out.data(), n, s, src, l)
                   : mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), n, s, src, l)
                                         : meshopt_decodeIndexSequence(out.data(), n, s, src, l);
    if (rc != 0)
      fail(p, "the " + std::to_string(length) + " bytes of compressed " + mode + " data cannot be decoded (meshoptimizer: error " +
                  std::to_string(rc) + ")");
    if (filter == "OCTAHEDRAL") filter_octahedral(out.data(), n, s);
    else if (filter == "QUATERNION") filter_quaternion(out.data(), n);
    else if (filter == "EXPONENTIAL") filter_exponential(out.data(), n, s);
    decoded[static_cast<int>(v)] = std::move(out);
  }
}

}  // namespace softpbr::pbr::gltf
