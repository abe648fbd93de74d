// glTF 2.0 loading (see gltf.h): tinygltf parses the JSON and the buffers; everything the
// renderer reads is validated here against the specification before it is used.
#include "softpbr/loaders/gltf.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <utility>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "gltf/document.h"
#include "gltf/draco.h"
#include "gltf/files.h"
#include "gltf/meshopt.h"
#include "gltf/schema.h"
#include "gltf/tinygltf.h"
#include "json_reader.h"
#include "texture_cache.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/image/load.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/texture.h"

namespace softpbr::pbr {

namespace {

namespace tg = tinygltf;

// Most elements one accessor may hold: 2^28 (a VEC4 float accessor of 4 GiB).
constexpr std::size_t kMaxElements = std::size_t{1} << 28;
// Deepest node hierarchy followed.
constexpr int kMaxDepth = 1024;

std::string str(std::size_t i) { return std::to_string(i); }
std::string number_text(double x) { return json_reader::show_number(x); }

class Loader {
 public:
  Loader(const std::string& file, const std::string& base_dir, const tg::Model& model, const GltfOptions& options,
         GltfScene& out, std::map<int, std::uint64_t> fallback,
         std::map<std::pair<std::size_t, std::size_t>, int> draco_indices)
      : file_(file),
        base_dir_(base_dir),
        m_(model),
        options_(options),
        out_(out),
        fallback_(std::move(fallback)),
        draco_indices_(std::move(draco_indices)) {}

  [[noreturn]] void fail(const std::string& pointer, const std::string& what) const {
    throw LoadError(file_ + ": " + pointer + ": " + what);
  }
  void warn(const std::string& what) { out_.warnings.push_back(file_ + ": " + what); }

  void load() {
    check_extensions();
    // EXT_meshopt_compression: every compressed view decoded before any accessor is read.
    gltf::decode_meshopt_views(m_, fallback_, options_.max_file_bytes, decoded_,
                               [this](const std::string& pointer, const std::string& what) { fail(pointer, what); });
    const int scene = pick_scene();
    std::vector<int> roots;
    if (scene >= 0) {
      roots = m_.scenes[static_cast<std::size_t>(scene)].nodes;
    } else {
      // No scenes: every node that is nobody's child.
      std::vector<bool> child(m_.nodes.size(), false);
      for (const tg::Node& n : m_.nodes)
        for (int c : n.children)
          if (c >= 0 && static_cast<std::size_t>(c) < child.size()) child[static_cast<std::size_t>(c)] = true;
      for (std::size_t i = 0; i < m_.nodes.size(); ++i)
        if (!child[i]) roots.push_back(static_cast<int>(i));
    }
    const std::string where = scene >= 0 ? "/scenes/" + str(static_cast<std::size_t>(scene)) + "/nodes" : "/nodes";
    std::vector<bool> on_path(m_.nodes.size(), false);
    for (std::size_t i = 0; i < roots.size(); ++i)
      visit(roots[i], glm::dmat4(1.0), where + "/" + str(i), 0, on_path);
    decode_images();
  }

 private:
  // ---- Extensions, scenes ------------------------------------------------------------

  void check_extensions() {
    static const std::set<std::string> kSupported = {"KHR_texture_transform", "KHR_materials_emissive_strength",
                                                     "KHR_mesh_quantization", "KHR_lights_punctual",
                                                     "KHR_materials_unlit", gltf::kMeshopt, gltf::kDraco};
    for (std::size_t i = 0; i < m_.extensionsRequired.size(); ++i)
      if (!kSupported.count(m_.extensionsRequired[i]))
        fail("/extensionsRequired/" + str(i), "the required extension " + m_.extensionsRequired[i] + " is not supported");
    for (const std::string& e : m_.extensionsUsed)
      if (!kSupported.count(e)) warn("the extension " + e + " is not supported and is ignored");
  }

  int pick_scene() const {
    if (m_.scenes.empty()) {
      if (options_.scene >= 0) fail("/scenes", "the file has no scene " + std::to_string(options_.scene));
      return -1;
    }
    int s = options_.scene >= 0 ? options_.scene : (m_.defaultScene >= 0 ? m_.defaultScene : 0);
    if (static_cast<std::size_t>(s) >= m_.scenes.size())
      fail(options_.scene >= 0 ? "/scenes" : "/scene", "scene " + std::to_string(s) + " does not exist (" +
                                                            str(m_.scenes.size()) + " scenes)");
    return s;
  }

  // ---- Nodes -------------------------------------------------------------------------

  glm::dmat4 local_matrix(const tg::Node& n, const std::string& pointer) const {
    auto finite = [&](const std::vector<double>& v, const char* what) {
      for (double x : v)
        if (!std::isfinite(x)) fail(pointer + "/" + what, "is not finite");
    };
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16) fail(pointer + "/matrix", "must have 16 numbers");
      finite(n.matrix, "matrix");
      glm::dmat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = n.matrix[static_cast<std::size_t>(c * 4 + r)];  // column-major
      return m;
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!n.translation.empty()) {
      if (n.translation.size() != 3) fail(pointer + "/translation", "must have 3 numbers");
      finite(n.translation, "translation");
      t[3] = glm::dvec4(n.translation[0], n.translation[1], n.translation[2], 1.0);
    }
    if (!n.rotation.empty()) {
      if (n.rotation.size() != 4) fail(pointer + "/rotation", "must have 4 numbers");
      finite(n.rotation, "rotation");
      // glTF stores (x, y, z, w); glm's constructor takes w first.
      const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      r = glm::mat4_cast(q);
    }
    if (!n.scale.empty()) {
      if (n.scale.size() != 3) fail(pointer + "/scale", "must have 3 numbers");
      finite(n.scale, "scale");
      s[0][0] = n.scale[0];
      s[1][1] = n.scale[1];
      s[2][2] = n.scale[2];
    }
    return t * r * s;
  }

  void visit(int index, const glm::dmat4& parent, const std::string& referrer, int depth, std::vector<bool>& on_path) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.nodes.size())
      fail(referrer, "node " + std::to_string(index) + " does not exist");
    const auto i = static_cast<std::size_t>(index);
    const std::string pointer = "/nodes/" + str(i);
    if (on_path[i]) fail(pointer, "is its own ancestor (the node hierarchy has a cycle)");
    if (depth > kMaxDepth) fail(pointer, "the node hierarchy is deeper than " + std::to_string(kMaxDepth));
    on_path[i] = true;
    const tg::Node& n = m_.nodes[i];
    const glm::dmat4 world = parent * local_matrix(n, pointer);
    if (n.mesh >= 0) add_mesh(n.mesh, world, pointer + "/mesh");
    if (n.camera >= 0) add_camera(n.camera, world, pointer + "/camera");
    if (auto it = n.extensions.find("KHR_lights_punctual"); it != n.extensions.end() && it->second.Has("light"))
      add_light(it->second.Get("light").GetNumberAsInt(), world, pointer + "/extensions/KHR_lights_punctual/light");
    for (std::size_t c = 0; c < n.children.size(); ++c)
      visit(n.children[c], world, pointer + "/children/" + str(c), depth + 1, on_path);
    on_path[i] = false;
  }

  // ---- Accessors ---------------------------------------------------------------------

  struct Elements {
    const std::uint8_t* base = nullptr;  // null: no bufferView (zeros, then sparse values)
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
    int components = 0;
    bool normalized = false;
  };

  static std::size_t component_size(int type) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
      default: return 0;
    }
  }

  // The bytes [offset, offset + length) of bufferView `view`, checked against its buffer.
  std::pair<const std::uint8_t*, std::size_t> view_bytes(int view, const std::string& referrer) const {
    if (view < 0 || static_cast<std::size_t>(view) >= m_.bufferViews.size())
      fail(referrer, "bufferView " + std::to_string(view) + " does not exist");
    const tg::BufferView& v = m_.bufferViews[static_cast<std::size_t>(view)];
    const std::string pointer = "/bufferViews/" + std::to_string(view);
    if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= m_.buffers.size())
      fail(pointer + "/buffer", "buffer " + std::to_string(v.buffer) + " does not exist");
    const tg::Buffer& b = m_.buffers[static_cast<std::size_t>(v.buffer)];
    const auto decoded = decoded_.find(view);
    const auto declared = fallback_.find(v.buffer);
    if (declared != fallback_.end() && decoded == decoded_.end())
      fail(pointer + "/buffer", "buffer " + std::to_string(v.buffer) +
                                    " has no data (it has no uri): only EXT_meshopt_compression views may use it");
    // A compressed view's own buffer may be a placeholder: its byteLength is what counts.
    const std::uint64_t size = declared != fallback_.end() ? declared->second : b.data.size();
    if (v.byteOffset > size || v.byteLength > size - v.byteOffset)
      fail(pointer, str(v.byteLength) + " bytes at offset " + str(v.byteOffset) + " run past buffer " +
                        std::to_string(v.buffer) + " (" + std::to_string(size) + " bytes)");
    if (decoded != decoded_.end()) return {decoded->second.data(), decoded->second.size()};
    return {b.data.data() + v.byteOffset, v.byteLength};
  }

  Elements elements(int index, const std::string& referrer) const {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.accessors.size())
      fail(referrer, "accessor " + std::to_string(index) + " does not exist");
    const tg::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
    const std::string pointer = "/accessors/" + std::to_string(index);
    Elements e;
    const std::size_t csize = component_size(a.componentType);
    if (csize == 0) fail(pointer + "/componentType", "unknown component type " + std::to_string(a.componentType));
    const int comps = tg::GetNumComponentsInType(static_cast<std::uint32_t>(a.type));
    if (comps <= 0 || comps > 16) fail(pointer + "/type", "unknown type");
    if (a.count < 1 || a.count > kMaxElements)
      fail(pointer + "/count", "must be in 1 … " + str(kMaxElements) + ", got " + str(a.count));
    e.count = a.count;
    e.component_type = a.componentType;
    e.components = comps;
    e.normalized = a.normalized;
    const std::size_t elem = csize * static_cast<std::size_t>(comps);
    if (a.bufferView >= 0) {
      const auto [bytes, length] = view_bytes(a.bufferView, pointer + "/bufferView");
      const std::size_t given = m_.bufferViews[static_cast<std::size_t>(a.bufferView)].byteStride;
      if (given != 0 && (given < elem || given > 252 || given % csize != 0))
        fail("/bufferViews/" + std::to_string(a.bufferView) + "/byteStride",
             "stride " + str(given) + " does not fit elements of " + str(elem) + " bytes");
      e.stride = given != 0 ? given : elem;
      if (a.byteOffset > length || (e.count - 1) > (length - a.byteOffset) / e.stride ||
          (e.count - 1) * e.stride + elem > length - a.byteOffset)
        fail(pointer, str(e.count) + " elements of " + str(elem) + " bytes run past bufferView " +
                          std::to_string(a.bufferView) + " (" + str(length) + " bytes)");
      e.base = bytes + a.byteOffset;
    } else if (!a.sparse.isSparse) {
      // Allowed by the specification (all zeros), though rarely meant.
      e.base = nullptr;
    }
    return e;
  }

  static float component(const std::uint8_t* p, int type, bool normalized) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const auto v = static_cast<std::int8_t>(*p);
        return normalized ? std::max(static_cast<float>(v) / 127.0f, -1.0f) : static_cast<float>(v);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? static_cast<float>(*p) / 255.0f : static_cast<float>(*p);
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        std::int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(static_cast<float>(v) / 32767.0f, -1.0f) : static_cast<float>(v);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? static_cast<float>(v) / 65535.0f : static_cast<float>(v);
      }
      default: {  // UNSIGNED_INT (never normalized for attributes)
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return static_cast<float>(v);
      }
    }
  }

  static std::uint32_t index_value(const std::uint8_t* p, int type) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
      }
      default: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
    }
  }

  // The accessor's elements as floats, `components` per element (which must match).
  std::vector<float> read_floats(int index, const std::string& referrer, std::initializer_list<int> allowed,
                                 int* components_out = nullptr) const {
    const Elements e = elements(index, referrer);
    const std::string pointer = "/accessors/" + std::to_string(index);
    if (std::find(allowed.begin(), allowed.end(), e.components) == allowed.end())
      fail(pointer + "/type", "has " + std::to_string(e.components) + " components, which " + referrer + " cannot use");
    const std::size_t csize = component_size(e.component_type);
    const auto comps = static_cast<std::size_t>(e.components);
    std::vector<float> out(e.count * comps, 0.0f);
    if (e.base != nullptr)
      for (std::size_t i = 0; i < e.count; ++i)
        for (std::size_t c = 0; c < comps; ++c)
          out[i * comps + c] = component(e.base + i * e.stride + c * csize, e.component_type, e.normalized);
    const tg::Accessor& a = m_.accessors[static_cast<std::size_t>(index)];
    if (a.sparse.isSparse) {
      const std::string sp = pointer + "/sparse";
      if (a.sparse.count < 1 || static_cast<std::size_t>(a.sparse.count) > e.count)
        fail(sp + "/count", "must be in 1 … " + str(e.count));
      const auto n = static_cast<std::size_t>(a.sparse.count);
      const int itype = a.sparse.indices.componentType;
      const std::size_t isize = component_size(itype);
      if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        fail(sp + "/indices/componentType", "must be an unsigned integer type");
      auto bytes_of = [&](int view, int offset, std::size_t need, const std::string& where) {
        const auto [b, len] = view_bytes(view, where + "/bufferView");
        if (offset < 0 || static_cast<std::size_t>(offset) > len || need > len - static_cast<std::size_t>(offset))
          fail(where, str(need) + " bytes at offset " + std::to_string(offset) + " run past bufferView " +
                          std::to_string(view) + " (" + str(len) + " bytes)");
        return b + offset;
      };
      const std::uint8_t* ip = bytes_of(a.sparse.indices.bufferView, a.sparse.indices.byteOffset, n * isize, sp + "/indices");
      const std::uint8_t* vp =
          bytes_of(a.sparse.values.bufferView, a.sparse.values.byteOffset, n * comps * csize, sp + "/values");
      std::uint32_t previous = 0;
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t at = index_value(ip + k * isize, itype);
        if (at >= e.count || (k > 0 && at <= previous))
          fail(sp + "/indices", "index " + std::to_string(at) + " is out of range or not increasing");
        previous = at;
        for (std::size_t c = 0; c < comps; ++c)
          out[at * comps + c] = component(vp + (k * comps + c) * csize, e.component_type, e.normalized);
      }
    }
    if (components_out != nullptr) *components_out = e.components;
    return out;
  }

  std::vector<std::uint32_t> read_indices(int index, std::size_t vertex_count, const std::string& referrer) const {
    const Elements e = elements(index, referrer);
    const std::string pointer = "/accessors/" + std::to_string(index);
    if (e.components != 1) fail(pointer + "/type", "indices must be SCALAR");
    if (e.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        e.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        e.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(pointer + "/componentType", "indices must be unsigned bytes, shorts or ints");
    if (m_.accessors[static_cast<std::size_t>(index)].sparse.isSparse)
      fail(pointer + "/sparse", "sparse index accessors are not supported");
    if (e.base == nullptr) fail(pointer, "indices need a bufferView");
    std::vector<std::uint32_t> out(e.count);
    for (std::size_t i = 0; i < e.count; ++i) {
      out[i] = index_value(e.base + i * e.stride, e.component_type);
      if (out[i] >= vertex_count)
        fail(pointer, "index " + std::to_string(out[i]) + " at element " + str(i) + " is out of range (" +
                          str(vertex_count) + " vertices)");
    }
    return out;
  }

  // ---- Meshes ------------------------------------------------------------------------

  // The triangles of a primitive's index list for its mode (glTF 2.0, §3.7.2.1).
  std::vector<std::uint32_t> triangles(int mode, const std::vector<std::uint32_t>& v) const {
    std::vector<std::uint32_t> t;
    const std::size_t n = v.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      t.assign(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n - n % 3));
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (std::size_t i = 0; i + 2 < n; ++i) {
        const std::size_t odd = i % 2;
        t.insert(t.end(), {v[i], v[i + 1 + odd], v[i + 2 - odd]});
      }
    } else {  // TRIANGLE_FAN
      for (std::size_t i = 1; i + 1 < n; ++i) t.insert(t.end(), {v[i], v[i + 1], v[0]});
    }
    return t;
  }

  // A primitive's KHR_draco_mesh_compression object, decoded.
  gltf::DracoMesh draco_mesh(const tg::Value& x, const std::string& ep) const {
    if (!x.IsObject()) fail(ep, "must be an object");
    auto index = [&](const tg::Value& v, const std::string& where) {
      const double d = v.IsNumber() ? v.GetNumberAsDouble() : -1.0;
      if (!(d >= 0.0 && d <= 2147483647.0) || d != std::floor(d)) fail(where, "must be an integer ≥ 0");
      return static_cast<int>(d);
    };
    if (!x.Has("bufferView")) fail(ep, "has no bufferView (required)");
    const int view = index(x.Get("bufferView"), ep + "/bufferView");
    if (!x.Has("attributes") || !x.Get("attributes").IsObject()) fail(ep + "/attributes", "must be an object (required)");
    const tg::Value& attributes = x.Get("attributes");
    std::map<std::string, int> ids;
    for (const std::string& key : attributes.Keys()) ids[key] = index(attributes.Get(key), ep + "/attributes/" + key);
    const auto [bytes, length] = view_bytes(view, ep + "/bufferView");
    return gltf::decode_draco({bytes, length}, ids, kMaxElements,
                              [&](const std::string& sub, const std::string& what) { fail(ep + sub, what); });
  }

  // A Draco attribute's values as the accessor `a` describes them (its type and count must
  // match; integers normalized when the accessor says so).
  std::vector<float> draco_values(const gltf::DracoMesh& d, const std::string& name, int a, const std::string& referrer,
                                  std::initializer_list<int> allowed, int* components_out) const {
    if (a < 0 || static_cast<std::size_t>(a) >= m_.accessors.size())
      fail(referrer, "accessor " + std::to_string(a) + " does not exist");
    const tg::Accessor& acc = m_.accessors[static_cast<std::size_t>(a)];
    const std::string pointer = "/accessors/" + std::to_string(a);
    const int comps = tg::GetNumComponentsInType(static_cast<std::uint32_t>(acc.type));
    if (std::find(allowed.begin(), allowed.end(), comps) == allowed.end())
      fail(pointer + "/type", "has " + std::to_string(comps) + " components, which " + referrer + " cannot use");
    if (component_size(acc.componentType) == 0)
      fail(pointer + "/componentType", "unknown component type " + std::to_string(acc.componentType));
    const gltf::DracoAttribute& da = d.attributes.at(name);
    if (da.components != comps)
      fail(pointer + "/type", "has " + std::to_string(comps) + " components, but the Draco attribute has " +
                                  std::to_string(da.components));
    if (acc.count != d.points)
      fail(pointer + "/count", "is " + str(acc.count) + ", but the Draco mesh has " + str(d.points) + " points");
    std::vector<float> v = da.values;
    if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
      if (da.dequantized)
        fail(pointer + "/componentType", "is an integer type, but the Draco attribute holds floats");
      if (acc.normalized) {
        const float scale = acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE             ? 127.0f
                            : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE  ? 255.0f
                            : acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT          ? 32767.0f
                            : acc.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 65535.0f
                                                                                           : 1.0f;
        for (float& x : v) x = std::max(x / scale, -1.0f);
      }
    }
    if (components_out != nullptr) *components_out = comps;
    return v;
  }

  std::shared_ptr<const Mesh> primitive_mesh(const tg::Primitive& p, const std::string& pointer, bool normal_mapped) {
    auto attribute = [&](const char* name) {
      const auto it = p.attributes.find(name);
      return it == p.attributes.end() ? -1 : it->second;
    };
    const int position = attribute("POSITION");
    if (position < 0) fail(pointer + "/attributes", "has no POSITION");
    const std::string ap = pointer + "/attributes/";
    // KHR_draco_mesh_compression: the attributes it names and the triangles come from the
    // Draco data, described by the primitive's accessors.
    std::optional<gltf::DracoMesh> draco;
    if (const auto it = p.extensions.find(gltf::kDraco); it != p.extensions.end())
      draco = draco_mesh(it->second, pointer + "/extensions/" + gltf::kDraco);
    auto values = [&](const char* name, int a, std::initializer_list<int> allowed, int* comps) {
      if (!draco || draco->attributes.count(name) == 0) return read_floats(a, ap + name, allowed, comps);
      return draco_values(*draco, name, a, ap + name, allowed, comps);
    };
    const std::vector<float> pos = values("POSITION", position, {3}, nullptr);
    const std::size_t n = pos.size() / 3;
    for (std::size_t i = 0; i < pos.size(); ++i)
      if (!std::isfinite(pos[i]))
        fail("/accessors/" + std::to_string(position), "position " + str(i / 3) + " is not finite");
    auto optional = [&](const char* name, std::initializer_list<int> allowed, int* comps = nullptr) {
      const int a = attribute(name);
      if (a < 0) return std::vector<float>{};
      std::vector<float> v = values(name, a, allowed, comps);
      if (v.size() / static_cast<std::size_t>(comps != nullptr ? *comps : *allowed.begin()) != n)
        fail(ap + name, "has " + str(m_.accessors[static_cast<std::size_t>(a)].count) + " elements for " + str(n) +
                            " positions");
      for (float x : v)
        if (!std::isfinite(x)) fail("/accessors/" + std::to_string(a), "holds a value that is not finite");
      return v;
    };
    const std::vector<float> normal = optional("NORMAL", {3});
    const std::vector<float> tangent = optional("TANGENT", {4});
    const std::vector<float> uv0 = optional("TEXCOORD_0", {2});
    const std::vector<float> uv1 = optional("TEXCOORD_1", {2});
    int color_comps = 4;
    const std::vector<float> color = optional("COLOR_0", {3, 4}, &color_comps);

    std::vector<std::uint32_t> order;
    if (draco) {
      order = draco->indices;  // triangles
    } else if (p.indices >= 0) {
      order = read_indices(p.indices, n, pointer + "/indices");
    } else {
      order.resize(n);
      std::iota(order.begin(), order.end(), 0u);
    }
    const int mode = draco ? TINYGLTF_MODE_TRIANGLES : p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    auto mesh = std::make_shared<Mesh>();
    mesh->indices = triangles(mode, order);
    mesh->vertices.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      MeshVertex& v = mesh->vertices[i];
      v.position = {pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]};
      v.normal = normal.empty() ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]);
      v.uv = uv0.empty() ? glm::vec2(0.0f) : glm::vec2(uv0[2 * i], uv0[2 * i + 1]);
    }
    if (!tangent.empty()) {
      mesh->tangents.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        mesh->tangents[i] = {tangent[4 * i], tangent[4 * i + 1], tangent[4 * i + 2], tangent[4 * i + 3] < 0.0f ? -1.0f : 1.0f};
    }
    if (!uv1.empty()) {
      mesh->uv1.resize(n);
      for (std::size_t i = 0; i < n; ++i) mesh->uv1[i] = {uv1[2 * i], uv1[2 * i + 1]};
    }
    if (!color.empty()) {
      const auto c = static_cast<std::size_t>(color_comps);
      mesh->colors.resize(n);
      for (std::size_t i = 0; i < n; ++i)
        mesh->colors[i] = {color[c * i], color[c * i + 1], color[c * i + 2], c == 4 ? color[c * i + 3] : 1.0f};
    }
    if (normal.empty()) flat_normals(*mesh);
    if (normal_mapped && mesh->tangents.empty()) generate_tangents(*mesh);
    out_.triangles += mesh->triangle_count();
    return mesh;
  }

  // glTF: "When normals are not specified, client implementations MUST calculate flat
  // normals": every triangle gets vertices of its own with the face's normal.
  static void flat_normals(Mesh& mesh) {
    Mesh flat;
    const std::size_t corners = mesh.indices.size();
    flat.vertices.reserve(corners);
    flat.indices.resize(corners);
    const bool t = !mesh.tangents.empty(), u = !mesh.uv1.empty(), c = !mesh.colors.empty();
    for (std::size_t k = 0; k < corners; k += 3) {
      const glm::vec3 a = mesh.vertices[mesh.indices[k]].position, b = mesh.vertices[mesh.indices[k + 1]].position,
                      d = mesh.vertices[mesh.indices[k + 2]].position;
      const glm::vec3 cr = glm::cross(b - a, d - a);
      const float len = std::sqrt(glm::dot(cr, cr));
      const glm::vec3 n = len > 0.0f && std::isfinite(len) ? cr / len : glm::vec3(0.0f, 1.0f, 0.0f);
      for (std::size_t j = 0; j < 3; ++j) {
        const std::uint32_t src = mesh.indices[k + j];
        MeshVertex v = mesh.vertices[src];
        v.normal = n;
        flat.indices[k + j] = static_cast<std::uint32_t>(flat.vertices.size());
        flat.vertices.push_back(v);
        if (t) flat.tangents.push_back(mesh.tangents[src]);
        if (u) flat.uv1.push_back(mesh.uv1[src]);
        if (c) flat.colors.push_back(mesh.colors[src]);
      }
    }
    mesh = std::move(flat);
  }

  void add_mesh(int index, const glm::dmat4& world, const std::string& referrer) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.meshes.size())
      fail(referrer, "mesh " + std::to_string(index) + " does not exist");
    const tg::Mesh& mesh = m_.meshes[static_cast<std::size_t>(index)];
    const std::string pointer = "/meshes/" + std::to_string(index);
    const glm::mat4 transform(world);
    const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
    for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tg::Primitive& p = mesh.primitives[k];
      const std::string pp = pointer + "/primitives/" + str(k);
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        if (mode >= 0 && mode <= 3) {
          warn(pp + ": points and lines are not drawn");
          continue;
        }
        fail(pp + "/mode", "unknown mode " + std::to_string(mode));
      }
      // A Draco primitive's indices accessor only describes the Draco data's triangles.
      if (const auto d = draco_indices_.find({static_cast<std::size_t>(index), k}); d != draco_indices_.end())
        if (d->second < 0 || static_cast<std::size_t>(d->second) >= m_.accessors.size())
          fail(pp + "/indices", "accessor " + std::to_string(d->second) + " does not exist");
      const Material& material = this->material(p.material, pp + "/material");
      const bool normal_mapped =
          p.material >= 0 && m_.materials[static_cast<std::size_t>(p.material)].normalTexture.index >= 0;
      (void)material;
      const auto key = std::make_tuple(index, k, mirrored);
      auto it = meshes_.find(key);
      if (it == meshes_.end()) {
        const auto unmirrored = std::make_tuple(index, k, false);
        auto base = meshes_.find(unmirrored);
        std::shared_ptr<const Mesh> m =
            base != meshes_.end() ? base->second : primitive_mesh(p, pp, normal_mapped);
        if (base == meshes_.end()) meshes_[unmirrored] = m;
        if (mirrored) {
          // A mirroring transform turns counter-clockwise triangles clockwise on screen.
          auto flipped = std::make_shared<Mesh>(*m);
          for (std::size_t t = 0; t + 2 < flipped->indices.size(); t += 3) std::swap(flipped->indices[t + 1], flipped->indices[t + 2]);
          m = flipped;
          meshes_[key] = m;
        }
        it = meshes_.find(key);
      }
      placed_.push_back({it->second, p.material, transform});
    }
  }

  // ---- Materials and textures --------------------------------------------------------

  raster::Sampler sampler(int index, const std::string& referrer) {
    raster::Sampler s;
    s.max_anisotropy = kAnisotropy;
    if (index < 0) return s;  // glTF: repeat, filters "auto" → trilinear
    if (static_cast<std::size_t>(index) >= m_.samplers.size())
      fail(referrer, "sampler " + std::to_string(index) + " does not exist");
    const tg::Sampler& g = m_.samplers[static_cast<std::size_t>(index)];
    const std::string pointer = "/samplers/" + std::to_string(index);
    auto wrap = [&](int w, const char* name) {
      switch (w) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT: return raster::Wrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return raster::Wrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return raster::Wrap::MirroredRepeat;
        default: fail(pointer + "/" + name, "unknown wrap mode " + std::to_string(w));
      }
    };
    s.wrap_u = wrap(g.wrapS, "wrapS");
    s.wrap_v = wrap(g.wrapT, "wrapT");
    switch (g.magFilter) {
      case -1:
      case TINYGLTF_TEXTURE_FILTER_LINEAR: s.mag_filter = raster::Filter::Linear; break;
      case TINYGLTF_TEXTURE_FILTER_NEAREST: s.mag_filter = raster::Filter::Nearest; break;
      default: fail(pointer + "/magFilter", "unknown filter " + std::to_string(g.magFilter));
    }
    using F = raster::Filter;
    using M = raster::MipFilter;
    switch (g.minFilter) {
      case -1:
      case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR: s.min_filter = F::Linear, s.mip_filter = M::Linear; break;
      case TINYGLTF_TEXTURE_FILTER_NEAREST: s.min_filter = F::Nearest, s.mip_filter = M::None; break;
      case TINYGLTF_TEXTURE_FILTER_LINEAR: s.min_filter = F::Linear, s.mip_filter = M::None; break;
      case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST: s.min_filter = F::Nearest, s.mip_filter = M::Nearest; break;
      case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST: s.min_filter = F::Linear, s.mip_filter = M::Nearest; break;
      case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR: s.min_filter = F::Nearest, s.mip_filter = M::Linear; break;
      default: fail(pointer + "/minFilter", "unknown filter " + std::to_string(g.minFilter));
    }
    if (s.mip_filter == M::None) s.max_anisotropy = 1;
    return s;
  }

  // Fills `slot` from a textureInfo: the texture's image (queued for decoding), sampler,
  // UV set and KHR_texture_transform.
  void texture_slot(TextureSlot& slot, int texture, int tex_coord, const tg::ExtensionMap& extensions,
                    raster::ColorSpace space, const std::string& pointer) {
    if (texture < 0) return;
    if (static_cast<std::size_t>(texture) >= m_.textures.size())
      fail(pointer + "/index", "texture " + std::to_string(texture) + " does not exist");
    const tg::Texture& t = m_.textures[static_cast<std::size_t>(texture)];
    const std::string tp = "/textures/" + std::to_string(texture);
    if (t.source < 0) {
      warn(tp + ": has no image this loader can read (only PNG and JPEG sources are); the slot is left empty");
      return;
    }
    if (static_cast<std::size_t>(t.source) >= m_.images.size())
      fail(tp + "/source", "image " + std::to_string(t.source) + " does not exist");
    slot.sampler = sampler(t.sampler, tp + "/sampler");
    int uv_set = tex_coord;
    if (auto it = extensions.find("KHR_texture_transform"); it != extensions.end()) {
      const tg::Value& x = it->second;
      const std::string xp = pointer + "/extensions/KHR_texture_transform";
      auto number = [&](const tg::Value& v, const std::string& where) {
        if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) fail(where, "expected a finite number");
        return static_cast<float>(v.GetNumberAsDouble());
      };
      auto vec2 = [&](const char* key, glm::vec2 fallback) {
        if (!x.Has(key)) return fallback;
        const tg::Value& v = x.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2) fail(xp + "/" + key, "expected two numbers");
        return glm::vec2(number(v.Get(0), xp + "/" + key + "/0"), number(v.Get(1), xp + "/" + key + "/1"));
      };
      slot.transform.offset = vec2("offset", {0.0f, 0.0f});
      slot.transform.scale = vec2("scale", {1.0f, 1.0f});
      if (x.Has("rotation")) slot.transform.rotation = number(x.Get("rotation"), xp + "/rotation");
      if (x.Has("texCoord")) uv_set = x.Get("texCoord").GetNumberAsInt();
    }
    if (uv_set != 0 && uv_set != 1) {
      warn(pointer + ": TEXCOORD_" + std::to_string(uv_set) + " is not supported; the slot is left empty");
      return;
    }
    slot.uv_set = uv_set;
    // The texture itself is made once per image and colour space, after every material is
    // known, so that all images decode in parallel.
    pending_.push_back({&slot, t.source, space});
  }

  // Reads material `index` once (-1: the default material) and returns it; its texture
  // slots are filled by decode_images().
  const Material& material(int index, const std::string& referrer) {
    if (auto it = materials_.find(index); it != materials_.end()) return *it->second;
    if (index < 0) {
      // The default material (glTF 2.0, §3.9.6): metallic 1, roughness 1, white.
      auto m = std::make_unique<Material>();
      m->base_color = {1.0f, 1.0f, 1.0f};
      m->metallic = 1.0f;
      m->roughness = 1.0f;
      return *(materials_[index] = std::move(m));
    }
    if (static_cast<std::size_t>(index) >= m_.materials.size())
      fail(referrer, "material " + std::to_string(index) + " does not exist");
    const tg::Material& g = m_.materials[static_cast<std::size_t>(index)];
    const std::string pointer = "/materials/" + std::to_string(index);
    auto unit = [&](double x, const std::string& where) {
      if (!std::isfinite(x)) fail(where, "is not finite");
      return static_cast<float>(std::clamp(x, 0.0, 1.0));
    };
    auto m = std::make_unique<Material>();
    const auto& pbr = g.pbrMetallicRoughness;
    const std::string pp = pointer + "/pbrMetallicRoughness";
    if (pbr.baseColorFactor.size() != 4) fail(pp + "/baseColorFactor", "must have 4 numbers");
    m->base_color = {unit(pbr.baseColorFactor[0], pp + "/baseColorFactor/0"), unit(pbr.baseColorFactor[1], pp + "/baseColorFactor/1"),
                     unit(pbr.baseColorFactor[2], pp + "/baseColorFactor/2")};
    m->alpha = unit(pbr.baseColorFactor[3], pp + "/baseColorFactor/3");
    m->metallic = unit(pbr.metallicFactor, pp + "/metallicFactor");
    m->roughness = unit(pbr.roughnessFactor, pp + "/roughnessFactor");
    if (g.emissiveFactor.size() != 3) fail(pointer + "/emissiveFactor", "must have 3 numbers");
    float strength = 1.0f;
    if (auto it = g.extensions.find("KHR_materials_emissive_strength"); it != g.extensions.end() &&
                                                                      it->second.Has("emissiveStrength")) {
      const double s = it->second.Get("emissiveStrength").GetNumberAsDouble();
      if (!std::isfinite(s) || s < 0.0)
        fail(pointer + "/extensions/KHR_materials_emissive_strength/emissiveStrength", "must be a finite number ≥ 0");
      strength = static_cast<float>(s);
    }
    m->emissive = glm::vec3(unit(g.emissiveFactor[0], pointer + "/emissiveFactor/0"),
                            unit(g.emissiveFactor[1], pointer + "/emissiveFactor/1"),
                            unit(g.emissiveFactor[2], pointer + "/emissiveFactor/2")) *
                  strength;
    if (g.alphaMode == "OPAQUE" || g.alphaMode.empty()) m->alpha_mode = AlphaMode::Opaque;
    else if (g.alphaMode == "MASK") m->alpha_mode = AlphaMode::Mask;
    else if (g.alphaMode == "BLEND") m->alpha_mode = AlphaMode::Blend;
    else fail(pointer + "/alphaMode", "must be OPAQUE, MASK or BLEND, got " + g.alphaMode);
    if (!std::isfinite(g.alphaCutoff) || g.alphaCutoff < 0.0) fail(pointer + "/alphaCutoff", "must be a number ≥ 0");
    m->alpha_cutoff = static_cast<float>(std::min(g.alphaCutoff, 1.0));
    m->double_sided = g.doubleSided;
    m->unlit = g.extensions.count("KHR_materials_unlit") != 0;
    if (!std::isfinite(g.normalTexture.scale)) fail(pointer + "/normalTexture/scale", "is not finite");
    m->normal_scale = static_cast<float>(g.normalTexture.scale);
    m->occlusion_strength = unit(g.occlusionTexture.strength, pointer + "/occlusionTexture/strength");
    using CS = raster::ColorSpace;
    texture_slot(m->base_color_texture, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                 pbr.baseColorTexture.extensions, CS::Srgb, pp + "/baseColorTexture");
    texture_slot(m->metallic_roughness_texture, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                 pbr.metallicRoughnessTexture.extensions, CS::Linear, pp + "/metallicRoughnessTexture");
    texture_slot(m->normal_texture, g.normalTexture.index, g.normalTexture.texCoord, g.normalTexture.extensions,
                 CS::Linear, pointer + "/normalTexture");
    texture_slot(m->occlusion_texture, g.occlusionTexture.index, g.occlusionTexture.texCoord,
                 g.occlusionTexture.extensions, CS::Linear, pointer + "/occlusionTexture");
    texture_slot(m->emissive_texture, g.emissiveTexture.index, g.emissiveTexture.texCoord, g.emissiveTexture.extensions,
                 CS::Srgb, pointer + "/emissiveTexture");
    return *(materials_[index] = std::move(m));
  }

  // The memory the textures will take, from the images' headers, before any is decoded:
  // each texture's mip chain (4/3 of its 8-bit texels) kept, and a decoded image for each
  // thread decoding at once; with the model's buffers, within options_.memory_limit.
  void check_texture_memory(const std::vector<std::pair<int, raster::ColorSpace>>& jobs) const {
    std::uint64_t used = 0, largest = 0;
    for (const tg::Buffer& b : m_.buffers) used += b.data.size();
    for (const tg::Image& im : m_.images) used += im.image.size();
    for (const auto& bytes : external_) used += bytes.size();
    const std::uint64_t threads = options_.pool != nullptr ? options_.pool->size() : 1;
    for (const auto& [index, space] : jobs) {
      const image::ImageHeader h = image::read_image_header(encoded(index));
      const std::uint64_t texels = std::uint64_t(h.width) * std::uint64_t(h.height) * 4;
      used += texels + texels / 3 + 64;
      largest = std::max(largest, texels);
      const std::uint64_t total = used + std::min<std::uint64_t>(threads, jobs.size()) * largest;
      if (total > options_.memory_limit)
        fail("/images/" + std::to_string(index),
             "its texture (" + std::to_string(h.width) + "x" + std::to_string(h.height) +
                 ") brings the model's buffers and textures to an estimated " + format_bytes(total) +
                 ", over the memory limit of " + format_bytes(options_.memory_limit));
    }
  }

  // fn(0) … fn(count − 1), on the pool when there is one.
  void for_each_job(std::size_t count, const std::function<void(std::size_t)>& fn) const {
    if (options_.pool != nullptr) options_.pool->parallel_for(count, fn);
    else for (std::size_t k = 0; k < count; ++k) fn(k);
  }

  // An image's encoded bytes: in a buffer view or a data URI (tinygltf copied them), or
  // in its own file (after read_images()).
  std::span<const std::uint8_t> encoded(int index) const {
    const auto i = static_cast<std::size_t>(index);
    if (!m_.images[i].image.empty()) return m_.images[i].image;
    return external_[i];
  }

  // Every external image's path joins the files read (GltfScene::files: an output must not
  // replace one); the ones the jobs decode are read, in parallel on the pool, before
  // anything is decoded (check_texture_memory reads their headers).
  void read_images(const std::vector<std::pair<int, raster::ColorSpace>>& jobs) {
    std::vector<std::string> paths(m_.images.size());
    for (std::size_t i = 0; i < m_.images.size(); ++i) {
      const tg::Image& im = m_.images[i];
      if (im.bufferView >= 0 || !gltf::is_external_uri(im.uri)) continue;
      paths[i] = gltf::uri_path(base_dir_, im.uri);
      out_.files.push_back(paths[i]);
    }
    external_.assign(m_.images.size(), {});
    std::vector<int> wanted;
    for (const auto& job : jobs)
      if (!paths[static_cast<std::size_t>(job.first)].empty() &&
          std::find(wanted.begin(), wanted.end(), job.first) == wanted.end())
        wanted.push_back(job.first);
    std::vector<std::string> problems(wanted.size());
    auto read = [&](std::size_t k) {
      const auto i = static_cast<std::size_t>(wanted[k]);
      problems[k] = gltf::read_external(paths[i], options_.max_file_bytes, options_.roots, external_[i]);
    };
    for_each_job(wanted.size(), read);
    for (std::size_t k = 0; k < wanted.size(); ++k)
      if (!problems[k].empty())
        fail("/images/" + std::to_string(wanted[k]) + "/uri", problems[k]);
  }

  // Decodes every image a slot needs, once per image and colour space, on the pool, and
  // fills the slots (of the cached materials and of the objects that copied them).
  void decode_images() {
    std::map<std::pair<int, raster::ColorSpace>, std::size_t> job_of;
    std::vector<std::pair<int, raster::ColorSpace>> jobs;
    for (const Pending& p : pending_) {
      const auto key = std::make_pair(p.image, p.space);
      if (job_of.emplace(key, jobs.size()).second) jobs.push_back(key);
    }
    read_images(jobs);
    check_texture_memory(jobs);
    std::vector<std::shared_ptr<const raster::Texture>> textures(jobs.size());
    auto decode = [&](std::size_t j) {
      const auto [index, space] = jobs[j];
      const tg::Image& im = m_.images[static_cast<std::size_t>(index)];
      const std::string name =
          file_ + ": /images/" + std::to_string(index) + (im.uri.empty() || im.uri.rfind("data:", 0) == 0 ? "" : " (" + im.uri + ")");
      const std::span<const std::uint8_t> bytes = encoded(index);
      if (bytes.empty()) throw LoadError(name + ": the image could not be read" + (im.uri.empty() ? "" : " (an empty file)"));
      try {
        // Decoded with room for the mip chain, which the texture then builds in place.
        image::Image8 pixels = image::load_image8(bytes, name, options_.image_limits, &raster::Texture::rgba8_chain_bytes);
        textures[j] = std::make_shared<const raster::Texture>(std::move(pixels), space);
      } catch (const LoadError&) {
        throw;
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        throw LoadError(e.what());
      }
    };
    for_each_job(jobs.size(), decode);
    for (const Pending& p : pending_) p.slot->texture = textures[job_of.at({p.image, p.space})];
    // The objects, now that their materials are complete.
    for (const Placed& o : placed_) out_.objects.push_back({o.mesh, *materials_.at(o.material), o.transform});
  }

  // ---- Cameras and lights ------------------------------------------------------------

  void add_camera(int index, const glm::dmat4& world, const std::string& referrer) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.cameras.size())
      fail(referrer, "camera " + std::to_string(index) + " does not exist");
    const tg::Camera& c = m_.cameras[static_cast<std::size_t>(index)];
    const std::string pointer = "/cameras/" + std::to_string(index);
    GltfCamera g;
    g.name = c.name;
    const glm::dvec3 eye(world * glm::dvec4(0, 0, 0, 1));
    const glm::dvec3 forward(world * glm::dvec4(0, 0, -1, 0));
    const glm::dvec3 up(world * glm::dvec4(0, 1, 0, 0));
    g.camera.position = glm::vec3(eye);
    g.camera.target = glm::vec3(eye + forward);
    g.camera.up = glm::vec3(up);
    if (c.type == "orthographic") {
      // glTF 2.0 §5.13: xmag and ymag not zero (and not negative: a mirrored view is not
      // drawn), znear ≥ 0, zfar > znear.
      const tg::OrthographicCamera& o = c.orthographic;
      const std::string op = pointer + "/orthographic";
      auto magnification = [&](double x, const char* name) {
        if (!(x > 0.0) || !(x <= 1e30)) fail(op + "/" + name, "must be a number in (0, 1e30], got " + number_text(x));
        if (!(static_cast<float>(x) >= 1e-30f)) fail(op + "/" + name, "must be at least 1e-30, got " + number_text(x));
        return static_cast<float>(x);
      };
      g.camera.orthographic = true;
      g.camera.xmag = magnification(o.xmag, "xmag");
      g.camera.ymag = magnification(o.ymag, "ymag");
      if (!(o.znear >= 0.0) || !(o.znear <= 1e30)) fail(op + "/znear", "must be a number in [0, 1e30], got " + number_text(o.znear));
      if (!(o.zfar > o.znear) || !(o.zfar <= 1e30))
        fail(op + "/zfar", "must be above znear and at most 1e30, got " + number_text(o.zfar));
      g.camera.near = static_cast<float>(o.znear);
      g.camera.far = static_cast<float>(o.zfar);
      if (!(g.camera.far - g.camera.near >= 1e-30f))
        fail(op + "/zfar", "must be at least 1e-30 beyond znear in float precision, got " + number_text(o.zfar));
    } else if (c.type == "perspective") {
      const tg::PerspectiveCamera& p = c.perspective;
      if (!(p.yfov > 0.0 && p.yfov < 3.14159)) fail(pointer + "/perspective/yfov", "must be in (0, π)");
      if (!(p.znear > 0.0) || !std::isfinite(p.znear)) fail(pointer + "/perspective/znear", "must be > 0");
      if (p.zfar != 0.0 && !(p.zfar > p.znear)) fail(pointer + "/perspective/zfar", "must be above znear");
      g.camera.fovy = static_cast<float>(p.yfov);
      g.camera.near = static_cast<float>(p.znear);
      // An infinite far plane (zfar absent) becomes a far one: 10^5 × znear keeps the depth
      // buffer's precision usable.
      g.camera.far = static_cast<float>(p.zfar != 0.0 ? p.zfar : p.znear * 1e5);
      g.aspect_ratio = static_cast<float>(p.aspectRatio);
    } else {
      fail(pointer + "/type", "must be perspective or orthographic");  // (tinygltf refuses others first)
    }
    out_.cameras.push_back(g);
  }

  void add_light(int index, const glm::dmat4& world, const std::string& referrer) {
    if (index < 0 || static_cast<std::size_t>(index) >= m_.lights.size())
      fail(referrer, "light " + std::to_string(index) + " does not exist");
    const tg::Light& l = m_.lights[static_cast<std::size_t>(index)];
    const std::string pointer = "/extensions/KHR_lights_punctual/lights/" + std::to_string(index);
    Light out;
    if (l.type == "point") out.type = LightType::Point;
    else if (l.type == "spot") out.type = LightType::Spot;
    else if (l.type == "directional") out.type = LightType::Directional;
    else fail(pointer + "/type", "must be point, spot or directional, got " + l.type);
    if (!l.color.empty()) {
      if (l.color.size() != 3) fail(pointer + "/color", "must have 3 numbers");
      for (double c : l.color)
        if (!(c >= 0.0) || !std::isfinite(c)) fail(pointer + "/color", "must be finite and non-negative");
      out.color = {static_cast<float>(l.color[0]), static_cast<float>(l.color[1]), static_cast<float>(l.color[2])};
    }
    if (!(l.intensity >= 0.0) || !std::isfinite(l.intensity)) fail(pointer + "/intensity", "must be finite and ≥ 0");
    // KHR_lights_punctual: candela (point, spot) and lux (directional) scale the light's
    // radiance directly, as the glTF Sample Viewer applies them (docs/scene-format.md).
    out.intensity = static_cast<float>(l.intensity);
    if (!(l.range >= 0.0) || !std::isfinite(l.range)) fail(pointer + "/range", "must be finite and ≥ 0");
    out.range = static_cast<float>(l.range);
    out.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
    const glm::dvec3 d(world * glm::dvec4(0, 0, -1, 0));
    const double len = std::sqrt(glm::dot(d, d));
    if (!(len > 0.0)) fail(referrer, "the light's node has a degenerate transform");
    out.direction = glm::vec3(d / len);
    if (out.type == LightType::Spot) {
      out.inner_cone = static_cast<float>(l.spot.innerConeAngle);
      out.outer_cone = static_cast<float>(l.spot.outerConeAngle);
    }
    out_.lights.push_back(out);
  }

  static constexpr int kAnisotropy = 8;

  struct Pending {
    TextureSlot* slot;
    int image;
    raster::ColorSpace space;
  };

  std::string file_;
  std::string base_dir_;
  // The encoded bytes of the external images the materials use, by image index (tinygltf
  // reads none: TINYGLTF_NO_EXTERNAL_IMAGE), read on the pool by read_images().
  std::vector<std::vector<unsigned char>> external_;
  const tg::Model& m_;
  const GltfOptions& options_;
  GltfScene& out_;
  std::map<int, std::uint64_t> fallback_;               // buffers without data: their byteLength
  std::map<int, std::vector<std::uint8_t>> decoded_;    // EXT_meshopt_compression views
  std::map<std::pair<std::size_t, std::size_t>, int> draco_indices_;  // Draco primitives' "indices"
  std::map<std::tuple<int, std::size_t, bool>, std::shared_ptr<const Mesh>> meshes_;
  std::map<int, std::unique_ptr<Material>> materials_;
  std::vector<Pending> pending_;
  struct Placed {
    std::shared_ptr<const Mesh> mesh;
    int material;
    glm::mat4 transform;
  };
  std::vector<Placed> placed_;
};

// ---- Files ----------------------------------------------------------------------------

std::vector<unsigned char> read_file(const std::filesystem::path& path, std::uint64_t limit, const std::string& what) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw LoadError(what + ": cannot read: " + ec.message());
  if (size > limit) throw LoadError(what + ": " + std::to_string(size) + " bytes is over the limit of " + std::to_string(limit));
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> bytes(static_cast<std::size_t>(size));
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
    throw LoadError(what + ": cannot read");
  return bytes;
}

struct FsContext {
  std::uint64_t limit;
  const std::vector<std::filesystem::path>* roots;
  std::vector<std::string> files;  // every external file read (GltfScene::files)
};

// tinygltf's file reader (external buffers: images it leaves to Loader::read_images).
bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  ctx->files.push_back(path);
  if (const std::string problem = gltf::read_external(path, ctx->limit, *ctx->roots, *out); !problem.empty()) {
    if (err) *err += problem + "\n";
    return false;
  }
  return true;
}

// tinygltf's image loader callback: keeps an image's encoded bytes (softpbr::image decodes
// them later, with its checks). An image in a buffer view comes with a pointer tinygltf 2.7
// computed without checking that the view lies inside its buffer (fuzz_gltf read past a
// buffer's end): checked here, against the model tinygltf is filling (`user` is that model;
// its buffers and views are parsed first).
bool keep_encoded(tg::Image* image, const int index, std::string* err, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
  const auto* model = static_cast<const tg::Model*>(user);
  if (model != nullptr && image->bufferView >= 0) {
    const auto v = static_cast<std::size_t>(image->bufferView);
    const tg::BufferView* view = v < model->bufferViews.size() ? &model->bufferViews[v] : nullptr;
    const tg::Buffer* buffer = view != nullptr && view->buffer >= 0 &&
                                       static_cast<std::size_t>(view->buffer) < model->buffers.size()
                                   ? &model->buffers[static_cast<std::size_t>(view->buffer)]
                                   : nullptr;
    const std::size_t have = buffer != nullptr ? buffer->data.size() : 0;
    if (view == nullptr || buffer == nullptr || size < 0 || view->byteOffset > have ||
        view->byteLength > have - view->byteOffset || static_cast<std::size_t>(size) != view->byteLength) {
      if (err != nullptr) {
        *err += "/images/" + std::to_string(index) + "/bufferView: bufferView " + std::to_string(image->bufferView);
        if (view != nullptr && buffer != nullptr)
          *err += " (bytes " + std::to_string(view->byteOffset) + " to " +
                  std::to_string(static_cast<std::uint64_t>(view->byteOffset) + view->byteLength) + ")";
        *err += " does not lie inside its buffer" +
                (buffer != nullptr ? " of " + std::to_string(have) + " bytes" : std::string()) + "\n";
      }
      return false;
    }
  }
  image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

std::string first_line(const std::string& s) {
  std::string line = s.substr(0, s.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

}  // namespace

GltfScene load_gltf(const std::filesystem::path& path, const GltfOptions& options) {
  const std::vector<unsigned char> bytes = read_file(path, options.max_file_bytes, path.string());
  return load_gltf(bytes, path.string(), path.parent_path(), options);
}

GltfScene load_gltf(std::span<const std::uint8_t> bytes, const std::string& file, const std::filesystem::path& base,
                    const GltfOptions& options) {
  if (bytes.size() > options.max_file_bytes || bytes.size() > std::numeric_limits<unsigned>::max())
    throw LoadError(file + ": " + std::to_string(bytes.size()) + " bytes is over the limit of " +
                    std::to_string(options.max_file_bytes));
  // The document: the .glb container, the JSON's limits (a streaming pass), its one DOM,
  // the schema check and the pre-pass on that DOM (gltf/document.h).
  const gltf::Container container = gltf::read_container(bytes);
  if (!container.bin_problem.empty()) throw LoadError(file + ": " + container.bin_problem);
  gltf::check_json(container, file, options.memory_limit);
  gltf::ErrorHints hints;
  std::vector<std::uint8_t> rewritten;
  std::map<int, std::uint64_t> fallback;
  std::map<std::pair<std::size_t, std::size_t>, int> draco_indices;
  {
    nlohmann::json dom = gltf::parse_json(container.json);
    if (const auto problem = gltf::check_schema(dom)) throw LoadError(file + ": " + *problem);
    // EXT_meshopt_compression's placeholder buffers and Draco primitives' indices, which
    // tinygltf refuses, rewritten.
    bytes = gltf::prepare_for_tinygltf(bytes, container, dom, rewritten, fallback, draco_indices);
    hints = gltf::error_hints(dom);
  }  // the DOM is freed before tinygltf builds its own
  if (bytes.size() > std::numeric_limits<unsigned>::max())
    throw LoadError(file + ": " + std::to_string(bytes.size()) + " bytes is over the limit of " +
                    std::to_string(std::numeric_limits<unsigned>::max()));
  tg::TinyGLTF parser;
  FsContext fs_context{options.max_file_bytes, &options.roots, {}};
  parser.SetFsCallbacks({&tg::FileExists, &tg::ExpandFilePath, &read_whole_file, &tg::WriteWholeFile, &fs_context});
  tg::Model model;
  parser.SetImageLoader(&keep_encoded, &model);
  std::string err, warn;
  const std::string base_dir = base.string();
  bool ok = false;
  try {
    if (container.binary)
      ok = parser.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()), base_dir);
    else
      ok = parser.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                      static_cast<unsigned>(bytes.size()), base_dir);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw LoadError(file + ": " + first_line(e.what()));
  }
  if (!ok) {
    // A few references tinygltf checks itself: said with their JSON pointer when found.
    const std::string pointed = gltf::tinygltf_error_with_pointer(hints, err);
    if (!pointed.empty()) throw LoadError(file + ": " + pointed);
    throw LoadError(file + ": " + (err.empty() ? std::string("not a glTF file") : first_line(err)));
  }
  GltfScene out;
  out.files = std::move(fs_context.files);
  for (std::size_t start = 0; start < warn.size();) {
    const std::size_t end = warn.find('\n', start);
    const std::string line = warn.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!line.empty()) out.warnings.push_back(file + ": " + line);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  Loader(file, base_dir, model, options, out, std::move(fallback), std::move(draco_indices)).load();
  return out;
}

}  // namespace softpbr::pbr
