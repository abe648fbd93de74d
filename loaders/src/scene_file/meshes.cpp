// Scene files: meshes, procedural shapes or OBJ models, built once each and charged to the
// memory budget (see scene_file/loader.h).
#include "loader.h"

#include "../mtl_textures.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <string>

#include <glm/matrix.hpp>

#include "softpbr/loaders/gltf.h"
#include <functional>
#include <limits>

namespace softpbr::pbr::scene_file {

namespace {

// `mesh` with its node transform applied: positions by M, normals by M's inverse
// transpose (normalised), tangents by M with the handedness flipped when M mirrors (the
// loader already reversed such a mesh's winding).
Mesh baked(const Mesh& mesh, const glm::mat4& m) {
  Mesh out = mesh;
  const glm::mat3 linear(m);
  const glm::mat3 normals = glm::transpose(glm::inverse(linear));
  const float handedness = glm::determinant(linear) < 0.0f ? -1.0f : 1.0f;
  auto unit = [](glm::vec3 v, glm::vec3 fallback) {
    const float len = std::sqrt(glm::dot(v, v));
    return len > 0.0f && std::isfinite(len) ? v / len : fallback;
  };
  for (MeshVertex& v : out.vertices) {
    v.position = glm::vec3(m * glm::vec4(v.position, 1.0f));
    v.normal = unit(normals * v.normal, v.normal);
  }
  for (glm::vec4& t : out.tangents) t = glm::vec4(unit(linear * glm::vec3(t), glm::vec3(t)), t.w * handedness);
  return out;
}

// A glTF model's objects as the shapes of a model (materials one per shape, in order), and
// the bytes of its textures, each counted once.
ObjModel gltf_as_model(const GltfScene& g, std::uint64_t& texture_bytes) {
  ObjModel model;
  model.warnings = g.warnings;
  model.files = g.files;
  std::set<const raster::Texture*> seen;
  for (std::size_t i = 0; i < g.objects.size(); ++i) {
    const Object& o = g.objects[i];
    model.shapes.push_back({"primitive " + std::to_string(i), baked(*o.mesh, o.transform), static_cast<int>(i)});
    model.materials.emplace_back("material " + std::to_string(i), o.material);
    for (const TextureSlot* t : {&o.material.base_color_texture, &o.material.metallic_roughness_texture,
                                 &o.material.normal_texture, &o.material.occlusion_texture, &o.material.emissive_texture})
      if (t->texture && seen.insert(t->texture.get()).second) texture_bytes += t->texture->texel_bytes();
  }
  return model;
}

// pbr::fit_transform of the bounds of all `parts` (the function make_gallery uses too, so
// gallery_spot.json matches it bit for bit).
// Empty when the bounds' extent overflows float (coordinates near ±3e38: the scale would be
// 0, an empty image): the caller says so.
std::optional<glm::mat4> fit_parts(const std::vector<std::shared_ptr<const Mesh>>& parts, float size) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  Bounds all{glm::vec3(inf), glm::vec3(-inf)};
  for (const auto& mesh : parts) all = merge(all, bounds(*mesh));
  const glm::vec3 e = all.extent(), c = all.centre();
  if (!all.empty() && !(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z) && std::isfinite(c.x) &&
                        std::isfinite(c.y) && std::isfinite(c.z)))
    return std::nullopt;
  return pbr::fit_transform(all, size);
}

}  // namespace

std::uint64_t mesh_bytes(std::uint64_t vertices, std::uint64_t triangles) {
  constexpr std::uint64_t kVertexBytes = sizeof(MeshVertex);
  constexpr std::uint64_t kTriangleBytes = 3 * sizeof(decltype(Mesh::indices)::value_type);
  return vertices * kVertexBytes + triangles * kTriangleBytes;
}

void MeshLibrary::define(const Node& meshes) {
  if (!meshes.value.is_object()) r_.fail(meshes, "expected an object of named meshes, got " + json_reader::show(meshes.value));
  named_.emplace(meshes);
  for (const auto& item : meshes.value.items()) {
    const Json name(item.key());
    mesh(Node{name, meshes.pointer});
  }
}

LoadedMesh& MeshLibrary::mesh(const Node& spec) {
  std::string key;
  std::optional<Node> def;
  if (spec.value.is_string()) {
    const std::string name = spec.value.get<std::string>();
    if (!named_ || !named_->value.contains(name))
      r_.fail(spec, "no mesh named " + json_reader::show(spec.value) + " in /meshes");
    key = "#" + name;
    def.emplace(named_->child(name));
  } else {
    key = spec.value.dump();
    def.emplace(spec);
  }
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  return cache_.emplace(key, build(*def)).first->second;
}

LoadedMesh MeshLibrary::build(const Node& spec) {
  if (!spec.value.is_object()) r_.fail(spec, "expected a mesh object or the name of a mesh in /meshes, got " + json_reader::show(spec.value));
  std::optional<float> fit;
  if (auto f = r_.member(spec, "fit")) fit = r_.number_f(*f, 0, 1e30, true);
  LoadedMesh out;
  if (auto file = r_.member(spec, "file")) {
    out = build_obj(spec, *file);
  } else {
    out = build_shape(spec);
  }
  if (fit) {
    const std::optional<glm::mat4> m = fit_parts(out.parts, *fit);
    if (!m) r_.fail(*r_.member(spec, "fit"), "the mesh's bounds span more than float holds (coordinates beyond about +-1.7e38): it cannot be fitted");
    out.fit = *m;
    out.has_fit = true;
  }
  return out;
}

LoadedMesh MeshLibrary::build_obj(const Node& spec, const Node& file) {
  const std::filesystem::path rel = r_.string(file);
  std::string lower = rel.extension().string();
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // A glTF model's animation (its moment and which: pbr::GltfOptions::time, animation) and
  // material variant (an OBJ model's is refused below, by name).
  if (lower == ".gltf" || lower == ".glb") r_.object(spec, {"file", "fit", "variant", "time", "animation", "scene"});
  else r_.object(spec, {"file", "fit", "variant"});
  if (rel.empty()) r_.fail(file, "expected a file name, got \"\"");
  const std::filesystem::path path = rel.is_absolute() ? rel : base_dir_ / rel;
  std::shared_ptr<ObjModel> model;
  // MTL maps load into the scene's cache, bounded by what the budget has left, and are
  // charged once the model is read (its meshes' size is only known then too).
  ObjOptions options;
  options.texture_memory_limit = budget_.left();
  options.roots = textures_.cache().roots();
  options.memory_limit = budget_.left();
  options.missing_images = missing_images_;
  const std::uint64_t textures_before = textures_.bytes();
  std::uint64_t gltf_texture_bytes = 0;
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  // A glTF model's material variant (KHR_materials_variants), by name or index.
  std::string variant;
  const std::optional<Node> variant_key = r_.member(spec, "variant");
  if (variant_key) {
    variant = r_.string(*variant_key);
    if (variant.empty()) r_.fail(*variant_key, "expected a material variant's name or index, got \"\"");
  }
  if (ext == ".gltf" || ext == ".glb") {
    // A glTF model: its primitives become the parts, baked into the model's space by their
    // node transforms, each with its material, like an OBJ's shapes (its lights and cameras
    // are not used here).
    check_at(r_, file, [&] {
      GltfOptions g;
      g.variant = variant;
      g.roots = textures_.cache().roots();
      g.memory_limit = budget_.left();
      g.missing_images = missing_images_;
      if (auto t = r_.member(spec, "time")) g.time = r_.number(*t, -1e9, 1e9);
      if (auto a = r_.member(spec, "animation")) {
        if (a->value.is_string()) g.animation = r_.string(*a);
        else g.animation = std::to_string(r_.integer(*a, 0, 1'000'000'000));
      }
      if (auto sc = r_.member(spec, "scene")) {
        if (sc->value.is_string()) g.scene_name = r_.string(*sc);
        else g.scene_name = std::to_string(r_.integer(*sc, 0, 1'000'000'000));
        if (g.scene_name.empty()) r_.fail(*sc, "expected a scene's name or index, got \"\"");
      }
      if (const std::string problem = detail::outside_roots(path, g.roots); !problem.empty())
        throw LoadError(path.string() + ": " + problem);
      g.image_limits.max_decoded_bytes = std::min<std::uint64_t>(g.image_limits.max_decoded_bytes, budget_.left());
      model = std::make_shared<ObjModel>(gltf_as_model(load_gltf(path, g), gltf_texture_bytes));
    });
  } else {
    if (variant_key) r_.fail(*variant_key, "a glTF model's material variant; an OBJ model has none");
    check_at(r_, file, [&] { model = std::make_shared<ObjModel>(detail::load_obj(path, options, textures_.cache())); });
  }
  for (const std::string& w : model->warnings) warnings_.push_back(w);
  files_.push_back(path.string());
  files_.insert(files_.end(), model->files.begin(), model->files.end());
  LoadedMesh out;
  std::uint64_t v = 0, t = 0;
  for (const ObjShape& s : model->shapes) {
    out.parts.push_back(std::shared_ptr<const Mesh>(model, &s.mesh));
    out.part_material.push_back(s.material);
    v += s.mesh.vertices.size();
    t += s.mesh.triangle_count();
  }
  for (const auto& m : model->materials) out.materials.push_back(m.second);
  out.obj = model;
  budget_.charge(file, textures_.bytes() - textures_before + gltf_texture_bytes, "this model's textures");
  budget_.charge(file, mesh_bytes(v, t), "this model");
  return out;
}

LoadedMesh MeshLibrary::build_shape(const Node& spec) {
  if (!spec.value.contains("type")) r_.fail(spec, "missing key \"type\" (a procedural shape) or \"file\" (an OBJ model)");
  const Node type = r_.required(spec, "type");
  const std::string kind = r_.choice(type, {"uv_sphere", "icosphere", "cube", "plane", "torus"});
  auto num = [&](const char* key, float fallback, double lo, double hi, bool open_lo) {
    auto m = r_.member(spec, key);
    return m ? r_.number_f(*m, lo, hi, open_lo) : fallback;
  };
  auto count = [&](const char* key, int fallback, int lo, int hi) {
    auto m = r_.member(spec, key);
    return m ? static_cast<int>(r_.integer(*m, lo, hi)) : fallback;
  };
  // Vertex and triangle counts are known before the shape is built: check the memory first.
  std::uint64_t v = 0, t = 0;
  std::function<Mesh()> make;
  constexpr double kBig = 1e30;
  if (kind == "uv_sphere") {
    r_.object(spec, {"type", "fit", "radius", "segments", "rings"});
    const float radius = num("radius", 1.0f, 0, kBig, true);
    const int segments = count("segments", 32, 3, 4096), rings = count("rings", std::max(2, segments / 2), 2, 4096);
    v = std::uint64_t(segments + 1) * std::uint64_t(rings + 1), t = 2ull * segments * rings;
    make = [=] { return uv_sphere(radius, segments, rings); };
  } else if (kind == "icosphere") {
    r_.object(spec, {"type", "fit", "radius", "subdivisions"});
    const float radius = num("radius", 1.0f, 0, kBig, true);
    const int n = count("subdivisions", 3, 0, 8);
    t = 20ull << (2 * n), v = 3 * t;
    make = [=] { return icosphere(radius, n); };
  } else if (kind == "cube") {
    r_.object(spec, {"type", "fit", "size"});
    const float size = num("size", 1.0f, 0, kBig, true);
    v = 24, t = 12;
    make = [=] { return cube(size); };
  } else if (kind == "plane") {
    r_.object(spec, {"type", "fit", "width", "depth", "subdivisions"});
    const float w = num("width", 1.0f, 0, kBig, true), d = num("depth", 1.0f, 0, kBig, true);
    const int n = count("subdivisions", 1, 1, 4096);
    v = std::uint64_t(n + 1) * std::uint64_t(n + 1), t = 2ull * n * n;
    make = [=] { return plane(w, d, n); };
  } else {
    r_.object(spec, {"type", "fit", "major", "minor", "segments", "sides"});
    const float major = num("major", 1.0f, 0, kBig, true);
    const float minor = num("minor", 0.25f * major, 0, kBig, true);
    if (!(minor < major)) {
      const auto where = r_.member(spec, "minor");  // present: the default is below major
      r_.fail(where ? where->pointer : spec.pointer, "a torus needs minor < major (" +
                  json_reader::show_number(minor) + " >= " + json_reader::show_number(major) + ")");
    }
    const int segments = count("segments", 48, 3, 4096), sides = count("sides", 24, 3, 4096);
    v = std::uint64_t(segments + 1) * std::uint64_t(sides + 1), t = 2ull * segments * sides;
    make = [=] { return torus(major, minor, segments, sides); };
  }
  budget_.charge(spec, mesh_bytes(v, t), "this mesh");
  LoadedMesh out;
  check_at(r_, spec, [&] { out.parts.push_back(std::make_shared<const Mesh>(make())); });
  out.part_material.push_back(-1);
  return out;
}

}  // namespace softpbr::pbr::scene_file
