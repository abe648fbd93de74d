// JSON scene files (see scene_file.h; the format is docs/scene-format.md).
#include "softpbr/pbr/scene_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <system_error>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "json_reader.h"
#include "softpbr/pbr/obj.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace softpbr::pbr {

using json_reader::Json;
using json_reader::Node;
using json_reader::Reader;

namespace {

// ---- Memory estimates ---------------------------------------------------------------------
// Bytes a mesh's own arrays take (MeshVertex and three indices a triangle).
std::uint64_t mesh_bytes(std::uint64_t vertices, std::uint64_t triangles) {
  constexpr std::uint64_t kVertexBytes = sizeof(MeshVertex);
  constexpr std::uint64_t kTriangleBytes = 3 * sizeof(decltype(Mesh::indices)::value_type);
  return vertices * kVertexBytes + triangles * kTriangleBytes;
}
// Bytes drawing a mesh with the PbrShader holds until the frame is rasterized, as the
// rasterizer counts them.
std::uint64_t draw_bytes(std::uint64_t vertices, std::uint64_t triangles) {
  return raster::draw_geometry_bytes(vertices, triangles, raster::kVaryingCount<PbrShader::Varyings>);
}

// ---- Meshes -------------------------------------------------------------------------------
// A mesh spec once loaded: a procedural shape (one part) or an OBJ model (one part per
// shape, with its MTL materials), and the fit transform.
struct LoadedMesh {
  std::vector<std::shared_ptr<const Mesh>> parts;
  std::vector<int> part_material;      // OBJ: index into materials, −1 none
  std::vector<Material> materials;     // OBJ's MTL materials
  std::shared_ptr<const Mesh> merged;  // all parts in one mesh, made when an object needs it
  std::shared_ptr<const ObjModel> obj; // kept to merge on demand
  glm::mat4 fit{1.0f};
  bool has_fit = false;
};

// pbr::fit_transform of the bounds of all `parts` (the function make_gallery uses too, so
// gallery_spot.json matches it bit for bit).
glm::mat4 fit_parts(const std::vector<std::shared_ptr<const Mesh>>& parts, float size) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  Bounds all{glm::vec3(inf), glm::vec3(-inf)};
  for (const auto& mesh : parts) all = merge(all, bounds(*mesh));
  return pbr::fit_transform(all, size);
}

class Loader {
 public:
  Loader(const Reader& reader, std::filesystem::path base_dir, const SceneLoadOptions& options)
      : r_(reader), base_dir_(std::move(base_dir)), options_(options) {}

  SceneFile load(const Node& root);

 private:
  void charge(const Node& where, std::uint64_t bytes, const char* what);
  LoadedMesh& mesh(const Node& spec);
  LoadedMesh build_mesh(const Node& spec);
  Material material(const Node& spec);
  Light light(const Node& spec);
  Camera camera(const Node& spec);
  glm::mat4 transform(const Node& spec);
  void object(const Node& spec, SceneFile& out);
  void render(const Node& spec, SceneFile& out);
  void animation(const Node& spec, Animation& out);

  const Reader& r_;
  std::filesystem::path base_dir_;
  SceneLoadOptions options_;
  std::optional<Node> named_meshes_;
  std::map<std::string, LoadedMesh> cache_;  // by name ("#name") or by the spec's JSON text
  std::uint64_t bytes_ = 0;
  std::vector<std::string> warnings_;
};

void Loader::charge(const Node& where, std::uint64_t bytes, const char* what) {
  bytes_ += bytes;
  if (bytes_ > options_.memory_limit)
    r_.fail(where, std::string(what) + " brings the scene's estimated memory to " + format_bytes(bytes_) +
                       ", over the limit of " + format_bytes(options_.memory_limit));
}

LoadedMesh& Loader::mesh(const Node& spec) {
  std::string key;
  std::optional<Node> def;
  if (spec.value.is_string()) {
    const std::string name = spec.value.get<std::string>();
    if (!named_meshes_ || !named_meshes_->value.contains(name))
      r_.fail(spec, "no mesh named " + json_reader::show(spec.value) + " in /meshes");
    key = "#" + name;
    def.emplace(named_meshes_->child(name));
  } else {
    key = spec.value.dump();
    def.emplace(spec);
  }
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  return cache_.emplace(key, build_mesh(*def)).first->second;
}

LoadedMesh Loader::build_mesh(const Node& spec) {
  if (!spec.value.is_object()) r_.fail(spec, "expected a mesh object or the name of a mesh in /meshes, got " + json_reader::show(spec.value));
  LoadedMesh out;
  std::optional<float> fit;
  if (auto f = r_.member(spec, "fit")) fit = r_.number_f(*f, 0, 1e30, true);

  if (auto file = r_.member(spec, "file")) {
    r_.object(spec, {"file", "fit"});
    const std::filesystem::path rel = r_.string(*file);
    if (rel.empty()) r_.fail(*file, "expected a file name, got \"\"");
    const std::filesystem::path path = rel.is_absolute() ? rel : base_dir_ / rel;
    std::shared_ptr<ObjModel> model;
    try {
      model = std::make_shared<ObjModel>(load_obj(path));
    } catch (const std::exception& e) {
      r_.fail(*file, e.what());
    }
    for (const std::string& w : model->warnings) warnings_.push_back(w);
    std::uint64_t v = 0, t = 0;
    for (const ObjShape& s : model->shapes) {
      out.parts.push_back(std::shared_ptr<const Mesh>(model, &s.mesh));
      out.part_material.push_back(s.material);
      v += s.mesh.vertices.size();
      t += s.mesh.triangle_count();
    }
    for (const auto& m : model->materials) out.materials.push_back(m.second);
    out.obj = model;
    charge(*file, mesh_bytes(v, t), "this model");
  } else {
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
    charge(spec, mesh_bytes(v, t), "this mesh");
    try {
      out.parts.push_back(std::make_shared<const Mesh>(make()));
    } catch (const std::exception& e) {
      r_.fail(spec, e.what());
    }
    out.part_material.push_back(-1);
  }
  if (fit) {
    out.fit = fit_parts(out.parts, *fit);
    out.has_fit = true;
  }
  return out;
}

Material Loader::material(const Node& spec) {
  if (spec.value.is_string()) {
    const auto preset = material_preset(spec.value.get<std::string>());
    if (!preset) {
      std::vector<std::string> names;
      for (const NamedMaterial& m : material_presets()) names.emplace_back(m.name);
      r_.choice(spec, names);  // fails with the list of presets
    }
    return *preset;
  }
  r_.object(spec, {"preset", "base_color", "metallic", "roughness", "ao", "emissive"});
  Material m;
  if (auto p = r_.member(spec, "preset")) {
    if (!p->value.is_string()) r_.fail(*p, "expected a preset name, got " + json_reader::show(p->value));
    m = material(*p);
  }
  if (auto c = r_.member(spec, "base_color")) m.base_color = r_.vec3(*c, 0, 1);
  if (auto c = r_.member(spec, "metallic")) m.metallic = r_.number_f(*c, 0, 1);
  if (auto c = r_.member(spec, "roughness")) m.roughness = r_.number_f(*c, 0, 1);
  if (auto c = r_.member(spec, "ao")) m.ao = r_.number_f(*c, 0, 1);
  if (auto c = r_.member(spec, "emissive")) m.emissive = r_.vec3(*c, 0, 1e30);
  return m;
}

Light Loader::light(const Node& spec) {
  r_.object(spec, {"type", "position", "direction", "color", "intensity", "range", "inner_cone", "outer_cone"});
  Light l;
  const std::string type = r_.choice(r_.required(spec, "type"), {"point", "directional", "spot"});
  l.type = type == "point" ? LightType::Point : type == "directional" ? LightType::Directional : LightType::Spot;
  auto only = [&](const char* key, bool allowed) -> std::optional<Node> {
    auto m = r_.member(spec, key);
    if (m && !allowed) r_.fail(*m, "a " + type + " light has no \"" + key + "\"");
    return m;
  };
  const bool positioned = l.type != LightType::Directional, aimed = l.type != LightType::Point;
  if (auto p = only("position", positioned)) l.position = r_.vec3(*p);
  else if (positioned) r_.required(spec, "position");
  if (auto d = only("direction", aimed)) {
    l.direction = r_.vec3(*d);
    if (l.direction == glm::vec3(0.0f)) r_.fail(*d, "expected a non-zero direction, got [0, 0, 0]");
  } else if (aimed) {
    r_.required(spec, "direction");
  }
  if (auto c = r_.member(spec, "color")) l.color = r_.vec3(*c, 0, 1e30);
  if (auto i = r_.member(spec, "intensity")) l.intensity = r_.number_f(*i, 0, 1e30);
  if (auto g = only("range", positioned)) l.range = r_.number_f(*g, 0, 1e30);
  // Cone angles in degrees, from the spot's axis: 0 <= inner <= outer, 0 < outer <= 90.
  double inner = 0.0, outer = 45.0;
  std::optional<Node> outer_node = only("outer_cone", l.type == LightType::Spot);
  if (auto i = only("inner_cone", l.type == LightType::Spot)) inner = r_.number(*i, 0, 90);
  if (outer_node) outer = r_.number(*outer_node, 0, 90, true);
  if (inner > outer) r_.fail(r_.required(spec, "inner_cone"), "expected inner_cone <= outer_cone (" + json_reader::show_number(outer) + "), got " + json_reader::show_number(inner));
  l.inner_cone = static_cast<float>(dmath::radians(inner));
  l.outer_cone = static_cast<float>(dmath::radians(outer));
  try {
    prepare_light(l);
  } catch (const std::exception& e) {
    r_.fail(spec, e.what());
  }
  return l;
}

Camera Loader::camera(const Node& spec) {
  Camera c;
  const bool orbit = spec.value.is_object() && spec.value.contains("distance");
  if (orbit) {
    r_.object(spec, {"target", "distance", "yaw", "pitch", "fov", "near", "far"});
    OrbitCamera o;
    if (auto t = r_.member(spec, "target")) o.target = r_.vec3(*t);
    o.distance = r_.number_f(r_.required(spec, "distance"), 0, 1e18, true);  // validate(): < 1e19
    if (auto y = r_.member(spec, "yaw")) o.yaw = static_cast<float>(dmath::radians(r_.number(*y, -360, 360)));
    if (auto p = r_.member(spec, "pitch")) o.pitch = static_cast<float>(dmath::radians(r_.number(*p, -89, 89)));
    c = o.camera();
  } else {
    r_.object(spec, {"position", "target", "up", "fov", "near", "far"});
    if (auto p = r_.member(spec, "position")) c.position = r_.vec3(*p);
    if (auto t = r_.member(spec, "target")) c.target = r_.vec3(*t);
    if (auto u = r_.member(spec, "up")) c.up = r_.vec3(*u);
  }
  if (auto f = r_.member(spec, "fov")) c.fovy = static_cast<float>(dmath::radians(r_.number(*f, 0, 180, true, true)));
  if (auto n = r_.member(spec, "near")) c.near = r_.number_f(*n, 0, 1e30, true);
  if (auto f = r_.member(spec, "far")) c.far = r_.number_f(*f, 0, 1e30, true);
  try {
    validate(c);
  } catch (const std::exception& e) {
    r_.fail(spec, e.what());
  }
  return c;
}

// Rotation about one axis by `degrees` (0 x, 1 y, 2 z), sine and cosine from dmath.
glm::mat4 axis_rotation(int axis, double degrees) {
  const double angle = static_cast<float>(dmath::radians(degrees));
  const float c = static_cast<float>(dmath::cos(angle)), s = static_cast<float>(dmath::sin(angle));
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane the rotation turns
  glm::mat4 m(1.0f);
  m[i][i] = c;
  m[i][j] = s;
  m[j][i] = -s;
  m[j][j] = c;
  return m;
}

glm::mat4 Loader::transform(const Node& spec) {
  if (auto m = r_.member(spec, "matrix")) {
    r_.object(spec, {"matrix"});
    if (!m->value.is_array() || m->value.size() != 4)
      r_.fail(*m, "expected 4 rows of 4 numbers, got " + json_reader::show(m->value));
    glm::mat4 out;
    for (int row = 0; row < 4; ++row) {
      const std::vector<float> v = r_.numbers(m->at(row), 4, -1e30, 1e30);
      for (int col = 0; col < 4; ++col) out[col][row] = v[col];  // glm is column-major
    }
    if (out[0][3] != 0 || out[1][3] != 0 || out[2][3] != 0 || out[3][3] != 1)
      r_.fail(m->pointer + "/3", "expected the last row to be [0, 0, 0, 1] (an affine transform), got " + json_reader::show(m->value.at(3)));
    const float det = glm::determinant(glm::mat3(out));
    if (!std::isfinite(det) || det == 0.0f) r_.fail(*m, "expected an invertible matrix, its 3x3 part has determinant " + json_reader::show_number(det));
    return out;
  }
  r_.object(spec, {"translate", "rotate", "scale", "matrix"});
  // M = T · Rz · Ry · Rx · S (scale first, then rotate x, y, z, then translate); factors not
  // given are skipped, not multiplied as identities.
  glm::mat4 out(1.0f);
  bool any = false;
  auto apply = [&](const glm::mat4& m) { out = any ? m * out : m, any = true; };
  if (auto s = r_.member(spec, "scale")) {
    glm::vec3 v;
    if (s->value.is_number()) v = glm::vec3(r_.number_f(*s, 0, 1e30, true));
    else v = r_.vec3(*s, -1e30, 1e30);
    if (v.x == 0 || v.y == 0 || v.z == 0) r_.fail(*s, "expected non-zero scale factors, got " + json_reader::show(s->value));
    apply(glm::scale(glm::mat4(1.0f), v));
  }
  if (auto rot = r_.member(spec, "rotate")) {
    const std::vector<float> deg = r_.numbers(*rot, 3, -360, 360);
    const double exact[3] = {rot->value[0].get<double>(), rot->value[1].get<double>(), rot->value[2].get<double>()};
    for (int axis = 0; axis < 3; ++axis)
      if (deg[axis] != 0.0f) apply(axis_rotation(axis, exact[axis]));
  }
  if (auto t = r_.member(spec, "translate")) apply(glm::translate(glm::mat4(1.0f), r_.vec3(*t)));
  return out;
}

void Loader::object(const Node& spec, SceneFile& out) {
  r_.object(spec, {"name", "mesh", "material", "transform"});
  if (auto n = r_.member(spec, "name")) r_.string(*n);
  LoadedMesh& m = mesh(r_.required(spec, "mesh"));
  const glm::mat4 placed = [&] {
    const auto t = r_.member(spec, "transform");
    if (!t) return m.fit;
    const glm::mat4 tr = transform(*t);
    return m.has_fit ? tr * m.fit : tr;
  }();
  auto add = [&](std::shared_ptr<const Mesh> mesh, const Material& material, const Node& where) {
    if (out.scene.objects.size() >= kMaxObjects)
      r_.fail(where, "too many objects to draw (the limit is " + std::to_string(kMaxObjects) + ": each is a draw call)");
    charge(where, draw_bytes(mesh->vertices.size(), mesh->triangle_count()), "drawing this object");
    out.triangles += mesh->triangle_count();
    out.scene.objects.push_back({std::move(mesh), material, placed});
  };
  if (auto mat = r_.member(spec, "material")) {
    const Material material = this->material(*mat);
    if (m.parts.size() == 1) {
      add(m.parts[0], material, spec);
    } else {
      // One material for a whole OBJ model: draw its shapes merged, as make_gallery does.
      LoadedMesh& entry = m;
      if (!entry.merged) {
        auto merged = std::make_shared<const Mesh>(merge_shapes(*entry.obj));
        charge(spec, mesh_bytes(merged->vertices.size(), merged->triangle_count()), "merging this model");
        entry.merged = merged;
      }
      add(entry.merged, material, spec);
    }
  } else {
    for (std::size_t i = 0; i < m.parts.size(); ++i) {
      const int k = m.part_material[i];
      add(m.parts[i], k >= 0 ? m.materials[static_cast<std::size_t>(k)] : Material{}, spec);
    }
  }
}

void Loader::render(const Node& spec, SceneFile& out) {
  r_.object(spec, {"width", "height", "tonemap", "exposure", "gamma", "background", "threads", "tile_size"});
  RenderSettings& s = out.render;
  if (auto w = r_.member(spec, "width")) s.width = static_cast<int>(r_.integer(*w, 1, raster::kMaxTargetSize));
  if (auto h = r_.member(spec, "height")) s.height = static_cast<int>(r_.integer(*h, 1, raster::kMaxTargetSize));
  if (auto t = r_.member(spec, "tonemap"))
    s.output.tone_map = *tone_map_from_name(r_.choice(*t, {"none", "reinhard", "aces", "neutral"}));
  if (auto e = r_.member(spec, "exposure")) s.output.exposure = r_.number_f(*e, -64, 64);
  if (auto g = r_.member(spec, "gamma")) {
    if (g->value.is_string() && g->value.get<std::string>() == "srgb") s.output.gamma = 0.0f;
    else if (g->value.is_number()) s.output.gamma = r_.number_f(*g, 0.1, 10);
    else r_.fail(*g, "expected \"srgb\" or a number in [0.1, 10], got " + json_reader::show(g->value));
  }
  if (auto b = r_.member(spec, "background")) {
    if (b->value.is_array() && b->value.size() == 4) {
      const std::vector<float> v = r_.numbers(*b, 4, 0, 1e30);
      out.scene.background = {v[0], v[1], v[2], v[3]};
    } else {
      out.scene.background = glm::vec4(r_.vec3(*b, 0, 1e30), 1.0f);
    }
  }
  if (auto t = r_.member(spec, "threads")) s.threads = static_cast<unsigned>(r_.integer(*t, 0, 1024));
  if (auto t = r_.member(spec, "tile_size")) {
    s.tile_size = static_cast<int>(r_.integer(*t, raster::kMinTileSize, raster::kMaxTileSize));
    if (!raster::valid_tile_size(s.tile_size)) r_.fail(*t, "expected an even tile size, got " + std::to_string(s.tile_size));
  }
}

void Loader::animation(const Node& spec, Animation& a) {
  r_.object(spec, {"camera_degrees_per_frame", "light_degrees_per_frame", "light_pivot"});
  if (auto c = r_.member(spec, "camera_degrees_per_frame")) a.camera_degrees_per_frame = r_.number(*c, -360, 360);
  if (auto l = r_.member(spec, "light_degrees_per_frame")) a.light_degrees_per_frame = r_.number(*l, -360, 360);
  if (auto p = r_.member(spec, "light_pivot")) a.light_pivot = r_.vec3(*p);
}

SceneFile Loader::load(const Node& root) {
  r_.object(root, {"camera", "lights", "ambient", "meshes", "objects", "render", "animation"});
  SceneFile out;
  if (auto c = r_.member(root, "camera")) out.scene.camera = camera(*c);
  if (auto a = r_.member(root, "ambient")) out.scene.ambient = r_.vec3(*a, 0, 1e30);
  if (auto r = r_.member(root, "render")) render(*r, out);
  if (auto a = r_.member(root, "animation")) animation(*a, out.animation);
  if (auto l = r_.member(root, "lights")) {
    const std::size_t n = r_.array(*l, kMaxLights, "every light is evaluated at every pixel");
    for (std::size_t i = 0; i < n; ++i) out.scene.lights.push_back(light(l->at(i)));
  }
  if (auto m = r_.member(root, "meshes")) {
    if (!m->value.is_object()) r_.fail(*m, "expected an object of named meshes, got " + json_reader::show(m->value));
    named_meshes_.emplace(*m);
    // Build every named mesh now, so an unused one is still checked.
    for (const auto& item : m->value.items()) {
      const Json name(item.key());
      mesh(Node{name, m->pointer});
    }
  }
  const Node objects = r_.required(root, "objects");
  const std::size_t n = r_.array(objects, kMaxObjects, "each object is a draw call");
  for (std::size_t i = 0; i < n; ++i) object(objects.at(i), out);
  out.mesh_bytes = bytes_;
  out.warnings = std::move(warnings_);
  return out;
}

SceneFile parse(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                const SceneLoadOptions& options) {
  const Reader reader(name);
  if (const auto problem = json_reader::find_structure_problem(text)) reader.fail(problem->pointer, problem->message);
  Json root;
  try {
    // Comments (// and /* */) are accepted as an extension; see docs/scene-format.md.
    root = Json::parse(text.begin(), text.end(), nullptr, true, true);  // depth checked above
  } catch (const Json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 3, column 5: …" → drop the tag.
    std::string what = e.what();
    if (const auto close = what.find("] "); what.rfind("[json.exception", 0) == 0 && close != std::string::npos)
      what = what.substr(close + 2);
    for (char& c : what)
      if (static_cast<unsigned char>(c) < 0x20) c = '?';  // one line
    throw SceneFileError(name + ": invalid JSON: " + what);
  }
  Loader loader(reader, base_dir, options);
  return loader.load(Node{root, ""});
}

}  // namespace

SceneFile parse_scene_file(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                           const SceneLoadOptions& options) {
  try {
    return parse(text, name, base_dir, options);
  } catch (const json_reader::Error& e) {
    throw SceneFileError(e.what());  // the reader's line as is: "FILE: /pointer: what"
  }
}

SceneFile load_scene_file(const std::filesystem::path& path, const SceneLoadOptions& options) {
  const std::string name = path.string();
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw SceneFileError(name + ": is a folder, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneFileError(name + ": cannot open the scene file: " + std::generic_category().message(errno));
  const auto size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxSceneFileBytes)
    throw SceneFileError(name + ": the scene file is " + format_bytes(size) + ", over the limit of " +
                         format_bytes(kMaxSceneFileBytes) + " (meshes belong in OBJ files)");
  // Read at most one byte past the limit: a device or a pipe has no size to check first.
  std::string text;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > kMaxSceneFileBytes)
      throw SceneFileError(name + ": the scene file is over the limit of " + format_bytes(kMaxSceneFileBytes) +
                           " (meshes belong in OBJ files)");
  }
  if (in.bad()) throw SceneFileError(name + ": cannot read the scene file");
  return parse_scene_file(text, name, path.parent_path(), options);
}

std::uint64_t image_memory(int width, int height) {
  // Target colour (16) + depth (4), then the largest output's buffers, one output at a
  // time: PNG 8 (Image8 + encoding), .hdr 16 (float RGB + RGBE), .exr up to 52 (four float
  // planes and tinyexr's compression buffers). Measured peak resident memory of a 2048²
  // render of lights.json: 30 bytes a pixel with .png, 34 with .hdr, 50 with .exr.
  constexpr std::uint64_t kBytesPerPixel = 72;
  return static_cast<std::uint64_t>(std::max(width, 0)) * static_cast<std::uint64_t>(std::max(height, 0)) *
         kBytesPerPixel;
}

std::string format_bytes(std::uint64_t bytes) {
  char buf[32];
  if (bytes >= (std::uint64_t{1} << 30)) std::snprintf(buf, sizeof buf, "%.1f GiB", static_cast<double>(bytes) / (1 << 30));
  else if (bytes >= (std::uint64_t{1} << 20)) std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  else if (bytes >= 1024) std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(bytes) / 1024);
  else std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
  return buf;
}

}  // namespace softpbr::pbr
