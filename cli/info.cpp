// `softpbr info` (see info.h).
#include "info.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <new>
#include <string>

#include <glm/geometric.hpp>

#include "cli_error.h"
#include "softpbr/job/render_job.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/raster/pool.h"

namespace softpbr::cli {

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

CLI::App* add_info_command(CLI::App& app, InfoArgs& a) {
  CLI::App* c = app.add_subcommand(
      "info",
      "Describe an OBJ or glTF model (counts, bounds, materials, textures, extensions, problems) or a scene file (.json)");
  c->add_option("file", a.file, "An .obj, .gltf or .glb model, or a .json scene")->required();
  c->footer(kExitCodesHelp);
  return c;
}

namespace {

struct MeshProblems {
  std::size_t degenerate = 0;  // triangles of zero area (two equal positions or collinear)
};

MeshProblems find_problems(const pbr::Mesh& mesh) {
  MeshProblems p;
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::vec3 a = mesh.vertices[mesh.indices[t]].position, b = mesh.vertices[mesh.indices[t + 1]].position,
                    c = mesh.vertices[mesh.indices[t + 2]].position;
    const glm::vec3 n = glm::cross(b - a, c - a);
    if (n.x == 0.0f && n.y == 0.0f && n.z == 0.0f) ++p.degenerate;
  }
  return p;
}

void print_vec(const char* label, glm::vec3 v) { std::printf("%s(%g, %g, %g)", label, v.x, v.y, v.z); }

// "base_color 512x512, normal 512x512": the material's textured slots, or "".
std::string texture_list(const pbr::Material& m) {
  std::string out;
  auto add = [&](const char* name, const pbr::TextureSlot& slot) {
    if (!slot) return;
    out += (out.empty() ? "" : ", ") + std::string(name) + " " + std::to_string(slot.texture->width()) + "x" +
           std::to_string(slot.texture->height());
  };
  add("base_color", m.base_color_texture);
  add("metallic_roughness", m.metallic_roughness_texture);
  add("normal", m.normal_texture);
  add("occlusion", m.occlusion_texture);
  add("emissive", m.emissive_texture);
  return out;
}

int info_obj(const std::string& path) {
  pbr::ObjModel model;
  try {
    model = pbr::load_obj(path);
  } catch (const std::exception& e) {
    throw Error(kExitInput, e.what());
  }
  std::size_t vertices = 0, triangles = 0;
  pbr::Bounds all{glm::vec3(std::numeric_limits<float>::infinity()), glm::vec3(-std::numeric_limits<float>::infinity())};
  std::vector<std::string> problems = model.warnings;
  std::printf("%s\n", path.c_str());
  std::printf("  shapes     %zu\n", model.shapes.size());
  for (const pbr::ObjShape& s : model.shapes) {
    vertices += s.mesh.vertices.size();
    triangles += s.mesh.triangle_count();
    const pbr::Bounds b = pbr::bounds(s.mesh);
    if (!b.empty()) all = {glm::min(all.min, b.min), glm::max(all.max, b.max)};
    const std::string name = s.name.empty() ? "(unnamed)" : s.name;
    const std::string material =
        s.material >= 0 ? model.materials[static_cast<std::size_t>(s.material)].first : "(default material)";
    std::printf("    %-24s %8zu vertices %8zu triangles  %s\n", name.c_str(), s.mesh.vertices.size(),
                s.mesh.triangle_count(), material.c_str());
    const MeshProblems p = find_problems(s.mesh);
    if (p.degenerate)
      problems.push_back("shape " + name + ": " + std::to_string(p.degenerate) + " zero-area triangles (drawn as nothing)");
    if (s.mesh.triangle_count() == 0) problems.push_back("shape " + name + ": no triangles");
  }
  std::printf("  vertices   %zu\n  triangles  %zu\n", vertices, triangles);
  if (all.empty()) {
    std::printf("  bounds     (empty)\n");
    problems.push_back("the model has no vertices");
  } else {
    print_vec("  bounds     min ", all.min);
    print_vec(" max ", all.max);
    print_vec(" size ", all.extent());
    std::printf("\n");
  }
  std::printf("  materials  %zu\n", model.materials.size());
  for (const auto& [name, m] : model.materials) {
    std::printf("    %-24s base_color (%g, %g, %g) metallic %g roughness %g emissive (%g, %g, %g)\n", name.c_str(),
                m.base_color.r, m.base_color.g, m.base_color.b, m.metallic, m.roughness, m.emissive.r, m.emissive.g,
                m.emissive.b);
    if (const std::string t = texture_list(m); !t.empty()) std::printf("    %-24s textures %s\n", "", t.c_str());
  }
  if (model.texture_bytes > 0) std::printf("  textures   %s\n", pbr::format_bytes(model.texture_bytes).c_str());
  std::printf("  problems   %zu\n", problems.size());
  for (const std::string& p : problems) std::printf("    %s\n", printable_line(p).c_str());
  return kExitOk;
}

std::string or_unnamed(const std::string& name) { return name.empty() ? "(unnamed)" : printable_line(name); }

std::string join(const std::vector<std::string>& items, const char* none = "none") {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + printable_line(s);
  return out.empty() ? none : out;
}

// A glTF file: pbr::load_gltf validates it (the same error line and exit code as
// `softpbr render`) and gives what the scene draws and its warnings; pbr::inspect_gltf
// what the file holds, with image sizes from their headers (both from one parse:
// pbr::load_and_inspect_gltf).
int info_gltf(const std::string& path) {
  pbr::GltfScene scene;
  pbr::GltfInfo info;
  try {
    raster::ThreadPool pool(0);
    pbr::GltfModelInfo model = pbr::load_and_inspect_gltf(path, {.pool = &pool});
    scene = std::move(model.scene);
    info = std::move(model.info);
  } catch (const pbr::LoadError& e) {
    throw Error(kExitInput, e.what());
  } catch (const std::bad_alloc&) {
    throw Error(kExitInput, path + ": out of memory while loading it (the process's memory or address-space limit)");
  }
  std::printf("%s\n", path.c_str());
  std::printf("  asset      glTF %s%s\n", printable_line(info.version).c_str(),
              info.generator.empty() ? "" : (", generator \"" + printable_line(info.generator) + "\"").c_str());
  std::printf("  scenes     %zu", info.scenes);
  if (info.default_scene >= 0) std::printf(" (default %d)", info.default_scene);
  std::printf("\n");
  // Several scenes: what `softpbr render --scene N|NAME` shows.
  if (info.scene_names.size() > 1)
    for (std::size_t i = 0; i < info.scene_names.size(); ++i)
      std::printf("    %-3zu %s\n", i, or_unnamed(info.scene_names[i]).c_str());
  std::printf("  nodes      %zu\n", info.nodes);
  auto plural = [](std::size_t n) { return n == 1 ? "" : "s"; };
  std::printf("  meshes     %zu (%zu primitive%s, %zu triangles, each mesh counted once)\n", info.meshes.size(),
              info.primitives(), plural(info.primitives()), info.triangles());
  for (std::size_t i = 0; i < info.meshes.size(); ++i) {
    const pbr::GltfMeshInfo& m = info.meshes[i];
    std::printf("    %-3zu %-24s %4zu %-10s %10zu triangles", i, or_unnamed(m.name).c_str(), m.primitives.size(),
                m.primitives.size() == 1 ? "primitive" : "primitives", m.triangles);
    if (m.morph_targets) std::printf("  %zu morph targets", m.morph_targets);
    std::printf("\n");
  }
  // What the scene draws: each primitive of each node that has a mesh (instances counted).
  std::size_t degenerate = 0, drawn = 0;
  std::map<const pbr::Mesh*, std::size_t> degenerate_of;  // each mesh examined once, however many its instances
  for (const pbr::Object& o : scene.objects) {
    auto [it, added] = degenerate_of.try_emplace(o.mesh.get(), 0);
    if (added) it->second = find_problems(*o.mesh).degenerate;
    degenerate += it->second;
    drawn += o.mesh->triangle_count();
  }
  std::printf("  drawn      %zu primitive%s, %zu triangles (the scene's nodes)\n", scene.objects.size(),
              plural(scene.objects.size()), drawn);
  const pbr::Bounds all = pbr::world_bounds(scene.objects);
  if (all.empty()) {
    std::printf("  bounds     (empty)\n");
  } else {
    print_vec("  bounds     min ", all.min);
    print_vec(" max ", all.max);
    print_vec(" size ", all.extent());
    std::printf("\n");
  }
  std::printf("  materials  %zu\n", info.materials.size());
  for (std::size_t i = 0; i < info.materials.size(); ++i) {
    const pbr::GltfMaterialInfo& m = info.materials[i];
    std::string textures;
    for (const auto& slot : m.textures)
      textures += (textures.empty() ? "" : ", ") + slot.first + " " + std::to_string(slot.second);
    std::printf("    %-3zu %-24s %s%s%s%s%s\n", i, or_unnamed(m.name).c_str(), printable_line(m.alpha_mode).c_str(),
                m.double_sided ? ", double-sided" : "", textures.empty() ? "" : ", textures ", textures.c_str(),
                m.extensions.empty() ? "" : (", " + join(m.extensions)).c_str());
  }
  std::uint64_t encoded = 0;
  for (const pbr::GltfImageInfo& im : info.images) encoded += im.bytes;
  std::printf("  textures   %zu (%zu image%s, %s encoded)\n", info.textures.size(), info.images.size(),
              info.images.size() == 1 ? "" : "s", pbr::format_bytes(encoded).c_str());
  for (std::size_t i = 0; i < info.textures.size(); ++i) {
    const pbr::GltfTextureInfo& t = info.textures[i];
    std::string what = "no image";
    if (t.source >= 0 && static_cast<std::size_t>(t.source) < info.images.size()) {
      const pbr::GltfImageInfo& im = info.images[static_cast<std::size_t>(t.source)];
      const std::string size = im.width > 0 ? std::to_string(im.width) + "x" + std::to_string(im.height) : "size unknown";
      what = (im.format.empty() ? std::string("unknown format") : im.format) + " " + size +
             (im.detail.empty() ? "" : " (" + im.detail + ")") + ", image " +
             std::to_string(t.source) + " (" + printable_line(im.location) + ", " + pbr::format_bytes(im.bytes) + ")";
    }
    std::printf("    %-3zu %-24s %s\n", i, or_unnamed(t.name).c_str(), what.c_str());
  }
  std::printf("  extensions used: %s; required: %s\n", join(info.extensions_used).c_str(),
              join(info.extensions_required).c_str());
  {
    // Which of them softpbr renders, and which it ignores (a required one refuses the file).
    const std::vector<std::string>& known = pbr::gltf_extensions_rendered();
    std::vector<std::string> rendered, ignored;
    for (const std::string& e : info.extensions_used)
      (std::binary_search(known.begin(), known.end(), e) ? rendered : ignored).push_back(e);
    std::printf("  extensions rendered: %s; ignored: %s\n", join(rendered).c_str(), join(ignored).c_str());
  }
  if (!info.variants.empty()) {
    // KHR_materials_variants: what `softpbr render --variant NAME` (or N) shows.
    std::printf("  variants   %zu\n", info.variants.size());
    for (std::size_t i = 0; i < info.variants.size(); ++i)
      std::printf("    %-3zu %s\n", i, or_unnamed(info.variants[i]).c_str());
  }
  std::printf("  cameras    %zu\n", info.cameras.size());
  for (std::size_t i = 0; i < info.cameras.size(); ++i)
    std::printf("    %-3zu %-24s %s\n", i, or_unnamed(info.cameras[i].name).c_str(), printable_line(info.cameras[i].type).c_str());
  std::printf("  lights     %zu\n", info.lights.size());
  for (std::size_t i = 0; i < info.lights.size(); ++i)
    std::printf("    %-3zu %-24s %s\n", i, or_unnamed(info.lights[i].name).c_str(), printable_line(info.lights[i].type).c_str());
  std::printf("  animation  %zu skins, %zu animations (without --time: the nodes' own pose, skins and morph weights "
              "evaluated)\n",
              info.skins, info.animations);
  for (std::size_t i = 0; i < scene.animations.size(); ++i) {
    const pbr::GltfAnimation& a = scene.animations[i];
    std::printf("    %-3zu %-24s %9.3f s  %zu channel%s\n", i, or_unnamed(a.name).c_str(), a.duration, a.channels,
                plural(a.channels));
  }
  std::vector<std::string> problems = scene.warnings;
  if (degenerate) problems.push_back(std::to_string(degenerate) + " zero-area triangles (drawn as nothing)");
  if (drawn == 0) problems.push_back("the scene draws no triangles");
  std::printf("  problems   %zu\n", problems.size());
  for (const std::string& p : problems) std::printf("    %s\n", printable_line(p).c_str());
  return kExitOk;
}

int info_scene(const std::string& path) {
  pbr::SceneFile file;
  try {
    file = pbr::load_scene_file(path);
  } catch (const pbr::SceneFileError& e) {
    throw Error(kExitInput, e.what());
  }
  const pbr::Scene& s = file.scene;
  std::printf("%s\n", path.c_str());
  std::printf("  objects    %zu (%llu triangles)\n", s.objects.size(), static_cast<unsigned long long>(file.triangles));
  std::printf("  lights     %zu\n", s.lights.size());
  print_vec("  camera     position ", s.camera.position);
  print_vec(" target ", s.camera.target);
  std::printf("\n  render     %dx%d, tone map %s, exposure %g, gamma %s\n", file.render.width, file.render.height,
              std::string(pbr::tone_map_name(file.render.output.tone_map)).c_str(), file.render.output.exposure,
              file.render.output.gamma > 0 ? std::to_string(file.render.output.gamma).c_str() : "srgb");
  const job::MemoryEstimate memory = job::estimate_memory(file, file.render);  // what `render` checks
  std::printf("  memory     %s (estimate: meshes and draws %s, textures %s, environment %s, image %s)\n",
              pbr::format_bytes(memory.total()).c_str(), pbr::format_bytes(memory.mesh).c_str(),
              pbr::format_bytes(memory.texture).c_str(), pbr::format_bytes(memory.environment).c_str(),
              pbr::format_bytes(memory.image).c_str());
  std::printf("  problems   %zu\n", file.warnings.size());
  for (const std::string& w : file.warnings) std::printf("    %s\n", printable_line(w).c_str());
  return kExitOk;
}

}  // namespace

int run_info(const InfoArgs& a) {
  std::string ext = std::filesystem::path(a.file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext == ".json") return info_scene(a.file);
  if (ext == ".obj") return info_obj(a.file);
  if (ext == ".gltf" || ext == ".glb") return info_gltf(a.file);
  throw Error(kExitUsage, a.file + ": expected an .obj, .gltf or .glb model or a .json scene");
}

}  // namespace softpbr::cli
