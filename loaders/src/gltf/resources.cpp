// The glTF reader's resources (see resources.h): buffers, views, accessors, Draco
// attributes, images.
#include "gltf/resources.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "gltf/files.h"
#include "gltf/meshopt.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/raster/pool.h"

namespace softpbr::pbr::gltf {

void use_texture_extension_sources(tg::Model& model) {
  for (tg::Texture& t : model.textures)
    for (const char* name : kTextureSourceExtensions)
      if (auto it = t.extensions.find(name); it != t.extensions.end() && it->second.IsObject() &&
                                             it->second.Has("source") && it->second.Get("source").IsInt()) {
        t.source = it->second.Get("source").GetNumberAsInt();
        break;
      }
}

void Resources::decode_compressed_views() {
  decode_meshopt_views(m_, fallback_, options_.max_file_bytes, decoded_,
                       [this](const std::string& pointer, const std::string& what) { fail(pointer, what); });
}

// ---- Buffers, views and accessors ---------------------------------------------------

std::size_t Resources::component_size(int type) {
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
std::pair<const std::uint8_t*, std::size_t> Resources::view_bytes(int view, const std::string& referrer) const {
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

Resources::Elements Resources::elements(int index, const std::string& referrer) const {
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

float Resources::component(const std::uint8_t* p, int type, bool normalized) {
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

std::uint32_t Resources::index_value(const std::uint8_t* p, int type) {
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

std::vector<float> Resources::read_floats(int index, const std::string& referrer, std::initializer_list<int> allowed,
                                          int* components_out) const {
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

// An indices accessor's rules, for stored and for Draco-decoded indices alike: it exists,
// its count is in range, it is SCALAR of an unsigned type, not sparse.
Resources::Elements Resources::index_elements(int index, const std::string& referrer) const {
  const Elements e = elements(index, referrer);
  const std::string pointer = "/accessors/" + std::to_string(index);
  if (e.components != 1) fail(pointer + "/type", "indices must be SCALAR");
  if (e.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      e.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      e.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(pointer + "/componentType", "indices must be unsigned bytes, shorts or ints");
  if (m_.accessors[static_cast<std::size_t>(index)].sparse.isSparse)
    fail(pointer + "/sparse", "sparse index accessors are not supported");
  return e;
}

// The largest value a component of `type` holds (integer types), and its name.
static std::pair<double, const char*> integer_range(int type, double& lowest) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: lowest = -128; return {127, "BYTE"};
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: lowest = 0; return {255, "UNSIGNED_BYTE"};
    case TINYGLTF_COMPONENT_TYPE_SHORT: lowest = -32768; return {32767, "SHORT"};
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: lowest = 0; return {65535, "UNSIGNED_SHORT"};
    default: lowest = 0; return {4294967295.0, "UNSIGNED_INT"};
  }
}

std::vector<std::uint32_t> Resources::draco_indices(const DracoMesh& d, int index, const std::string& referrer) const {
  const Elements e = index_elements(index, referrer);
  const std::string pointer = "/accessors/" + std::to_string(index);
  // KHR_draco_mesh_compression: the accessor describes the decoded triangles, as it would
  // describe stored ones: their number and a type that holds every index.
  if (e.count != d.indices.size())
    fail(pointer + "/count", "is " + str(e.count) + ", but the Draco mesh has " + str(d.indices.size()) + " indices (" +
                                 str(d.indices.size() / 3) + " triangles)");
  double lowest = 0;
  const auto [highest, name] = integer_range(e.component_type, lowest);
  for (std::size_t i = 0; i < d.indices.size(); ++i)
    if (d.indices[i] > highest)
      fail(pointer + "/componentType", std::string(name) + " cannot hold the Draco mesh's index " +
                                           std::to_string(d.indices[i]) + " (element " + str(i) + ")");
  return d.indices;
}

std::vector<std::uint32_t> Resources::read_indices(int index, std::size_t vertex_count, const std::string& referrer) const {
  const Elements e = index_elements(index, referrer);
  const std::string pointer = "/accessors/" + std::to_string(index);
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

// ---- Draco ---------------------------------------------------------------------------

DracoMesh Resources::draco_mesh(const tg::Value& x, const std::string& ep) const {
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
  return decode_draco({bytes, length}, ids, kMaxElements,
                            [&](const std::string& sub, const std::string& what) { fail(ep + sub, what); });
}

std::vector<float> Resources::draco_values(const DracoMesh& d, const std::string& name, int a, const std::string& referrer,
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
  const DracoAttribute& da = d.attributes.at(name);
  if (da.components != comps)
    fail(pointer + "/type", "has " + std::to_string(comps) + " components, but the Draco attribute has " +
                                std::to_string(da.components));
  if (acc.count != d.points)
    fail(pointer + "/count", "is " + str(acc.count) + ", but the Draco mesh has " + str(d.points) + " points");
  if (acc.sparse.isSparse) fail(pointer + "/sparse", "a Draco attribute's accessor cannot be sparse");
  std::vector<float> v = da.values;
  // The accessor describes the decoded values as it would stored ones: floats for FLOAT,
  // integers its component type holds otherwise.
  if (acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT && !da.dequantized)
    fail(pointer + "/componentType", "is FLOAT, but the Draco attribute holds integers");
  if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
    if (da.dequantized)
      fail(pointer + "/componentType", "is an integer type, but the Draco attribute holds floats");
    double lowest = 0;
    const auto [highest, type_name] = integer_range(acc.componentType, lowest);
    for (std::size_t i = 0; i < v.size(); ++i)
      if (!(v[i] >= lowest && v[i] <= highest))
        fail(pointer + "/componentType", std::string(type_name) + " cannot hold the Draco attribute's value " +
                                             std::to_string(static_cast<long long>(v[i])) + " (element " + str(i / static_cast<std::size_t>(comps)) + ")");
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

// ---- Images -------------------------------------------------------------------------

// The memory the textures will take, from the images' headers, before any is decoded:
// each texture's mip chain (4/3 of its 8-bit texels) kept, and a decoded image for each
// thread decoding at once; with the model's buffers, within options_.memory_limit.
void Resources::check_texture_memory(const std::vector<std::pair<int, raster::ColorSpace>>& jobs) const {
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
void Resources::for_each_job(std::size_t count, const std::function<void(std::size_t)>& fn) const {
  if (options_.pool != nullptr) options_.pool->parallel_for(count, fn);
  else for (std::size_t k = 0; k < count; ++k) fn(k);
}

// An image's encoded bytes: in a buffer view or a data URI (tinygltf copied them), or
// in its own file (after read_images()).
std::span<const std::uint8_t> Resources::encoded(int index) const {
  const auto i = static_cast<std::size_t>(index);
  if (!m_.images[i].image.empty()) return m_.images[i].image;
  return external_[i];
}

// Every external image's path joins the files read (GltfScene::files: an output must not
// replace one); the ones the jobs decode are read, in parallel on the pool, before
// anything is decoded (check_texture_memory reads their headers).
void Resources::read_images(const std::vector<std::pair<int, raster::ColorSpace>>& jobs) {
  std::vector<std::string> paths(m_.images.size());
  for (std::size_t i = 0; i < m_.images.size(); ++i) {
    const tg::Image& im = m_.images[i];
    if (im.bufferView >= 0 || !is_external_uri(im.uri)) continue;
    paths[i] = uri_path(base_dir_, im.uri);
    out_.files.push_back(paths[i]);
  }
  external_.assign(m_.images.size(), {});
  std::vector<int> wanted;
  for (const auto& job : jobs)
    if (!paths[static_cast<std::size_t>(job.first)].empty() &&
        std::find(wanted.begin(), wanted.end(), job.first) == wanted.end())
      wanted.push_back(job.first);
  std::vector<std::string> problems(wanted.size());
  std::vector<char> unreadable(wanted.size(), 0);
  auto read = [&](std::size_t k) {
    const auto i = static_cast<std::size_t>(wanted[k]);
    bool file = false;
    problems[k] = read_external(paths[i], options_.max_file_bytes, options_.roots, external_[i], &file);
    unreadable[k] = file ? 1 : 0;
  };
  for_each_job(wanted.size(), read);
  missing_.assign(m_.images.size(), false);
  for (std::size_t k = 0; k < wanted.size(); ++k) {
    if (problems[k].empty()) continue;
    const std::string pointer = "/images/" + std::to_string(wanted[k]) + "/uri";
    // MissingImages::Warn: an image whose file cannot be read leaves its texture slots empty.
    if (unreadable[k] && options_.missing_images == MissingImages::Warn) {
      missing_[static_cast<std::size_t>(wanted[k])] = true;
      warn(pointer + ": " + problems[k] + " (a missing image: its textures are left out)");
      continue;
    }
    fail(pointer, problems[k]);
  }
}

std::vector<std::shared_ptr<const raster::Texture>> Resources::textures(
    const std::vector<std::pair<int, raster::ColorSpace>>& jobs) {
  read_images(jobs);
  check_texture_memory(jobs);
  std::vector<std::shared_ptr<const raster::Texture>> textures(jobs.size());
  auto decode = [&](std::size_t j, const image::ParallelFor& parallel) {
    const auto [index, space] = jobs[j];
    if (missing_[static_cast<std::size_t>(index)]) return;  // left out (read_images warned)
    const tg::Image& im = m_.images[static_cast<std::size_t>(index)];
    // The URI as a message quotes file content: at most 40 bytes.
    const std::string uri = im.uri.size() > 40 ? im.uri.substr(0, 40) + "…" : im.uri;
    const std::string name =
        file_ + ": /images/" + std::to_string(index) + (im.uri.empty() || im.uri.rfind("data:", 0) == 0 ? "" : " (" + uri + ")");
    const std::span<const std::uint8_t> bytes = encoded(index);
    if (bytes.empty()) throw LoadError(name + ": the image could not be read" + (im.uri.empty() ? "" : " (an empty file)"));
    try {
      // Decoded with room for the mip chain, which the texture then builds in place; a KTX2
      // file's own levels are used as stored (only those it lacks are built).
      if (image::is_ktx2(bytes)) {
        image::Ktx2Image k =
            image::load_ktx2(bytes, name, options_.image_limits, &raster::Texture::rgba8_chain_bytes, parallel);
        textures[j] = std::make_shared<const raster::Texture>(std::move(k.levels[0]),
                                                              std::span<const image::Image8>(k.levels).subspan(1), space);
      } else {
        image::Image8 pixels = image::load_image8(bytes, name, options_.image_limits, &raster::Texture::rgba8_chain_bytes);
        textures[j] = std::make_shared<const raster::Texture>(std::move(pixels), space);
      }
    } catch (const LoadError&) {
      throw;
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw LoadError(e.what());
    }
  };
  // Several textures: one a thread. One texture (a KTX2 file's blocks split between
  // threads; the same bytes as on one): the pool's threads lent to it, since a pool's
  // parallel_for cannot run inside another.
  if (jobs.size() == 1 && options_.pool != nullptr) {
    raster::ThreadPool* pool = options_.pool;
    decode(0, [pool](std::size_t count, const std::function<void(std::size_t)>& task) { pool->parallel_for(count, task); });
  } else {
    for_each_job(jobs.size(), [&](std::size_t j) { decode(j, {}); });
  }
  return textures;
}

}  // namespace softpbr::pbr::gltf
