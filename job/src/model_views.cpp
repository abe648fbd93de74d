// A model seen from several views (see model_views.h).
#include "softpbr/job/model_views.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <memory>
#include <new>
#include <set>
#include <stdexcept>

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/environment.h"

namespace softpbr::job {

namespace fs = std::filesystem;

namespace {

constexpr float kRingPitch = 15.0f;  // pbr::kDefaultPitch: the automatic camera's front
constexpr float kTopPitch = 89.0f;   // the highest pitch framing_camera takes

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
std::string vec(glm::vec3 v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }
std::string vec(glm::vec4 v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ", " + num(v.w) + ")"; }
std::string bounds_text(const pbr::Bounds& b) { return b.empty() ? "(empty)" : vec(b.min) + " to " + vec(b.max); }
std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? "none" : out;
}

// A material's factors as drawn (pbr::Material): what a changed baseColorFactor,
// metallicFactor or emissiveFactor changes.
std::string factors(const pbr::Material& m) {
  std::string s = "base_color " + vec(glm::vec4(m.base_color, m.alpha)) + " metallic " + num(m.metallic) + " roughness " +
                  num(m.roughness) + " emissive " + vec(m.emissive);
  if (m.alpha_mode == pbr::AlphaMode::Mask) s += " mask " + num(m.alpha_cutoff);
  if (m.alpha_mode == pbr::AlphaMode::Blend) s += " blend";
  if (m.double_sided) s += " double-sided";
  if (m.unlit) s += " unlit";
  auto slot = [&](const char* name, const pbr::TextureSlot& t) {
    if (t) s += std::string(" ") + name + " " + std::to_string(t.texture->width()) + "x" + std::to_string(t.texture->height());
  };
  slot("base_color_texture", m.base_color_texture);
  slot("metallic_roughness_texture", m.metallic_roughness_texture);
  slot("normal_texture", m.normal_texture);
  slot("occlusion_texture", m.occlusion_texture);
  slot("emissive_texture", m.emissive_texture);
  return s;
}

using Rows = std::vector<std::pair<std::string, std::string>>;

// What every kind of input has: what is drawn, where, and with which materials.
void add_drawn(Rows& rows, const pbr::LoadedScene& f, const pbr::Bounds& b) {
  std::uint64_t vertices = 0;
  std::set<const pbr::Mesh*> seen;
  for (const pbr::Object& o : f.scene.objects)
    if (o.mesh && seen.insert(o.mesh.get()).second) vertices += o.mesh->vertices.size();
  rows.emplace_back("drawn objects", std::to_string(f.scene.objects.size()));
  rows.emplace_back("drawn triangles", std::to_string(f.triangles));
  rows.emplace_back("vertices", std::to_string(vertices) + " (each mesh once)");
  rows.emplace_back("bounds", bounds_text(b));
  rows.emplace_back("size", b.empty() ? "(empty)" : vec(b.extent()));
  rows.emplace_back("lights", std::to_string(f.scene.lights.size()));
  for (std::size_t i = 0; i < f.scene.objects.size(); ++i)
    rows.emplace_back("object " + std::to_string(i) + " material", factors(f.scene.objects[i].material));
  rows.emplace_back("texture memory", pbr::format_bytes(f.texture_bytes));
  rows.emplace_back("warnings", std::to_string(f.warnings.size()));
}

void add_gltf_rows(Rows& rows, const pbr::GltfInfo& info) {
  rows.emplace_back("format", "glTF " + info.version);
  rows.emplace_back("generator", info.generator.empty() ? "(none)" : info.generator);
  rows.emplace_back("nodes", std::to_string(info.nodes));
  rows.emplace_back("meshes", std::to_string(info.meshes.size()));
  rows.emplace_back("primitives", std::to_string(info.primitives()));
  rows.emplace_back("triangles", std::to_string(info.triangles()) + " (each mesh once)");
  rows.emplace_back("materials", std::to_string(info.materials.size()));
  for (std::size_t i = 0; i < info.materials.size(); ++i) {
    const pbr::GltfMaterialInfo& m = info.materials[i];
    std::string s = (m.name.empty() ? "(unnamed)" : m.name) + ", " + m.alpha_mode + (m.double_sided ? ", double-sided" : "");
    for (const auto& [slot, index] : m.textures) s += ", " + slot + " texture " + std::to_string(index);
    if (!m.extensions.empty()) s += ", " + join(m.extensions);
    rows.emplace_back("material " + std::to_string(i), s);
  }
  rows.emplace_back("textures", std::to_string(info.textures.size()));
  for (std::size_t i = 0; i < info.textures.size(); ++i) {
    const int source = info.textures[i].source;
    std::string s = "no image";
    if (source >= 0 && static_cast<std::size_t>(source) < info.images.size()) {
      const pbr::GltfImageInfo& im = info.images[static_cast<std::size_t>(source)];
      s = (im.format.empty() ? std::string("unknown format") : im.format) + " " +
          (im.width > 0 ? std::to_string(im.width) + "x" + std::to_string(im.height) : "size unknown") + ", " +
          pbr::format_bytes(im.bytes) + (im.detail.empty() ? "" : " (" + im.detail + ")");
    }
    rows.emplace_back("texture " + std::to_string(i), s);
  }
  rows.emplace_back("extensions used", join(info.extensions_used));
  rows.emplace_back("extensions required", join(info.extensions_required));
  rows.emplace_back("cameras", std::to_string(info.cameras.size()));
  rows.emplace_back("skins, animations", std::to_string(info.skins) + ", " + std::to_string(info.animations));
}

// The studio (or the settings' environment) around a model of its own: as a glTF model is shown.
void light_model(pbr::LoadedScene& f, const Settings& s, raster::ThreadPool& pool) {
  f.scene.ambient = glm::vec3(pbr::kDefaultAmbient);
  f.scene.background = {0.05f, 0.05f, 0.06f, 1.0f};
  if (!s.env || *s.env != "none") {
    f.scene.environment.map = pbr::Environment::studio(&pool);
    f.scene.background_mode = pbr::BackgroundMode::Blur;
    f.environment_bytes = f.scene.environment.map->bytes();
  }
}

}  // namespace

std::vector<View> default_views(int count) {
  if (count < 1 || count > kMaxViews)
    throw Error(Error::Kind::Setting, "views", "expected 1 to " + std::to_string(kMaxViews) + " views, got " + std::to_string(count));
  std::vector<View> views{{0.0f, kRingPitch}};
  const int ring = count - 1 > 0 ? count - 1 : 1;  // the ring's views, the front included
  for (int k = 1; k + 1 < count; ++k) views.push_back({static_cast<float>(360.0 * k / ring), kRingPitch});
  if (count >= 2) views.push_back({0.0f, kTopPitch});
  return views;
}

std::vector<View> views_from_angles(const std::vector<float>& yaws, const std::vector<float>& pitches) {
  const std::size_t n = std::max<std::size_t>({yaws.size(), pitches.size(), 1});
  if (n > static_cast<std::size_t>(kMaxViews))
    throw Error(Error::Kind::Setting, "views", std::to_string(n) + " views, over the limit of " + std::to_string(kMaxViews));
  for (const auto* list : {&yaws, &pitches})
    if (list->size() > 1 && list->size() != n)
      throw Error(Error::Kind::Setting, list == &yaws ? "yaw" : "pitch",
                  "expected one angle or as many as the other list (" + std::to_string(n) + "), got " +
                      std::to_string(list->size()));
  std::vector<View> views;
  for (std::size_t i = 0; i < n; ++i) {
    View v;
    if (!yaws.empty()) v.yaw = yaws[yaws.size() == 1 ? 0 : i];
    if (!pitches.empty()) v.pitch = pitches[pitches.size() == 1 ? 0 : i];
    if (!std::isfinite(v.yaw)) throw Error(Error::Kind::Setting, "yaw", "expected finite numbers of degrees");
    if (!(v.pitch >= -89.0f && v.pitch <= 89.0f))
      throw Error(Error::Kind::Setting, "pitch", "expected degrees in [-89, 89], got " + num(v.pitch));
    views.push_back(v);
  }
  return views;
}

ViewedModel load_viewed(const std::string& input, const Settings& s, raster::ThreadPool& pool) {
  ViewedModel m;
  const std::string ext = lower_extension(input);
  try {
    if (ext == ".gltf" || ext == ".glb") {
      pbr::GltfModelInfo loaded = pbr::load_and_inspect_gltf(input, {.pool = &pool,
                                                                     .memory_limit = requested_memory_limit(s),
                                                                     .roots = s.roots,
                                                                     .missing_images = missing_images(s),
                                                                     .variant = s.variant.value_or(""),
                                                                     .time = s.time,
                                                                     .animation = s.animation.value_or("")});
      add_gltf_rows(m.summary, loaded.info);
      pbr::GltfView view;
      view.width = static_cast<int>(s.width.value_or(512));
      view.height = static_cast<int>(s.height.value_or(512));
      view.environment = !s.env || *s.env != "none";
      view.pool = &pool;
      m.light_rig = !view.environment && loaded.scene.lights.empty();
      std::vector<std::string> files = loaded.scene.files;
      m.scene = pbr::gltf_scene_file(std::move(loaded.scene), view, input);
      m.scene.inputs = std::move(files);
    } else if (ext == ".obj") {
      pbr::ObjOptions options;
      options.roots = s.roots;
      options.memory_limit = requested_memory_limit(s);
      options.texture_memory_limit = requested_memory_limit(s);
      options.missing_images = missing_images(s);
      auto model = std::make_shared<pbr::ObjModel>(pbr::load_obj(input, options));
      pbr::LoadedScene& f = m.scene;
      f.warnings = model->warnings;
      f.inputs = model->files;
      for (const pbr::ObjShape& shape : model->shapes) {
        pbr::Object o;
        o.mesh = std::shared_ptr<const pbr::Mesh>(model, &shape.mesh);
        if (shape.material >= 0) o.material = model->materials[static_cast<std::size_t>(shape.material)].second;
        f.triangles += shape.mesh.triangle_count();
        f.scene.objects.push_back(std::move(o));
      }
      std::set<const void*> counted;
      for (const pbr::Object& o : f.scene.objects) pbr::count_object_memory(f, o, counted);
      f.texture_bytes = model->texture_bytes;
      light_model(f, s, pool);
      m.light_rig = !f.scene.environment.map;
      m.summary.emplace_back("format", "OBJ");
      m.summary.emplace_back("shapes", std::to_string(model->shapes.size()));
      m.summary.emplace_back("materials", std::to_string(model->materials.size()));
      for (std::size_t i = 0; i < model->materials.size(); ++i)
        m.summary.emplace_back("material " + std::to_string(i), model->materials[i].first);
    } else {
      m.scene = pbr::load_scene_file(input, {.memory_limit = requested_memory_limit(s),
                                             .pool = &pool,
                                             .environment_cache = s.env_cache,
                                             .roots = s.roots,
                                             .missing_images = missing_images(s)});
      m.summary.emplace_back("format", "scene file");
    }
  } catch (const std::bad_alloc&) {
    throw Error(Error::Kind::Memory, "", input + ": out of memory while loading it (the process's memory or address-space limit)");
  }
  apply_environment(m.scene, s, pool);
  if (m.light_rig && m.scene.scene.environment.map) m.light_rig = false;  // --env given over a rig
  m.bounds = pbr::world_bounds(m.scene.scene.objects);
  add_drawn(m.summary, m.scene, m.bounds);
  return m;
}

pbr::Camera view_camera(const pbr::Bounds& b, int width, int height, View v, const std::string& what) {
  const auto finite3 = [](glm::vec3 p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); };
  if (!b.empty() && (!finite3(b.min) || !finite3(b.max)))
    throw Error(Error::Kind::Input, "", what + ": the views cannot frame bounds beyond float's range");
  // Yaw reduced into [0, 360) in double (exact: x − 360·floor(x/360) for |x| far below 2^52).
  double yaw = v.yaw;
  if (!(yaw >= 0.0 && yaw < 360.0)) {
    if (!(std::fabs(yaw) < 1e15)) throw Error(Error::Kind::Setting, "yaw", "expected degrees within ±1e15, got " + num(yaw));
    yaw -= 360.0 * std::floor(yaw / 360.0);
  }
  const pbr::Camera c = pbr::framing_camera(b, static_cast<float>(width) / static_cast<float>(height),
                                            static_cast<float>(dmath::radians(yaw)), static_cast<float>(dmath::radians(v.pitch)));
  try {
    pbr::validate(c);
  } catch (const std::invalid_argument& e) {
    throw Error(Error::Kind::Input, "", what + ": the views cannot frame the bounds " + bounds_text(b) + " in float precision (" +
                                            e.what() + ")");
  }
  return c;
}

pbr::Scene scene_for_view(const ViewedModel& model, const pbr::Camera& camera) {
  pbr::Scene s = model.scene.scene;
  s.camera = camera;
  if (model.light_rig) s.lights = pbr::default_light_rig(camera);
  return s;
}

}  // namespace softpbr::job
