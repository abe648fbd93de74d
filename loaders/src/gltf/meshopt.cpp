// EXT_meshopt_compression (see meshopt.h): meshoptimizer's lossless byte codecs (Debian's
// libmeshoptimizer) for the attribute and index streams, softpbr's filters after them.
#include "gltf/meshopt.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include <meshoptimizer.h>

namespace softpbr::pbr::gltf {

namespace tg = tinygltf;

namespace {

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
