// softpbr/job/render_job.h — one render job, as the command (`softpbr render`), the Python
// module (softpbr.render, render_hdr) and the viewer run it: load an input, apply the
// settings given over the scene's, check them and the memory estimate, render a frame,
// encode its outputs. Each front end only turns what it is given into Settings and the
// job's errors into its own (the command: an error line and exit code; Python: ValueError),
// so a setting is added here once (docs/design.md, "Render job").
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "softpbr/loaders/loaded_scene.h"
#include "softpbr/loaders/missing_images.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace softpbr::job {

// The largest frame number, for the command's --frames and Python's frame=: keeps names and
// angles sane (turntable angles are reduced modulo 360 in double, exact for any such frame).
inline constexpr long kMaxFrame = 9'999'999;

// A setting the job refuses (Kind::Setting: a bad value, before any work) or an input it
// cannot render (Kind::Input: an environment file that cannot be read, a render over the
// memory limit; Kind::Memory: the process ran out of memory loading it — Python's
// MemoryError, the command's input error). setting() names the setting as Python's keyword does ("tile_size", empty
// for none), detail() says what is wrong; what() is "tile_size: expected ...". The command
// writes the setting as its option: option_text(e) is "--tile-size: expected ...".
class Error : public std::runtime_error {
 public:
  enum class Kind { Setting, Input, Memory };
  Error(Kind kind, std::string setting, std::string detail);
  Kind kind() const { return kind_; }
  const std::string& setting() const { return setting_; }
  const std::string& detail() const { return detail_; }

 private:
  Kind kind_;
  std::string setting_, detail_;
};

// "--tile-size: expected ...": the message with the setting named as the command's option.
std::string option_text(const Error& e);

// What a front end sets over the scene's own values; a setting left empty keeps the
// scene's. Names are Python's keywords; the command's options are the same with '-'.
struct Settings {
  // The image and the renderer (pbr::RenderSettings; the scene file's /render).
  std::optional<long> width{}, height{};
  std::optional<long> msaa{};           // samples a pixel: 1, 4 or 8
  std::optional<std::string> tonemap{};  // none, reinhard, aces, neutral
  std::optional<float> exposure{};       // stops, [-64, 64]
  std::optional<float> gamma{};          // 0: the sRGB curve; else a power in [0.1, 10]
  std::optional<long> threads{};         // 0: all cores (the image is the same for any)
  std::optional<long> tile_size{};       // even, 8..4096 (the image is the same for any)
  // A glTF model's view (pbr::GltfView): the automatic camera turned and raised, degrees,
  // or the file's camera N.
  std::optional<float> yaw{}, pitch{};
  std::optional<long> camera{};
  // A glTF model's material variant (KHR_materials_variants): a name, or an index ("1");
  // GltfOptions::variant. Not for a scene file, whose glTF objects say their own.
  std::optional<std::string> variant{};
  // A glTF model's scene (glTF's "scenes"): a name, or an index ("1"); default the
  // file's "scene", else 0 (GltfOptions::scene_name).
  std::optional<std::string> scene{};
  // A glTF model's animations (pbr::GltfOptions): the moment, seconds in [-1e9, 1e9], and
  // the animation applied, an index or a name (default: every one).
  std::optional<double> time{};
  std::optional<std::string> animation{};
  // A glTF model's animation over frames: frame f is the model at f / fps seconds (in
  // (0, 1000]; not with `time`). The model is kept posable (pbr::GltfOptions::poseable)
  // and pose_frame poses each frame; the automatic camera frames the union of the model's
  // bounds at every frame's moment in the animation (docs/cli.md, "Animated models").
  std::optional<double> fps{};
  // Image-based lighting: a file, "studio" or "none"; its intensity and rotation (degrees);
  // what is seen behind the scene: environment, blur, transparent or R,G,B (linear).
  std::optional<std::string> env{};
  std::optional<float> env_intensity{}, env_rotation{};
  std::optional<std::string> background{};
  // Screen-space ambient occlusion of the environment's light: "on" (the default of a
  // scene with an environment) or "off" (EnvironmentLighting::occlusion).
  std::optional<std::string> occlusion{};
  // Shadows of the punctual lights (pbr::Light::shadows): "on" (every light casts them),
  // "off" (none does); unset: as the scene says (a glTF model's lights cast them, a scene
  // file's lights where they say "shadows": true). apply_shadows() puts it over a scene.
  std::optional<std::string> shadows{};
  // A ground under the objects (pbr::Ground): "shadow" (a shadow catcher: the objects'
  // soft contact shadow and the lights' shadows on the plane under them, black with the
  // shadow as alpha) or "none"; unset: as the scene says (a scene file's "ground"; none
  // for a glTF model). apply_shadows() puts it over a scene.
  std::optional<std::string> ground{};
  std::filesystem::path env_cache{};  // prefiltered environments kept in this folder
  // Loading: the memory limit in MiB (default pbr::kDefaultMemoryLimit) and the folders a
  // scene may read files from (empty: anywhere).
  std::optional<double> max_memory_mib{};
  std::vector<std::filesystem::path> roots{};
  // A model's texture image that cannot be read: "error" (the default: the model is
  // refused) or "warn" (its slot left empty, a warning); pbr::MissingImages.
  std::optional<std::string> missing_images{};
};

// Checks every setting given, before any work: Error (Kind::Setting) for the first bad one.
void validate(const Settings& settings);

// The memory limit the settings ask for, in bytes (pbr::kDefaultMemoryLimit by default).
std::uint64_t requested_memory_limit(const Settings& settings);
// settings.missing_images as the loaders take it (Error unless "warn").
pbr::MissingImages missing_images(const Settings& settings);

// Loads `input` — a scene file, or a glTF model (.gltf, .glb) shown with the automatic
// camera and light rig (pbr::gltf_scene_file) — with the settings' view, environment and
// background applied, images decoded on `pool`. Throws pbr::LoadError (a model) or
// pbr::SceneFileError (a scene file) naming the file, and Error: Kind::Setting for a
// setting this input cannot take (camera N of a file with fewer, a blurred background
// without an environment), Kind::Input for an environment file that cannot be read,
// Kind::Memory for a model that does not fit in the process's memory. `settings` must have passed validate().
pbr::LoadedScene load(const std::string& input, const Settings& settings, raster::ThreadPool& pool);

// A glTF model alone as load() shows it, without the environment overrides (but env
// "none": the light rig): pbr::gltf_scene_file with the settings' size, yaw, pitch and
// camera (Python's Scene.load_gltf). Throws as load().
pbr::LoadedScene load_model(const std::string& input, const Settings& settings, raster::ThreadPool& pool);

// Frame `frame` of a model loaded with settings.fps: `scene`'s objects replaced by the
// model's at frame / fps seconds, and its lights (when the model has its own) and camera
// (when viewed through one of its cameras) by theirs; deformed on `pool`. Does nothing
// for a scene loaded without fps. Throws pbr::LoadError as loading at that time would.
void pose_frame(const pbr::LoadedScene& loaded, const Settings& settings, long frame, pbr::Scene& scene,
                raster::ThreadPool& pool);

// The settings' environment and background over a scene already loaded (load() does it).
void apply_environment(pbr::LoadedScene& scene, const Settings& settings, raster::ThreadPool& pool);

// The settings' shadows over the scene's lights: with "on" every light casts shadows, with
// "off" none does; unset, the scene's own; and their ground ("shadow" or "none") over the
// scene's. load() does it; Python does it to the scene it renders.
void apply_shadows(pbr::Scene& scene, const Settings& settings);

// The scene's render settings with the settings given over them, every value checked (the
// scene's own too, which Python may have set to anything): Error (Kind::Setting).
pbr::RenderSettings resolve(const pbr::RenderSettings& scene, const Settings& settings);

// The memory a render is estimated to need, by what needs it.
struct MemoryEstimate {
  std::uint64_t image = 0;        // the target (pbr::image_memory: every sample, and the resolve),
                                  // with an environment's occlusion its buffers (pbr::occlusion_memory),
                                  // the lights' shadow maps and the ground (pbr::shadow_memory),
                                  // with a transmissive object the opaque copy (pbr::transmission_memory)
  std::uint64_t mesh = 0;         // meshes and their draws (LoadedScene::mesh_bytes)
  std::uint64_t texture = 0;      // textures' texels (LoadedScene::texture_bytes)
  std::uint64_t environment = 0;  // the environment's maps (LoadedScene::environment_bytes)
  std::uint64_t total() const { return image + mesh + texture + environment; }
};
MemoryEstimate estimate_memory(const pbr::LoadedScene& scene, const pbr::RenderSettings& settings);

// The machine's physical memory in bytes (0 when unknown).
std::uint64_t physical_memory();

// The limit a render is held to: `requested` (bytes), bounded by the machine's memory.
struct MemoryLimit {
  std::uint64_t bytes = 0;
  bool machine = false;  // the machine's memory is the bound (it is below `requested`)
};
MemoryLimit memory_limit(std::uint64_t requested);

// Error (Kind::Input, no setting) unless the estimate fits the limit: "a 800x600 render of
// this scene needs an estimated 5.0 GiB, over the limit of 4.0 GiB".
void check_memory(const MemoryEstimate& estimate, const pbr::RenderSettings& settings, const MemoryLimit& limit);

// What a frame is rendered to.
struct Outputs {
  bool rgba8 = false;   // the output transform's 8-bit image (tone mapped, sRGB or gamma)
  bool linear = false;  // one linear colour a pixel (with MSAA the samples' box resolve)
};

// One frame of `scene` into `target` (with MSAA best transient): the output transform into
// `rgba` and the linear colour into `linear` (1 sample, the target's size) for those that
// are not null (pbr::render_outputs; pbr::render when neither is asked for, the target's
// colour being the image).
void render_into(const pbr::Scene& scene, const pbr::OutputSettings& output, raster::Renderer& renderer,
                 raster::Target& target, raster::Image8* rgba, raster::Target* linear);

// A frame's images, and the targets it keeps for the next frame of the same size and
// sample count (a frame list, a batch of models, a viewer's frames).
class Frame {
 public:
  // Renders `scene` at the settings' size and MSAA with their output transform. The
  // samples are not kept (a transient target); with MSAA and `outputs.linear` the resolve
  // is made per tile.
  void render(const pbr::Scene& scene, const pbr::RenderSettings& settings, raster::Renderer& renderer, Outputs outputs);

  // The last frame's 8-bit image (outputs.rgba8) and its linear colour (outputs.linear).
  const raster::Image8& rgba() const { return rgba_; }
  raster::Image8 take_rgba() { return std::move(rgba_); }
  const raster::Target& linear() const;
  // The linear colour's target, taken out of the frame (the next frame makes another).
  raster::Target take_linear();

 private:
  std::optional<raster::Target> target_, resolved_;
  raster::Image8 rgba_;
};

// The output file formats, from a name's extension (case ignored).
enum class Format { Png, Hdr, Exr };
std::optional<Format> format_from_name(const std::string& name);

// The file bytes of a frame in `format`: .png the 8-bit image, .hdr and .exr the linear
// colour × 2^exposure (`name` only names the file in errors).
std::vector<std::uint8_t> encode(const Frame& frame, Format format, const pbr::OutputSettings& output,
                                 const std::string& name);

}  // namespace softpbr::job
