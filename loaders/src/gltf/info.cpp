// What a glTF file holds, for `softpbr info` (see gltf_info.h). Parses with tinygltf as
// gltf.cpp does, keeping from each image only its header's size (never its pixels).
#include <algorithm>
#include <limits>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "gltf/document.h"
#include "gltf/files.h"
#include "gltf/info.h"
#include "gltf/resources.h"
#include "gltf/tinygltf.h"
#include "gltf/variants.h"
#include "softpbr/image/load.h"
#include "softpbr/loaders/gltf_info.h"
#include "texture_cache.h"

namespace softpbr::pbr {

namespace {

namespace tg = tinygltf;

struct Context {
  std::uint64_t limit = 0;
  const std::vector<std::filesystem::path>* roots = nullptr;
  std::map<int, image::ImageHeader> headers;  // by image index
  std::map<int, std::size_t> sizes;
  std::string problem;  // the first file that could not be read: "path: reason"
  std::string problem_path;
};

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  auto* ctx = static_cast<Context*>(user);
  if (const std::string problem = gltf::read_external(path, ctx->limit, *ctx->roots, *out); !problem.empty()) {
    if (ctx->problem.empty()) {
      ctx->problem = problem;
      ctx->problem_path = path;
    }
    if (err) *err += problem + "\n";
    return false;
  }
  return true;
}

// The header of each image, by its index; the encoded bytes are dropped.
bool read_header(tg::Image* im, const int index, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                 void* user) {
  auto* ctx = static_cast<Context*>(user);
  const std::size_t n = size > 0 ? static_cast<std::size_t>(size) : 0;
  ctx->headers[index] = image::read_image_header(std::span<const std::uint8_t>(bytes, n));
  ctx->sizes[index] = n;
  im->as_is = true;
  return true;
}

std::string first_line(const std::string& s) {
  std::string line = s.substr(0, s.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// Triangles of `count` vertices (or indices) drawn with glTF mode `mode`.
std::size_t triangles_of(std::size_t count, int mode) {
  switch (mode) {
    case TINYGLTF_MODE_TRIANGLES: return count / 3;
    case TINYGLTF_MODE_TRIANGLE_STRIP:
    case TINYGLTF_MODE_TRIANGLE_FAN: return count >= 3 ? count - 2 : 0;
    default: return 0;
  }
}

std::size_t accessor_count(const tg::Model& m, int a) {
  return a >= 0 && static_cast<std::size_t>(a) < m.accessors.size() ? m.accessors[static_cast<std::size_t>(a)].count : 0;
}

std::size_t primitive_triangles(const tg::Model& m, const tg::Primitive& p) {
  std::size_t count = 0;
  if (p.indices >= 0) {
    count = accessor_count(m, p.indices);
  } else if (auto it = p.attributes.find("POSITION"); it != p.attributes.end()) {
    count = accessor_count(m, it->second);
  }
  return triangles_of(count, p.mode);
}

std::vector<std::string> keys(const tg::ExtensionMap& map) {
  std::vector<std::string> out;
  for (const auto& kv : map) out.push_back(kv.first);
  return out;
}

}  // namespace

std::size_t GltfInfo::primitives() const {
  std::size_t n = 0;
  for (const GltfMeshInfo& m : meshes) n += m.primitives.size();
  return n;
}

std::size_t GltfInfo::triangles() const {
  std::size_t n = 0;
  for (const GltfMeshInfo& m : meshes) n += m.triangles;
  return n;
}

GltfInfo inspect_gltf(const std::filesystem::path& path, const GltfOptions& options) {
  const std::string file = path.string();
  std::vector<std::uint8_t> bytes;
  {
    Context probe{options.max_file_bytes, &options.roots, {}, {}, {}, {}};
    std::string err;
    // The top-level file is not confined by the roots (as load_gltf: only what it refers to).
    const std::vector<std::filesystem::path> anywhere;
    probe.roots = &anywhere;
    if (!read_whole_file(&bytes, &err, file, &probe)) throw LoadError(first_line(err));
  }
  if (bytes.size() > std::numeric_limits<unsigned>::max()) throw LoadError(file + ": over the size limit");
  // The document as load_gltf reads it (gltf/document.h), but for the schema check: the
  // pre-pass rewrites EXT_meshopt_compression's placeholder buffers and Draco primitives'
  // indices, which tinygltf refuses; restore_prepass lists them as written.
  const gltf::Document doc = gltf::read_document(bytes, file, options.memory_limit, /*schema=*/false);
  const std::span<const std::uint8_t> parsed = doc.bytes;
  if (parsed.size() > std::numeric_limits<unsigned>::max()) throw LoadError(file + ": over the size limit");
  Context ctx{options.max_file_bytes, &options.roots, {}, {}, {}, {}};
  tg::TinyGLTF parser;
  parser.SetFsCallbacks({&gltf::file_exists, &tg::ExpandFilePath, &read_whole_file, &tg::WriteWholeFile, &ctx});
  parser.SetImageLoader(&read_header, &ctx);
  tg::Model m;
  std::string err, warn;
  const std::string base_dir = path.parent_path().string();
  bool ok = false;
  try {
    if (doc.container.binary)
      ok = parser.LoadBinaryFromMemory(&m, &err, &warn, parsed.data(), static_cast<unsigned>(parsed.size()), base_dir);
    else
      ok = parser.LoadASCIIFromString(&m, &err, &warn, reinterpret_cast<const char*>(parsed.data()),
                                      static_cast<unsigned>(parsed.size()), base_dir);
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw LoadError(file + ": " + first_line(e.what()));
  }
  if (!ok) {
    if (!ctx.problem.empty())
      throw LoadError(file + ": " + gltf::buffer_pointer(doc.hints, base_dir, ctx.problem_path) + ctx.problem);
    throw LoadError(file + ": " + (err.empty() ? std::string("not a glTF file") : first_line(err)));
  }

  gltf::use_texture_extension_sources(m);
  GltfInfo info = gltf::describe(m, file, base_dir, warn, std::move(ctx.headers), std::move(ctx.sizes), options);
  if (doc.rewritten()) gltf::restore_prepass(info, m, doc.draco_indices, doc.placeholders);
  return info;
}

}  // namespace softpbr::pbr

namespace softpbr::pbr::gltf {

GltfInfo describe(const tg::Model& m, const std::string& file, const std::string& base_dir, const std::string& warn,
                  std::map<int, image::ImageHeader> headers, std::map<int, std::size_t> sizes, const GltfOptions& options) {
  GltfInfo info;
  for (std::size_t start = 0; start < warn.size();) {
    const std::size_t end = warn.find('\n', start);
    const std::string line = warn.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!line.empty()) info.parser_warnings.push_back(file + ": " + line);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  // External image files (tinygltf reads none): each read for its header, one at a time.
  for (std::size_t i = 0; i < m.images.size(); ++i) {
    const tg::Image& im = m.images[i];
    if (im.bufferView >= 0 || !is_external_uri(im.uri)) continue;
    std::vector<unsigned char> encoded;
    const std::string problem = read_external(uri_path(base_dir, im.uri), options.max_file_bytes, options.roots, encoded);
    if (!problem.empty()) {
      info.parser_warnings.push_back(file + ": /images/" + std::to_string(i) + "/uri: " + problem);
      continue;
    }
    headers[static_cast<int>(i)] = image::read_image_header(encoded);
    sizes[static_cast<int>(i)] = encoded.size();
  }
  info.version = m.asset.version;
  info.generator = m.asset.generator;
  info.copyright = m.asset.copyright;
  info.scenes = m.scenes.size();
  info.default_scene = m.defaultScene;
  for (const tg::Scene& s : m.scenes) info.scene_names.push_back(s.name);
  info.nodes = m.nodes.size();
  info.accessors = m.accessors.size();
  info.buffer_views = m.bufferViews.size();
  info.buffers = m.buffers.size();
  for (const tg::Buffer& b : m.buffers) info.buffer_bytes += b.data.size();
  info.samplers = m.samplers.size();
  info.skins = m.skins.size();
  info.animations = m.animations.size();
  for (const tg::Mesh& mesh : m.meshes) {
    GltfMeshInfo mi;
    mi.name = mesh.name;
    for (const tg::Primitive& p : mesh.primitives) {
      GltfPrimitiveInfo pi;
      pi.mode = p.mode;
      pi.material = p.material;
      pi.indexed = p.indices >= 0;
      pi.triangles = primitive_triangles(m, p);
      for (const auto& kv : p.attributes) pi.attributes.push_back(kv.first);
      pi.extensions = keys(p.extensions);
      mi.triangles += pi.triangles;
      mi.morph_targets = std::max(mi.morph_targets, p.targets.size());
      mi.primitives.push_back(std::move(pi));
    }
    info.meshes.push_back(std::move(mi));
  }
  for (const tg::Material& g : m.materials) {
    GltfMaterialInfo mi;
    mi.name = g.name;
    mi.alpha_mode = g.alphaMode.empty() ? "OPAQUE" : g.alphaMode;
    mi.double_sided = g.doubleSided;
    const tg::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    for (const auto& [slot, index] : {std::pair<const char*, int>{"base_color", pbr.baseColorTexture.index},
                                      {"metallic_roughness", pbr.metallicRoughnessTexture.index},
                                      {"normal", g.normalTexture.index},
                                      {"occlusion", g.occlusionTexture.index},
                                      {"emissive", g.emissiveTexture.index}})
      if (index >= 0) mi.textures.emplace_back(slot, index);
    mi.extensions = keys(g.extensions);
    info.materials.push_back(std::move(mi));
  }
  for (const tg::Texture& t : m.textures) info.textures.push_back({t.name, t.source, t.sampler});
  for (std::size_t i = 0; i < m.images.size(); ++i) {
    const tg::Image& im = m.images[i];
    GltfImageInfo ii;
    ii.name = im.name;
    ii.mime_type = im.mimeType;
    // tinygltf keeps no URI for an image it decoded from a data URI.
    if (im.bufferView >= 0) ii.location = "bufferView " + std::to_string(im.bufferView);
    else if (im.uri.empty() || im.uri.rfind("data:", 0) == 0) ii.location = "data URI";
    else ii.location = im.uri;
    if (auto it = headers.find(static_cast<int>(i)); it != headers.end()) {
      ii.format = it->second.format;
      ii.width = it->second.width;
      ii.height = it->second.height;
      ii.detail = it->second.detail;
      ii.bytes = sizes[static_cast<int>(i)];
    }
    info.images.push_back(std::move(ii));
  }
  for (const tg::Camera& c : m.cameras) info.cameras.push_back({c.name, c.type});
  for (const tg::Light& l : m.lights) info.lights.push_back({l.name, l.type});
  info.extensions_used = m.extensionsUsed;
  info.variants = variant_names(m);
  info.extensions_required = m.extensionsRequired;
  return info;
}

void restore_prepass(GltfInfo& info, const tg::Model& m,
                     const std::map<std::pair<std::size_t, std::size_t>, int>& draco_indices,
                     const std::map<int, std::uint64_t>& placeholders) {
  for (const auto& [at, accessor] : draco_indices) {
    const auto [mesh, primitive] = at;
    if (mesh >= info.meshes.size() || primitive >= info.meshes[mesh].primitives.size()) continue;
    GltfMeshInfo& mi = info.meshes[mesh];
    GltfPrimitiveInfo& pi = mi.primitives[primitive];
    mi.triangles -= pi.triangles;
    pi.indexed = true;
    pi.triangles = triangles_of(accessor_count(m, accessor), pi.mode);
    mi.triangles += pi.triangles;
  }
  for (const auto& [index, declared] : placeholders) {
    (void)declared;
    const auto i = static_cast<std::size_t>(index);
    if (i < m.buffers.size()) info.buffer_bytes -= m.buffers[i].data.size();
  }
}

}  // namespace softpbr::pbr::gltf
