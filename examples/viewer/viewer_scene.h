// viewer/viewer_scene.h — from viewer state to a softpbr scene and an image.
//
// Gallery mode (material kGalleryMaterial) is the paper's gallery (pbr::make_gallery):
// one preset per row, roughness rising across the columns, with the current mesh in every
// cell. Preset mode shows one object of the current mesh at the origin, three times the
// size of a gallery cell (2.4 units), in the chosen preset with the state's roughness and
// metallic. Either way the camera is the state's fly camera and the gallery's three point
// lights turn about the y axis by the state's light angle. Images are tone mapped as the
// paper does (pbr::gallery_output(): Reinhard, gamma 2.2).
//
// A glTF model (.gltf, .glb) is an entry of the mesh list too: it is drawn alone with its
// own materials and node transforms, fitted so its bounding sphere (world_bounds' centre,
// half their diagonal) has a diameter of 0.8 · kSingleObjectScale (2.4 units) centred on the
// origin, under the same camera, lights and environment; the material keys do not change
// it.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "softpbr/job/render_job.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"
#include "viewer_state.h"

namespace viewer {

// Preset mode draws its single object at this scale of a gallery cell's 0.8-unit fit.
inline constexpr float kSingleObjectScale = 3.0f;

struct NamedMesh {
  std::string name;
  std::shared_ptr<const softpbr::pbr::Mesh> mesh;  // null: the gallery's UV spheres (or a glTF model)
  // A glTF model's objects with their materials, already fitted (see above); empty for
  // a mesh.
  std::vector<softpbr::pbr::Object> model{};
  // A glTF model's file, its KHR_materials_variants names and the one shown (0: the file's
  // default materials, i: variants[i − 1]).
  std::filesystem::path file{};
  std::vector<std::string> variants{};
  std::size_t variant = 0;
};

// An OBJ file (all shapes merged) or a glTF model (.gltf/.glb, by the extension; images
// decoded on `pool`) as an entry of the mesh list, named by the file's stem. Throws
// pbr::LoadError naming the file (and the line or JSON pointer); the loader's warnings
// are appended to `warnings`.
NamedMesh load_model(const std::filesystem::path& file, std::vector<std::string>& warnings,
                     softpbr::raster::ThreadPool* pool = nullptr);

// The G key: a glTF model with KHR_materials_variants is loaded again with its next variant
// (after the last, its default materials), fitted as before (the variants change materials
// only). Returns false, and leaves `entry` as it is, for an entry without variants. Throws
// what load_model throws (the file changed or vanished since).
bool next_variant(NamedMesh& entry, std::vector<std::string>& warnings, softpbr::raster::ThreadPool* pool = nullptr);

// What the title shows of an entry's variant: "" for the default (or no variants), else
// "variant NAME".
std::string variant_label(const NamedMesh& entry);

// The sphere grid, spot and the teapot from `assets_dir` (assets/ of the source tree), a
// torus and a cube, then each file (load_model: OBJ or glTF). Throws pbr::LoadError naming
// the file and line. The loader's warnings about the files are appended to `warnings`.
std::vector<NamedMesh> load_meshes(const std::filesystem::path& assets_dir,
                                   const std::vector<std::filesystem::path>& files,
                                   std::vector<std::string>& warnings, softpbr::raster::ThreadPool* pool = nullptr);

// The environments B cycles through: entry 0 is none (null), then the built-in studio,
// then each file (pbr::load_environment, prefiltered on `pool`).
using Environments = std::vector<std::shared_ptr<const softpbr::pbr::Environment>>;
Environments load_environments(const std::vector<std::filesystem::path>& files, softpbr::raster::ThreadPool* pool);

// The scene for a state. Throws std::out_of_range if state.mesh is not in `meshes` (or
// state.environment, when not 0, not in `environments`). With an environment the scene is
// lit by it as well as by the lights and shows it as the background.
softpbr::pbr::Scene build_scene(const ViewerState& state, const std::vector<NamedMesh>& meshes,
                                const Environments& environments = {});

// Renders the state's scene into `target` and tone maps it to RGBA8 (job::render_into, as
// pbr::render_rgba8: a transient multisampled target works, a kept one holds the frame
// afterwards).
softpbr::raster::Image8 render_view(const ViewerState& state, const std::vector<NamedMesh>& meshes,
                                    softpbr::raster::Renderer& renderer, softpbr::raster::Target& target,
                                    const Environments& environments = {});

// The same as a frame of the render job (softpbr::job::Frame, as the command and Python
// render): width x height with the state's MSAA, its target kept for the next frame of that
// size and sample count and keeping no samples (only the image is shown).
const softpbr::raster::Image8& render_view(const ViewerState& state, const std::vector<NamedMesh>& meshes,
                                           softpbr::raster::Renderer& renderer, softpbr::job::Frame& frame, int width,
                                           int height, const Environments& environments = {});

// "gold r 0.30 metal", "gallery": the material part of the title bar.
std::string material_label(const ViewerState& state);

}  // namespace viewer
