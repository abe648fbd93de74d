// softpbr/loaders/scene_file.h — JSON scene files: camera, lights, objects (procedural shapes
// or OBJ files), materials, render settings and the turntable animation, loaded into a
// pbr::Scene. The format is documented in docs/scene-format.md.
//
// Scene files are untrusted input (docs/design.md, "Errors"): every key is known, every value has the
// expected type and range, counts and memory are bounded before anything large is built,
// and every problem is one SceneFileError line naming the file and the JSON pointer
// (RFC 6901) of the value, e.g.
//   gallery.json: /objects/3/material/roughness: expected a number in [0, 1], got 2
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "softpbr/loaders/loaded_scene.h"
#include "softpbr/loaders/missing_images.h"

namespace softpbr::pbr {

// A scene file is invalid; what() is one line: "FILE: /json/pointer: what was expected, got X".
class SceneFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// ---- Limits (documented in docs/scene-format.md) -----------------------------------------
// A scene file larger than this is refused before it is read: hand-written or generated
// scenes are kilobytes; meshes belong in OBJ files.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{64} << 20;
// Every light is evaluated at every shaded pixel (no light culling), so the cost of a
// frame grows linearly with the light count: 256 lights at 1920×1080 already take minutes.
inline constexpr std::size_t kMaxLights = 256;
// Each object is one draw call with its own vertex buffer.
inline constexpr std::size_t kMaxObjects = 100000;
// Default bound on the estimated memory of a render (scene_memory + image_memory).
inline constexpr std::uint64_t kDefaultMemoryLimit = std::uint64_t{4} << 30;

struct SceneLoadOptions {
  // The loader refuses a scene whose meshes and textures are estimated to need more
  // (checked before a procedural mesh is generated and before an image is decoded, from its
  // header; after an OBJ file is read, since its size is only then known).
  std::uint64_t memory_limit = kDefaultMemoryLimit;
  // Where an environment is prefiltered (none: on the calling thread), and the folder of
  // its disk cache (empty: none; see load_environment).
  raster::ThreadPool* pool = nullptr;
  std::filesystem::path environment_cache{};
  // When not empty, every file the scene reads — models, MTL files, images, glTF buffers —
  // must lie inside one of these folders once symbolic links and ".." are resolved (the
  // scene file itself is the caller's choice). Empty: any file the process may read.
  std::vector<std::filesystem::path> roots{};
  // A texture image of a mesh file (an OBJ's MTL map, a glTF model's image) that cannot be
  // read: the scene refused (Error) or the slot left empty with a warning (Warn);
  // missing_images.h. The scene file's own textures are the scene's choice: an error.
  MissingImages missing_images = MissingImages::Error;
};

// Reads and validates a scene file. Relative mesh and image paths resolve against the file's folder.
// Throws SceneFileError (one line: the path as given, the JSON pointer, the problem).
SceneFile load_scene_file(const std::filesystem::path& path, const SceneLoadOptions& options = {});

// The same from text: `name` is used in messages, `base_dir` resolves relative mesh and image paths.
SceneFile parse_scene_file(std::string_view text, const std::string& name, const std::filesystem::path& base_dir,
                           const SceneLoadOptions& options = {});

// Estimated bytes of the buffers a width × height render allocates: the float colour and
// depth target and the largest output's buffers (.exr's: 72 bytes a pixel in all); with
// `samples` > 1 (MSAA) also the multisampled target (20 bytes a sample) the resolve reads.
std::uint64_t image_memory(int width, int height, int samples = 1);

}  // namespace softpbr::pbr
