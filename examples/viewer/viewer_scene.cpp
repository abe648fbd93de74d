// Viewer state → scene → image (see viewer_scene.h).
#include "viewer_scene.h"

#include <algorithm>

#include <cctype>
#include <cstdio>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/material.h"
#include "softpbr/pbr/tonemap.h"

namespace viewer {

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {
std::shared_ptr<const pbr::Mesh> load_merged(const std::filesystem::path& file, std::vector<std::string>& warnings) {
  const pbr::ObjModel model = pbr::load_obj(file);
  warnings.insert(warnings.end(), model.warnings.begin(), model.warnings.end());
  auto mesh = std::make_shared<pbr::Mesh>(pbr::merge_shapes(model));
  if (mesh->triangle_count() == 0) throw pbr::LoadError(file.string() + ": has no triangles to show");
  return mesh;
}

// Turns a mesh a quarter turn about the x axis, (x, y, z) → (x, −z, y): exact, no rounding.
// A torus around the y axis, seen from the gallery's camera, is a thin edge; stood up it
// shows its hole.
pbr::Mesh stand_up(pbr::Mesh mesh) {
  for (pbr::MeshVertex& v : mesh.vertices) {
    v.position = {v.position.x, -v.position.z, v.position.y};
    v.normal = {v.normal.x, -v.normal.z, v.normal.y};
  }
  // A rotation keeps the handedness: w stays.
  for (glm::vec4& t : mesh.tangents) t = {t.x, -t.z, t.y, t.w};
  return mesh;
}

bool is_gltf(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb";
}

// Turns a point about the y axis by `angle` radians, with deterministic sin and cos.
glm::vec3 turn_about_y(glm::vec3 p, float angle) {
  const float c = static_cast<float>(softpbr::dmath::cos(angle));
  const float s = static_cast<float>(softpbr::dmath::sin(angle));
  return {c * p.x + s * p.z, p.y, -s * p.x + c * p.z};
}
}  // namespace

namespace {
NamedMesh load_model_variant(const std::filesystem::path& file, std::vector<std::string>& warnings,
                             raster::ThreadPool* pool, const std::string& variant) {
  if (!is_gltf(file)) return {file.stem().string(), load_merged(file, warnings)};
  pbr::GltfScene g = pbr::load_gltf(file, {.pool = pool, .variant = variant});
  warnings.insert(warnings.end(), g.warnings.begin(), g.warnings.end());
  if (g.triangles == 0 || g.objects.empty()) throw pbr::LoadError(file.string() + ": has no triangles to show");
  const pbr::Bounds b = pbr::world_bounds(g.objects);
  const glm::vec3 centre = (b.min + b.max) * 0.5f;
  const float radius = 0.5f * glm::length(b.max - b.min);
  const float scale = radius > 0.0f ? 0.4f * kSingleObjectScale / radius : 1.0f;
  const glm::mat4 fit = glm::scale(glm::mat4(1.0f), glm::vec3(scale)) * glm::translate(glm::mat4(1.0f), -centre);
  NamedMesh entry{file.stem().string(), nullptr, std::move(g.objects), file, std::move(g.variants)};
  for (pbr::Object& o : entry.model) o.transform = fit * o.transform;
  return entry;
}
}  // namespace

NamedMesh load_model(const std::filesystem::path& file, std::vector<std::string>& warnings, raster::ThreadPool* pool) {
  return load_model_variant(file, warnings, pool, "");
}

bool next_variant(NamedMesh& entry, std::vector<std::string>& warnings, raster::ThreadPool* pool) {
  if (entry.variants.empty()) return false;
  const std::size_t next = (entry.variant + 1) % (entry.variants.size() + 1);
  // By name (the loader looks names up first), or by index ("0", "1", …) for a name that is
  // empty or repeated.
  std::string chosen;
  if (next != 0) {
    const std::string& name = entry.variants[next - 1];
    const bool unique = !name.empty() && std::count(entry.variants.begin(), entry.variants.end(), name) == 1;
    chosen = unique ? name : std::to_string(next - 1);
  }
  NamedMesh loaded = load_model_variant(entry.file, warnings, pool, chosen);
  loaded.name = entry.name;
  loaded.variant = next;
  entry = std::move(loaded);
  return true;
}

std::string variant_label(const NamedMesh& entry) {
  if (entry.variant == 0 || entry.variant > entry.variants.size()) return "";
  return "variant " + entry.variants[entry.variant - 1];
}

std::vector<NamedMesh> load_meshes(const std::filesystem::path& assets_dir,
                                   const std::vector<std::filesystem::path>& files,
                                   std::vector<std::string>& warnings, raster::ThreadPool* pool) {
  std::vector<NamedMesh> meshes;
  meshes.push_back({"spheres", nullptr});
  // The bundled models' warnings are known and harmless (the teapot's MTL sets both d and
  // Tr): only the user's files get theirs reported.
  std::vector<std::string> bundled_warnings;
  meshes.push_back({"spot", load_merged(assets_dir / "models/spot/spot_triangulated.obj", bundled_warnings)});
  meshes.push_back({"teapot", load_merged(assets_dir / "models/teapot/teapot.obj", bundled_warnings)});
  // Procedural shapes (pbr/mesh.h), fitted into the cell like the models: a torus (tube
  // 0.4 of the ring's radius) standing up, and a cube with flat faces and sharp edges.
  meshes.push_back({"torus", std::make_shared<pbr::Mesh>(stand_up(pbr::torus(1.0f, 0.4f, 96, 48)))});
  meshes.push_back({"cube", std::make_shared<pbr::Mesh>(pbr::cube(1.0f))});
  for (const std::filesystem::path& f : files) meshes.push_back(load_model(f, warnings, pool));
  return meshes;
}

Environments load_environments(const std::vector<std::filesystem::path>& files, raster::ThreadPool* pool) {
  Environments list{nullptr, pbr::Environment::studio()};
  for (const std::filesystem::path& f : files) list.push_back(pbr::load_environment(f, {}, pool));
  return list;
}

pbr::Scene build_scene(const ViewerState& state, const std::vector<NamedMesh>& meshes, const Environments& environments) {
  pbr::GalleryOptions options;
  const NamedMesh& entry = meshes.at(state.mesh);
  options.mesh = entry.mesh;
  const bool model = !entry.model.empty();
  const bool single = state.material != kGalleryMaterial || model;
  if (model) {
    options.rows = {"gold"};  // one cell (replaced by the model below), the gallery's lights
    options.columns = 1;
  } else if (single) {
    options.rows = {std::string(pbr::material_presets()[static_cast<std::size_t>(state.material)].name)};
    options.columns = 1;
  }
  pbr::Scene scene = pbr::make_gallery(options);
  if (model) {
    scene.objects = entry.model;
  } else if (single) {
    pbr::Object& o = scene.objects.at(0);
    o.material.roughness = state.roughness();
    o.material.metallic = state.metallic ? 1.0f : 0.0f;
    o.transform = glm::scale(glm::mat4(1.0f), glm::vec3(kSingleObjectScale)) * o.transform;
  }
  scene.camera = state.camera.camera();
  if (state.light_angle != 0.0f)
    for (pbr::Light& l : scene.lights) l.position = turn_about_y(l.position, state.light_angle);
  softpbr::job::Settings shadows;
  shadows.shadows = state.shadows ? "on" : "off";
  shadows.ground = state.ground ? "shadow" : "none";
  softpbr::job::apply_shadows(scene, shadows);
  if (state.environment != 0) {
    scene.environment.map = environments.at(state.environment);
    scene.background_mode = pbr::BackgroundMode::Environment;
  }
  return scene;
}

raster::Image8 render_view(const ViewerState& state, const std::vector<NamedMesh>& meshes, raster::Renderer& renderer,
                           raster::Target& target, const Environments& environments) {
  // The render job's frame (softpbr::job): each tile tone mapped right after it is drawn,
  // the bytes of render() then tone_map_to_rgba8(), so a transient target needs nothing more.
  raster::Image8 image;
  softpbr::job::render_into(build_scene(state, meshes, environments), pbr::gallery_output(), renderer, target, &image,
                            nullptr);
  return image;
}

const raster::Image8& render_view(const ViewerState& state, const std::vector<NamedMesh>& meshes,
                                  raster::Renderer& renderer, softpbr::job::Frame& frame, int width, int height,
                                  const Environments& environments) {
  pbr::RenderSettings settings;
  settings.width = width;
  settings.height = height;
  settings.msaa = state.msaa;
  settings.output = pbr::gallery_output();
  frame.render(build_scene(state, meshes, environments), settings, renderer, {.rgba8 = true});
  return frame.rgba();
}

std::string material_label(const ViewerState& state) {
  if (state.material == kGalleryMaterial) return "gallery";
  char text[96];
  std::snprintf(text, sizeof text, "%s r %.2f %s",
                std::string(pbr::material_presets()[static_cast<std::size_t>(state.material)].name).c_str(),
                static_cast<double>(state.roughness()), state.metallic ? "metal" : "dielectric");
  return text;
}

}  // namespace viewer
