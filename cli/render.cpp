// `softpbr render` (see render.h).
#include "render.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <system_error>

#include "cli_error.h"
#include "frames.h"
#include "scenario.h"
#include "softpbr/image/write.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/raster/raster.h"

namespace softpbr::cli {

namespace fs = std::filesystem;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

CLI::App* add_render_command(CLI::App& app, RenderArgs& a) {
  CLI::App* c = app.add_subcommand("render", "Render a scene file to .png, .hdr and/or .exr images");
  c->add_option("scene", a.scenes,
                "Scene file (JSON, see docs/scene-format.md), or a glTF 2.0 model (.gltf, .glb) shown with an automatic "
                "camera and light rig. Several: one image each, with outputs like thumbs/{name}.png or thumbs/");
  c->add_option("--scenario", a.scenario,
                "A Khronos glTF Render Fidelity scenario (.json: model, lighting, orbit, target, verticalFoV, "
                "dimensions, renderSkybox) instead of a scene: its model, environment and orbit camera");
  c->add_option("--scenario-name", a.scenario_name, "With --scenario: the scenario of that name in a file of several");
  c->add_option("-o,--output", a.outputs,
                "Output file, format from the extension: .png (tone mapped, 8-bit), .hdr (linear "
                "Radiance RGBE) or .exr (linear float RGBA). Repeat for several. With --frames, #### is replaced by the frame number; "
                "{name} by the input's file name without extension, {index} by its position (from 0); a name ending in / "
                "is a folder (folder/{name}.png)")
      ->required()
      ->allow_extra_args(false);  // one file per -o, so "-o out.png scene.json" works
  job::Settings& s = a.settings;
  c->add_option("--width", s.width, "Image width in pixels (overrides the scene's render.width)");
  c->add_option("--height", s.height, "Image height in pixels");
  c->add_option("--threads", s.threads, "Worker threads, 0 = all cores (the image is the same for any)");
  c->add_option("--tile-size", s.tile_size, "Screen tile size, even, 8..4096 (the image is the same for any)");
  c->add_option("--tonemap", s.tonemap, "Tone map: none, reinhard, aces, neutral");
  c->add_option("--msaa", s.msaa, "Samples a pixel: 1 (no antialiasing), 4 or 8 (MSAA; overrides render.msaa)");
  c->add_option("--exposure", s.exposure, "Exposure in stops (colour x 2^E before tone mapping)");
  c->add_option("--gamma", s.gamma, "PNG encoding: 0 for the sRGB curve, or a power in [0.1, 10] (overrides render.gamma)");
  c->add_option("--frames", a.frames,
                "Frame range A..B (inclusive): the turntable animation of the scene's camera and "
                "lights (a glTF model with --fps: its animation); frames whose outputs exist are skipped");
  c->add_option("--shard", a.shard, "i/N: render only the frames k of the range with k mod N = i (i from 0)");
  c->add_option("--yaw", s.yaw, "glTF models: turn the automatic camera this many degrees around the vertical axis");
  c->add_option("--pitch", s.pitch, "glTF models: raise the automatic camera this many degrees (-89..89; default 15, "
                                    "0 for a level view)");
  c->add_option("--camera", s.camera, "glTF models: view through camera N of the file (from 0)");
  c->add_option("--variant", s.variant,
                "glTF models: show the material variant NAME (KHR_materials_variants; or N, its index from 0; "
                "`softpbr info` lists them)");
  c->add_option("--scene", s.scene,
                "glTF models: show scene N (from 0) or NAME of the file (default: its \"scene\", else 0; `softpbr info` "
                "lists them)");
  c->add_option("--time", s.time,
                "glTF models: the moment, in seconds, at which the animations are applied (without it none is: "
                "the nodes' own pose, skins and morph weights evaluated)");
  c->add_option("--animation", s.animation,
                "glTF models: apply only animation N (from 0) or NAME (default: every animation; `softpbr info` "
                "lists them)");
  c->add_option("--fps", s.fps,
                "glTF models: with --frames, frame i is the model at i/F seconds (its animations, or --animation's); "
                "the automatic camera frames the model over the whole animation");
  c->add_flag("--turntable", a.turntable,
              "With --fps: the camera and lights also turn as --frames turns them without --fps");
  c->add_option("--env", s.env,
                "Environment lighting: an equirectangular .hdr/.exr, \"studio\" (built in; the default for "
                "glTF models) or \"none\"");
  c->add_option("--env-intensity", s.env_intensity, "Scale the environment's radiance (>= 0)");
  c->add_option("--env-rotation", s.env_rotation, "Turn the environment about the vertical axis, degrees");
  c->add_option("--background", s.background,
                "What is seen behind the scene: environment, blur, transparent or R,G,B (linear)");
  c->add_option("--missing-images", s.missing_images,
                "A model's texture image that cannot be read (an OBJ's MTL map, a glTF image file): error (the "
                "default: the model is refused) or warn (its texture left out, a warning; for thumbnails of "
                "downloaded models)");
  c->add_option("--occlusion", s.occlusion,
                "on (the default with an environment) or off: screen-space ambient occlusion of the environment's light");
  c->add_option("--shadows", s.shadows,
                "on (every light casts shadows) or off (none does); default: as the scene says (a glTF model's "
                "lights cast them, a scene file's where \"shadows\": true)");
  c->add_option("--ground", s.ground,
                "shadow (a shadow catcher under the model: its soft contact shadow and the lights' shadows, "
                "black with the shadow as alpha: over --background transparent it composites onto any page) or none; "
                "default: as the scene says (none for a glTF model)");
  c->add_option("--env-cache", a.env_cache, "Keep prefiltered environments in this folder, for batch jobs");
  c->add_flag("--force", a.force, "Render frames even when their outputs exist");
  c->add_flag("-q,--quiet", a.quiet, "Print nothing but errors");
  a.max_memory_mib = static_cast<double>(pbr::kDefaultMemoryLimit >> 20);
  c->add_option("--max-memory", a.max_memory_mib, "Refuse renders estimated to need more than this many MiB")->capture_default_str();
  c->add_option("--root", a.roots,
                 "Read the scene's models, MTL files and images only from inside this folder (repeat for several; "
                 "symbolic links and .. resolved). Default: anywhere. Recommended for scenes from others")
      ->allow_extra_args(false);
  c->footer(kExitCodesHelp);
  return c;
}

namespace {

// A job's error as the command's: a bad setting is a bad command line (exit 2), an input
// that cannot be rendered exit 3; the setting is named as its option ("--tile-size: ...").
Error command_error(const job::Error& e) {
  return Error(e.kind() == job::Error::Kind::Setting ? kExitUsage : kExitInput, job::option_text(e));
}

using job::Format;

Format output_format(const std::string& path) {
  if (const std::optional<Format> f = job::format_from_name(path)) return *f;
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  throw Error(kExitUsage, path + ": unknown output format \"" + ext + "\" (expected .png, .hdr or .exr)");
}

// The nearest folder of `path` that exists ("." for a relative name), whether the output's
// own folder is missing (then it is created when the output is written), and whether what
// exists there is a file instead of a folder.
struct ExistingFolder {
  fs::path folder;
  bool missing = false;
  bool not_a_folder = false;
};
ExistingFolder nearest_existing_folder(const fs::path& path) {
  ExistingFolder f{path.parent_path(), false, false};
  struct stat st {};
  // ENOENT: not there; ENOTDIR: a component on the way is not a folder (found further up).
  int status;
  while ((status = ::stat(f.folder.empty() ? "." : f.folder.c_str(), &st)) != 0 && (errno == ENOENT || errno == ENOTDIR) &&
         !f.folder.empty() && f.folder != f.folder.root_path()) {
    f.missing = true;
    f.folder = f.folder.parent_path();
  }
  if (f.folder.empty()) f.folder = ".";
  f.not_a_folder = status == 0 && !S_ISDIR(st.st_mode);
  return f;
}

// Fails early, before any rendering, when an output cannot be created
// (image::output_problem: a new name or a regular file, within NAME_MAX). An output's
// missing folders (thumbs/ in -o thumbs/{name}.png) are no problem when the nearest folder
// that exists can hold them: they are created as the output is written, and only then, so
// that a command that fails leaves no folder behind (create_output_folders).
void check_writable(const std::string& path) {
  const ExistingFolder existing = nearest_existing_folder(path);
  std::string problem;
  if (existing.not_a_folder) {
    problem = "cannot write: " + existing.folder.string() + " is not a folder";
  } else if (!existing.missing) {
    problem = image::output_problem(path);
  } else {
    const std::string name = fs::path(path).filename().string();
    if (::access(existing.folder.c_str(), W_OK | X_OK) != 0)
      problem = errno == EROFS ? "cannot write: the folder " + existing.folder.string() + " is on a read-only file system"
                               : "cannot write: no permission to create folders in " + existing.folder.string();
    else if (name.empty() || name == "." || name == "..")
      problem = "cannot write: not a file name";
    else if (name.size() > 255)
      problem = "cannot write: the file name is " + std::to_string(name.size()) + " bytes, over the limit of 255";
  }
  if (!problem.empty()) throw Error(kExitOutput, path + ": " + problem);
}

// Creates the missing folders of a frame's outputs, right before they are written.
void create_output_folders(const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    const fs::path folder = fs::path(path).parent_path();
    std::error_code ec;
    if (folder.empty() || fs::is_directory(folder, ec)) continue;
    fs::create_directories(folder, ec);
    if (ec) throw Error(kExitOutput, path + ": cannot create the folder " + folder.string() + ": " + ec.message());
  }
}

// The identity of an existing file (device and inode), to tell an output that is an input
// under another name (a hard link, "./a.png") from a new file.
struct FileId {
  dev_t dev = 0;
  ino_t ino = 0;
  auto operator<=>(const FileId&) const = default;
};
std::optional<FileId> file_id(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  return FileId{st.st_dev, st.st_ino};
}

// An input of the command is never an output: refused before it could be replaced.
void check_not_input(const std::string& output, const std::map<FileId, std::string>& inputs) {
  if (const auto id = file_id(output))
    if (const auto it = inputs.find(*id); it != inputs.end())
      throw Error(kExitOutput, output + ": cannot write: it is " + (it->second == output ? "an input" : "the input " + it->second) +
                                   " of this command (an output never replaces an input)");
}

class Progress {
 public:
  Progress(bool enabled, std::size_t total, const char* unit) : enabled_(enabled), total_(total), unit_(unit), start_(Clock::now()) {}
  // `what`: the frame number or the model just finished.
  void update(std::size_t done, const std::string& what) {
    if (!enabled_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double per = done > 0 ? elapsed / static_cast<double>(done) : 0.0;
    std::fprintf(stderr, "\r\033[Ksoftpbr: %s %s, %zu/%zu done, %.2f s/%s, %.0f s left", unit_, printable_line(what).c_str(),
                 done, total_, per, unit_, per * static_cast<double>(total_ - done));
    std::fflush(stderr);
  }
  // Erases the line (before an error line is printed under it).
  void clear() {
    if (enabled_) std::fputs("\r\033[K", stderr);
  }
  ~Progress() { clear(); }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  std::size_t total_;
  const char* unit_;
  Clock::time_point start_;
};

// An output name for input `index` (docs/scene-format.md, "Several inputs"): a name ending
// in '/' is a folder, given <name>.png; {name} is the input's file name without its
// extension, {index} its position among the inputs (from 0). The frame number (####) is
// put in first, so a '#' in an input's name is only a character.
bool is_folder_output(const std::string& o) { return !o.empty() && o.back() == '/'; }
bool has_input_pattern(const std::string& o) {
  return is_folder_output(o) || o.find("{name}") != std::string::npos || o.find("{index}") != std::string::npos;
}
std::string output_path(const std::string& pattern, const std::string& input, std::size_t index, long frame) {
  const std::string o = frame_path(pattern, frame);
  if (!has_input_pattern(pattern)) return o;
  const std::string name = fs::path(input).stem().string();
  if (is_folder_output(o)) return o + name + ".png";
  std::string out;
  for (std::size_t i = 0; i < o.size();) {
    if (o.compare(i, 6, "{name}") == 0) {
      out += name;
      i += 6;
    } else if (o.compare(i, 7, "{index}") == 0) {
      out += std::to_string(index);
      i += 7;
    } else {
      out += o[i++];
    }
  }
  return out;
}

// What every input of the command shares: the settings checked once, the files it must
// never overwrite, and in a batch the renderer (its threads load the models too) and frame.
struct Run {
  const RenderArgs* args = nullptr;
  job::Settings settings;  // the options given, with --max-memory, --root and --env-cache
  FrameRange range;
  Shard shard;
  std::vector<Format> formats;
  std::map<FileId, std::string> inputs;     // grows as inputs are loaded
  bool batch = false;                       // several inputs
  std::optional<Scenario> scenario;          // --scenario: its camera replaces the model's
  std::optional<raster::Renderer> renderer;  // a batch's (RendererOptions from --threads, --tile-size)
  job::Frame frame;                          // its target, kept for the next input of its size
};

// The scene of `input` with the command's overrides.
pbr::LoadedScene load_input(const Run& run, const std::string& input, raster::ThreadPool& pool) {
  try {
    pbr::LoadedScene f = job::load(input, run.settings, pool);
    if (run.scenario) {
      f.scene.camera = scenario_camera(*run.scenario, pbr::world_bounds(f.scene.objects));
      try {
        pbr::validate(f.scene.camera);
      } catch (const std::invalid_argument& e) {
        throw Error(kExitInput, run.args->scenario + ": the orbit camera is invalid in float precision (" + e.what() + ")");
      }
      if (!run.args->scenario.empty()) f.inputs.push_back(run.args->scenario);
    }
    return f;
  } catch (const job::Error& e) {
    throw command_error(e);
  } catch (const pbr::LoadError& e) {
    throw Error(kExitInput, e.what());
  } catch (const pbr::SceneFileError& e) {
    throw Error(kExitInput, e.what());
  }
}

// Renders input `index` to its outputs: every frame of this shard for a single input, the
// one frame of a batch's input. Returns whether it
// rendered (false: its outputs existed and were skipped).
bool render_input(Run& run, std::size_t index, Progress* frame_progress) {
  const RenderArgs& a = *run.args;
  const std::string& input = a.scenes[index];
  auto path = [&](std::size_t k, long frame) { return output_path(a.outputs[k], input, index, frame); };
  const FrameRange range = run.range;
  const Shard shard = run.shard;
  std::map<FileId, std::string>& inputs = run.inputs;
  // A batch's input whose outputs all exist is skipped before it is loaded.
  if (run.batch && !a.force) {
    bool all_exist = true;
    for (std::size_t k = 0; k < a.outputs.size() && all_exist; ++k) {
      std::error_code ec;
      all_exist = fs::is_regular_file(fs::symlink_status(path(k, range.first), ec));
    }
    if (all_exist) {
      if (!a.quiet) std::printf("%s: exists, skipped\n", path(0, range.first).c_str());
      return false;
    }
  }
  // 2. The scene, with command-line overrides.
  for (std::size_t k = 0; k < a.outputs.size(); ++k) check_not_input(path(k, range.first), inputs);
  const job::Settings& settings = run.settings;
  pbr::LoadedScene file;
  if (run.renderer) {
    file = load_input(run, input, run.renderer->pool());
  } else {
    // A single input's images decode on a pool of the threads the render will use.
    raster::ThreadPool pool(static_cast<unsigned>(settings.threads.value_or(0)));
    file = load_input(run, input, pool);
  }
  for (const std::string& f : file.inputs)
    if (const auto id = file_id(f)) inputs.emplace(*id, f);
  for (std::size_t k = 0; k < a.outputs.size(); ++k) check_not_input(path(k, range.first), inputs);
  if (!a.quiet)
    for (const std::string& w : file.warnings) std::fprintf(stderr, "softpbr: warning: %s\n", printable_line(w).c_str());
  pbr::RenderSettings s;
  try {
    s = job::resolve(file.render, settings);
  } catch (const job::Error& e) {
    throw command_error(e);
  }

  // 3. Memory, before the target is allocated.
  const job::MemoryLimit limit = job::memory_limit(job::requested_memory_limit(settings));
  try {
    job::check_memory(job::estimate_memory(file, s), s, limit);
  } catch (const job::Error& e) {
    const bool from_cli = settings.width || settings.height;
    const std::string where = from_cli ? (run.batch ? input + ": " : std::string()) + "--width " + std::to_string(s.width) +
                                             " --height " + std::to_string(s.height)
                                       : input + ": /render";
    throw Error(kExitInput, where + ": " + e.detail() + (limit.machine ? " (the machine's memory)" : " (--max-memory)"));
  }

  // 4. The frames of this shard.
  const long frame_count = shard_frame_count(range, shard);
  if (frame_count == 0 && !a.quiet)
    std::printf("shard %ld/%ld: no frame of %ld..%ld is this shard's (nothing to render)\n", shard.index, shard.count,
                range.first, range.last);
  std::optional<raster::Renderer> own_renderer;
  if (!run.renderer) {
    own_renderer.emplace(raster::RendererOptions{s.threads, s.tile_size});
    if (own_renderer->threads() < own_renderer->requested_threads() && !a.quiet)
      std::fprintf(stderr, "softpbr: the system started %u of the %u threads asked for; rendering with %u (the same images)\n",
                   own_renderer->threads(), own_renderer->requested_threads(), own_renderer->threads());
  }
  raster::Renderer& renderer = run.renderer ? *run.renderer : *own_renderer;
  std::size_t done = 0, skipped = 0;
  for (long j = 0; j < frame_count; ++j) {
    const long frame = shard_frame(range, shard, j);
    std::vector<std::string> paths;
    bool all_exist = true;
    for (std::size_t k = 0; k < a.outputs.size(); ++k) {
      paths.push_back(path(k, frame));
      std::error_code ec;
      all_exist = all_exist && fs::is_regular_file(fs::symlink_status(paths.back(), ec));
    }
    // A single render always overwrites; frame lists and batches resume.
    if (all_exist && !a.force && (a.frames || run.batch)) {
      ++skipped;
      if (!a.quiet) std::printf("%s: exists, skipped\n", paths[0].c_str());
      if (frame_progress) frame_progress->update(++done, std::to_string(frame));
      continue;
    }
    for (const std::string& p : paths) check_not_input(p, inputs);
    // A PNG output is tone mapped tile by tile on the renderer's threads, each tile right
    // after it is drawn; .hdr, .exr and the hash read the linear colour (with MSAA the box
    // resolve, made per tile: the samples are not kept).
    const auto png_at = std::find(run.formats.begin(), run.formats.end(), Format::Png);
    const bool png = png_at != run.formats.end();
    // The frame's scene: with --fps the model at frame / fps (turning only with
    // --turntable), else the turntable's frame.
    pbr::Scene scene = file.scene;
    if (settings.fps) {
      try {
        job::pose_frame(file, settings, frame, scene, renderer.pool());
      } catch (const pbr::LoadError& e) {
        throw Error(kExitInput, e.what());
      }
    }
    if (!settings.fps || a.turntable) scene = pbr::animate(scene, file.animation, frame);
    run.frame.render(scene, s, renderer, {.rgba8 = png, .linear = true});
    const raster::Target& linear = run.frame.linear();
    // Then three independent jobs on the renderer's threads: the hash (XXH3 of the linear
    // colour, one a pixel: the resolve with MSAA), the count of non-finite pixels, the PNG
    // encoding.
    const auto scale = static_cast<float>(softpbr::dmath::exp2(s.output.exposure));  // as .hdr and .exr apply it
    std::uint64_t hash = 0;
    std::size_t non_finite = 0;
    std::vector<std::uint8_t> png_bytes;
    std::exception_ptr png_error;
    const std::string& png_name = png ? paths[static_cast<std::size_t>(png_at - run.formats.begin())] : paths[0];
    renderer.pool().parallel_for(3, [&](std::size_t job_index) {
      if (job_index == 0) {
        hash = raster::hash_colors(linear);
      } else if (job_index == 1 && !a.quiet) {
        // Not silent: a colour beyond float (emissive or lights near 1e30 summed, or scaled
        // by --exposure) is stored as 0 by .hdr and .exr while the PNG shows it white.
        for (const glm::vec4& c : linear.colors()) {
          const glm::vec3 v = glm::vec3(c) * scale;
          non_finite += !(std::isfinite(v.r) && std::isfinite(v.g) && std::isfinite(v.b));
        }
      } else if (job_index == 2 && png) {
        try {
          png_bytes = job::encode(run.frame, Format::Png, s.output, png_name);
        } catch (...) {
          png_error = std::current_exception();
        }
      }
    });
    if (non_finite > 0)
      std::fprintf(stderr, "softpbr: warning: %s: %zu pixels are not finite (a radiance beyond float, exposure included); .hdr and .exr store them as 0\n",
                   paths[0].c_str(), non_finite);
    // Every output of the frame is written to a temporary first, then all are renamed: on
    // any failure none is replaced.
    image::OutputFiles files;
    create_output_folders(paths);
    try {
      if (png_error) std::rethrow_exception(png_error);
      // .hdr and .exr hold one linear colour a pixel: with MSAA the box resolve of linear
      // radiance (as pbr::write_exr does).
      for (std::size_t i = 0; i < paths.size(); ++i) {
        if (run.formats[i] == Format::Png) files.add(paths[i], png_bytes);
        else files.add(paths[i], job::encode(run.frame, run.formats[i], s.output, paths[i]));
      }
      files.commit();
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw Error(kExitOutput, e.what());
    }
    if (!a.quiet)
      for (const std::string& p : paths)
        std::printf("%s: %dx%d, hash %016llx\n", p.c_str(), s.width, s.height, static_cast<unsigned long long>(hash));
    std::fflush(stdout);
    if (frame_progress) frame_progress->update(++done, std::to_string(frame));
  }
  if (!a.quiet && frame_count > 1)
    std::printf("%ld frames: %ld rendered, %zu skipped (already complete)\n", frame_count,
                frame_count - static_cast<long>(skipped), skipped);
  return skipped < static_cast<std::size_t>(frame_count);
}

}  // namespace

int run_render(const RenderArgs& given) {
  // A scenario names the model and the settings it does not override (scenario.h).
  RenderArgs with_scenario;
  if (!given.scenario.empty()) {
    if (!given.scenes.empty())
      throw Error(kExitUsage, "--scenario: names its model; give no scene besides it (got " + given.scenes[0] + ")");
    if (given.frames) throw Error(kExitUsage, "--frames: a scenario is one image");
    with_scenario = given;
    const Scenario scenario = read_scenario(given.scenario, given.scenario_name);
    with_scenario.scenes = {scenario.model};
    apply_scenario(scenario, with_scenario.settings);
  } else if (given.scenes.empty()) {
    throw Error(kExitUsage, "render: expected a scene file or model (or --scenario FILE)");
  } else if (!given.scenario_name.empty()) {
    throw Error(kExitUsage, "--scenario-name: needs --scenario");
  }
  const RenderArgs& a = given.scenario.empty() ? given : with_scenario;
  // 1. The command line alone, before any work: values, formats, frame list, outputs.
  Run run;
  run.args = &a;
  if (!given.scenario.empty()) run.scenario = read_scenario(given.scenario, given.scenario_name);
  run.settings = a.settings;
  run.settings.max_memory_mib = a.max_memory_mib;
  run.settings.roots.assign(a.roots.begin(), a.roots.end());
  run.settings.env_cache = a.env_cache;
  try {
    job::validate(run.settings);
  } catch (const job::Error& e) {
    throw command_error(e);
  }
  const std::vector<std::string>& scenes = a.scenes;
  run.batch = scenes.size() > 1;
  if (run.batch && a.frames)
    throw Error(kExitUsage, "--frames: renders one scene; " + std::to_string(scenes.size()) + " inputs were given");
  // The outputs, checked for every input's names as for a single input's.
  std::set<std::string> distinct;
  for (const std::string& o : a.outputs) {
    if (run.batch && !has_input_pattern(o))
      throw Error(kExitUsage, o + ": with several inputs an output needs {name}, {index} or a folder ending in / "
                                  "(e.g. thumbs/{name}.png or thumbs/)");
    if (is_folder_output(o) && has_frame_pattern(o))
      throw Error(kExitUsage, o + ": a folder output has no frame number (write folder/{name}_####.png)");
    const std::string first = output_path(o, scenes[0], 0, 0);
    if (!has_frame_pattern(o)) check_writable(first);  // a device says so before its missing extension
    run.formats.push_back(output_format(first));
    for (std::size_t i = 1; i < scenes.size(); ++i) {
      const std::string name = output_path(o, scenes[i], i, 0);
      if (output_format(name) != run.formats.back())
        throw Error(kExitUsage, name + ": not the format of " + first + " (one output pattern, one format)");
    }
    if (!distinct.insert(o).second) throw Error(kExitUsage, o + ": given twice as an output");
  }
  run.range = a.frames ? parse_frames(*a.frames) : FrameRange{0, 0};
  run.shard = a.shard ? parse_shard(*a.shard) : Shard{};
  const FrameRange range = run.range;
  if (range.last > range.first)
    for (const std::string& o : a.outputs)
      if (!has_frame_pattern(o))
        throw Error(kExitUsage, o + ": with several frames an output needs a run of '#' for the frame number (e.g. out_####.png)");
  // The same file under two names ("a.png", "./a.png") is one output given twice; in a
  // batch, two inputs with one output name (a/x.glb and b/x.glb to {name}.png) are refused.
  std::map<fs::path, std::size_t> resolved;  // → the input
  for (std::size_t i = 0; i < scenes.size(); ++i)
    for (const std::string& pattern : a.outputs) {
      const std::string o = output_path(pattern, scenes[i], i, range.first);
      std::error_code ec;
      const fs::path p = fs::weakly_canonical(fs::absolute(o), ec);
      if (ec) continue;
      const auto found = resolved.emplace(p, i);
      if (found.second) continue;
      const std::size_t other = found.first->second;
      if (other == i) throw Error(kExitUsage, pattern + ": given twice as an output (under another name)");
      throw Error(kExitUsage, o + ": the output of both " + scenes[other] + " and " + scenes[i] + " (inputs " +
                                  std::to_string(other) + " and " + std::to_string(i) + "; tell them apart with {index})");
    }
  // Every output can be created: the first and the last frame's names (the longest).
  for (std::size_t i = 0; i < scenes.size(); ++i)
    for (const std::string& pattern : a.outputs) {
      check_writable(output_path(pattern, scenes[i], i, range.first));
      check_writable(output_path(pattern, scenes[i], i, range.last));
    }
  // No output is a file named on the command line (the others are checked as they load).
  for (const std::string& scene : scenes)
    if (const auto id = file_id(scene)) run.inputs.emplace(*id, scene);
  for (std::size_t i = 0; i < scenes.size(); ++i)
    for (const std::string& pattern : a.outputs) check_not_input(output_path(pattern, scenes[i], i, range.first), run.inputs);

  if (!run.batch) {
    Progress progress(!a.quiet && ::isatty(STDERR_FILENO), static_cast<std::size_t>(shard_frame_count(range, run.shard)), "frame");
    render_input(run, 0, &progress);
    return kExitOk;
  }

  // 5. A batch: the inputs k with k mod N = i for --shard i/N, one renderer for all; a bad
  // input is its one error line, the others are rendered, and the exit code is the first
  // failure's.
  const FrameRange inputs_range{0, static_cast<long>(scenes.size()) - 1};
  const long count = shard_frame_count(inputs_range, run.shard);
  if (count == 0 && !a.quiet)
    std::printf("shard %ld/%ld: no input of the %zu is this shard's (nothing to render)\n", run.shard.index,
                run.shard.count, scenes.size());
  const Shard input_shard = run.shard;
  run.shard = Shard{};  // each input has its one frame
  pbr::RenderSettings defaults;
  run.renderer.emplace(raster::RendererOptions{
      run.settings.threads ? static_cast<unsigned>(*run.settings.threads) : defaults.threads,
      run.settings.tile_size ? static_cast<int>(*run.settings.tile_size) : defaults.tile_size});
  if (run.renderer->threads() < run.renderer->requested_threads() && !a.quiet)
    std::fprintf(stderr, "softpbr: the system started %u of the %u threads asked for; rendering with %u (the same images)\n",
                 run.renderer->threads(), run.renderer->requested_threads(), run.renderer->threads());
  int status = kExitOk;
  std::size_t rendered = 0, skipped = 0, failed = 0;
  {
    Progress progress(!a.quiet && ::isatty(STDERR_FILENO), static_cast<std::size_t>(count), "model");
    for (long j = 0; j < count; ++j) {
      const auto i = static_cast<std::size_t>(shard_frame(inputs_range, input_shard, j));
      try {
        (render_input(run, i, nullptr) ? rendered : skipped) += 1;
      } catch (const Error& e) {
        progress.clear();
        std::fprintf(stderr, "%s\n", printable_line(e.what()).c_str());
        if (status == kExitOk) status = e.code();
        ++failed;
      } catch (const std::bad_alloc&) {
        progress.clear();
        std::fprintf(stderr, "%s: out of memory\n", printable_line(scenes[i]).c_str());
        if (status == kExitOk) status = kExitInput;
        ++failed;
      }
      progress.update(static_cast<std::size_t>(j + 1), fs::path(scenes[i]).filename().string());
    }
  }
  if (!a.quiet)
    std::printf("%ld inputs: %zu rendered, %zu skipped (already complete), %zu failed\n", count, rendered, skipped, failed);
  return status;
}

}  // namespace softpbr::cli
