// scene_file/loader.h — the parts of the scene-file loader (private to loaders/src): each reads
// one kind of value of the format (docs/scene-format.md) through a json_reader::Reader and
// fails with the value's JSON pointer. scene_file.cpp reads the top level with them.
//
//   camera.cpp     read_camera        /camera
//   lights.cpp     read_light         /lights/N
//   materials.cpp  read_material      /objects/N/material: a preset name or an object
//   textures.cpp   TextureLibrary     /objects/N/material/*_texture: image files, cached
//   meshes.cpp     MeshLibrary        /meshes, /objects/N/mesh: shapes and OBJ models, cached
//   objects.cpp    read_object        /objects/N: placement (read_transform) and draws
//   render.cpp     read_render, read_animation   /render, /animation
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "../json_reader.h"
#include "../texture_cache.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"

namespace softpbr::pbr::scene_file {

using json_reader::Json;
using json_reader::Node;
using json_reader::Reader;

// The scene's estimated memory (meshes, their draws and textures) against
// SceneLoadOptions::memory_limit.
class MemoryBudget {
 public:
  MemoryBudget(const Reader& reader, std::uint64_t limit) : r_(reader), limit_(limit) {}
  // Adds `bytes`; fails at `where` ("<what> brings the scene's estimated memory to …") past the limit.
  void charge(const Node& where, std::uint64_t bytes, const char* what);
  std::uint64_t bytes() const { return bytes_; }
  // What is left under the limit: the bound of an image read before it is decoded.
  std::uint64_t left() const { return bytes_ < limit_ ? limit_ - bytes_ : 0; }

 private:
  const Reader& r_;
  std::uint64_t limit_;
  std::uint64_t bytes_ = 0;
};

// Runs `check`, a validation of the library that throws std::exception on bad values, and
// fails at `spec` with its message.
template <class Check>
void check_at(const Reader& r, const Node& spec, Check&& check) {
  try {
    check();
  } catch (const std::bad_alloc&) {
    r.fail(spec, "out of memory while loading it (the process's memory or address-space limit)");
  } catch (const std::exception& e) {
    r.fail(spec, e.what());
  }
}

// The textures of one scene file: image paths resolve against the scene's folder; each file
// is loaded once per colour space (a TextureCache shared with the scene's OBJ models), and
// its texels are charged to the budget — refused before decoding when they would pass it.
class TextureLibrary {
 public:
  TextureLibrary(const Reader& reader, std::filesystem::path base_dir, MemoryBudget& budget)
      : r_(reader), base_dir_(std::move(base_dir)), budget_(budget) {}

  // A material's texture slot: an image path, or {"image", "sampler", "uv_set", "uv_transform"}.
  TextureSlot slot(const Node& spec, raster::ColorSpace space);
  detail::TextureCache& cache() { return cache_; }
  std::uint64_t bytes() const { return cache_.bytes(); }

 private:
  const Reader& r_;
  std::filesystem::path base_dir_;
  MemoryBudget& budget_;
  detail::TextureCache cache_;
};

Camera read_camera(const Reader& r, const Node& spec);
Light read_light(const Reader& r, const Node& spec);
Material read_material(const Reader& r, const Node& spec, TextureLibrary& textures);
// The object's model matrix from {"translate", "rotate", "scale"} or {"matrix"}.
glm::mat4 read_transform(const Reader& r, const Node& spec);
// /render: image size, output transform, renderer options, and the scene's background.
void read_render(const Reader& r, const Node& spec, SceneFile& out);
// /environment: the environment map (loaded and prefiltered, charged to the budget), its
// intensity and rotation, and the background.
void read_environment(const Reader& r, const Node& spec, const std::filesystem::path& base_dir, MemoryBudget& budget,
                      const SceneLoadOptions& options, SceneFile& out);
void read_animation(const Reader& r, const Node& spec, Animation& out);

// A mesh spec once loaded: a procedural shape (one part) or an OBJ model (one part per
// shape, with its MTL materials), and the fit transform.
struct LoadedMesh {
  std::vector<std::shared_ptr<const Mesh>> parts;
  std::vector<int> part_material;      // OBJ: index into materials, −1 none
  std::vector<Material> materials;     // OBJ's MTL materials
  std::shared_ptr<const Mesh> merged;  // all parts in one mesh, made when an object needs it
  std::shared_ptr<const ObjModel> obj; // kept to merge on demand
  // Parts (or the merged mesh) with MikkTSpace tangents, made once for the objects that
  // draw them with a normal map (keyed by the mesh they were made from).
  std::map<const Mesh*, std::shared_ptr<const Mesh>> with_tangents;
  glm::mat4 fit{1.0f};
  bool has_fit = false;
};

// Bytes a mesh's own arrays take (MeshVertex and three indices a triangle).
std::uint64_t mesh_bytes(std::uint64_t vertices, std::uint64_t triangles);

// The meshes of one scene file: named ones (/meshes) and inline specs, each built once
// (cached by name or by the spec's JSON text) and charged to the budget before it is built
// where its size is known first (procedural shapes). OBJ models' MTL maps load into the
// scene's texture cache.
class MeshLibrary {
 public:
  MeshLibrary(const Reader& reader, std::filesystem::path base_dir, MemoryBudget& budget, TextureLibrary& textures)
      : r_(reader), base_dir_(std::move(base_dir)), budget_(budget), textures_(textures) {}

  // /meshes: builds every named mesh now, so an unused one is still checked.
  void define(const Node& meshes);
  // A mesh spec or the name of one in /meshes.
  LoadedMesh& mesh(const Node& spec);
  // Warnings of the OBJ files read so far.
  std::vector<std::string>& warnings() { return warnings_; }
  // The model files read so far (OBJ and MTL, glTF).
  std::vector<std::string>& files() { return files_; }
  // What a model's texture image that cannot be read does (SceneLoadOptions::missing_images).
  void set_missing_images(MissingImages m) { missing_images_ = m; }

 private:
  LoadedMesh build(const Node& spec);
  LoadedMesh build_obj(const Node& spec, const Node& file);
  LoadedMesh build_shape(const Node& spec);

  const Reader& r_;
  std::filesystem::path base_dir_;
  MemoryBudget& budget_;
  TextureLibrary& textures_;
  std::optional<Node> named_;
  std::map<std::string, LoadedMesh> cache_;  // by name ("#name") or by the spec's JSON text
  std::vector<std::string> warnings_;
  std::vector<std::string> files_;
  MissingImages missing_images_ = MissingImages::Error;
};

// One entry of /objects: appended to out.scene.objects, one object per drawn part.
void read_object(const Reader& r, const Node& spec, MeshLibrary& meshes, TextureLibrary& textures, MemoryBudget& budget,
                 SceneFile& out);

}  // namespace softpbr::pbr::scene_file
