// `softpbr render` (see render.h).
#include "render.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <new>
#include <set>
#include <system_error>

#include "cli_error.h"
#include "frames.h"
#include "softpbr/image/write.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/gltf.h"
#include "softpbr/pbr/scene_file.h"
#include "softpbr/raster/raster.h"

namespace softpbr::cli {

namespace fs = std::filesystem;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

CLI::App* add_render_command(CLI::App& app, RenderArgs& a) {
  CLI::App* c = app.add_subcommand("render", "Render a scene file to .png, .hdr and/or .exr images");
  c->add_option("scene", a.scene,
                "Scene file (JSON, see docs/scene-format.md), or a glTF 2.0 model (.gltf, .glb) shown with an automatic "
                "camera and light rig")
      ->required();
  c->add_option("-o,--output", a.outputs,
                "Output file, format from the extension: .png (tone mapped, 8-bit), .hdr (linear "
                "Radiance RGBE) or .exr (linear float RGBA). Repeat for several. With --frames, #### is replaced by the frame number")
      ->required()
      ->allow_extra_args(false);  // one file per -o, so "-o out.png scene.json" works
  a.width_opt = c->add_option("--width", a.width, "Image width in pixels (overrides the scene's render.width)");
  a.height_opt = c->add_option("--height", a.height, "Image height in pixels");
  a.threads_opt = c->add_option("--threads", a.threads, "Worker threads, 0 = all cores (the image is the same for any)");
  a.tile_opt = c->add_option("--tile-size", a.tile_size, "Screen tile size, even, 8..4096 (the image is the same for any)");
  a.tonemap_opt = c->add_option("--tonemap", a.tonemap, "Tone map: none, reinhard, aces, neutral");
  a.msaa_opt = c->add_option("--msaa", a.msaa, "Samples a pixel: 1 (no antialiasing), 4 or 8 (MSAA; overrides render.msaa)");
  a.exposure_opt = c->add_option("--exposure", a.exposure, "Exposure in stops (colour x 2^E before tone mapping)");
  a.frames_opt = c->add_option("--frames", a.frames,
                               "Frame range A..B (inclusive): the turntable animation of the scene's camera and "
                               "lights; frames whose outputs exist are skipped");
  a.shard_opt = c->add_option("--shard", a.shard, "i/N: render only the frames k of the range with k mod N = i (i from 0)");
  c->add_option("--yaw", a.yaw, "glTF models: turn the automatic camera this many degrees around the vertical axis");
  c->add_option("--pitch", a.pitch, "glTF models: raise the automatic camera this many degrees (-89..89)");
  a.camera_opt = c->add_option("--camera", a.camera, "glTF models: view through camera N of the file (from 0)");
  c->add_flag("--force", a.force, "Render frames even when their outputs exist");
  c->add_flag("-q,--quiet", a.quiet, "Print nothing but errors");
  a.max_memory_mib = static_cast<double>(pbr::kDefaultMemoryLimit >> 20);
  c->add_option("--max-memory", a.max_memory_mib, "Refuse renders estimated to need more than this many MiB")->capture_default_str();
  c->footer(kExitCodesHelp);
  return c;
}

namespace {

bool is_gltf(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext == ".gltf" || ext == ".glb";
}

// A glTF model as a scene (docs/scene-format.md, "glTF models"): its objects and lights, a
// camera of the file or pbr::framing_camera, the default light rig when it has no lights.
pbr::SceneFile gltf_scene(const RenderArgs& a, raster::ThreadPool& pool) {
  pbr::SceneFile f;
  pbr::GltfScene g;
  try {
    g = pbr::load_gltf(a.scene, {.pool = &pool});
  } catch (const pbr::LoadError& e) {
    throw Error(kExitInput, e.what());
  }
  f.warnings = g.warnings;
  f.scene.objects = std::move(g.objects);
  f.triangles = g.triangles;
  const int w = a.width_opt->count() ? a.width : f.render.width, h = a.height_opt->count() ? a.height : f.render.height;
  if (a.camera_opt->count()) {
    if (a.camera < 0 || static_cast<std::size_t>(a.camera) >= g.cameras.size())
      throw Error(kExitUsage, "--camera: " + a.scene + " has " + std::to_string(g.cameras.size()) + " cameras, no camera " +
                                  std::to_string(a.camera));
    f.scene.camera = g.cameras[static_cast<std::size_t>(a.camera)].camera;
  } else {
    if (!(a.pitch >= -89.0f && a.pitch <= 89.0f) || !std::isfinite(a.yaw))
      throw Error(kExitUsage, "--pitch: expected degrees in [-89, 89]; --yaw: a finite number of degrees");
    f.scene.camera = pbr::framing_camera(pbr::world_bounds(f.scene.objects), static_cast<float>(w) / static_cast<float>(h),
                                         static_cast<float>(softpbr::dmath::radians(a.yaw)),
                                         static_cast<float>(softpbr::dmath::radians(a.pitch)));
  }
  f.scene.lights = g.lights.empty() ? pbr::default_light_rig(f.scene.camera) : std::move(g.lights);
  f.scene.ambient = glm::vec3(pbr::kDefaultAmbient);
  f.scene.background = {0.05f, 0.05f, 0.06f, 1.0f};
  // Memory: the meshes and their draws (18 varyings: the textured shader's), and textures.
  std::set<const void*> seen;
  for (const pbr::Object& o : f.scene.objects) {
    f.mesh_bytes += raster::draw_geometry_bytes(o.mesh->vertices.size(), o.mesh->triangle_count(), 18);
    if (seen.insert(o.mesh.get()).second)
      f.mesh_bytes += o.mesh->vertices.size() * sizeof(pbr::MeshVertex) + o.mesh->indices.size() * 4;
    for (const pbr::TextureSlot* t : {&o.material.base_color_texture, &o.material.metallic_roughness_texture,
                                      &o.material.normal_texture, &o.material.occlusion_texture,
                                      &o.material.emissive_texture})
      if (t->texture && seen.insert(t->texture.get()).second) f.mesh_bytes += t->texture->texel_bytes();
  }
  return f;
}

enum class Format { Png, Hdr, Exr };

Format output_format(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext == ".png") return Format::Png;
  if (ext == ".hdr") return Format::Hdr;
  if (ext == ".exr") return Format::Exr;
  throw Error(kExitUsage, path + ": unknown output format \"" + ext + "\" (expected .png, .hdr or .exr)");
}

// Fails early, before any rendering, when an output cannot be created.
void check_writable(const std::string& path) {
  const fs::path p(path);
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error(kExitOutput, path + ": cannot write: the folder " + dir.string() + " does not exist");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw Error(kExitOutput, path + ": cannot write: no permission to create files in " + dir.string());
  if (fs::is_directory(p, ec)) throw Error(kExitOutput, path + ": cannot write: it is a folder");
}

template <class T>
T in_range(const char* name, T value, T lo, T hi) {
  if (value < lo || value > hi)
    throw Error(kExitUsage, std::string(name) + ": expected a value in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got " + std::to_string(value));
  return value;
}

std::uint64_t physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : 0;
}

// Temporary files an interrupted run left beside its outputs (".NAME.tmpNNN", see
// image::write_file_atomic), by the output path they were meant to become.
std::multimap<fs::path, fs::path> stale_temporaries(const std::set<fs::path>& folders) {
  std::multimap<fs::path, fs::path> out;
  for (const fs::path& dir : folders) {
    std::error_code ec;
    for (fs::directory_iterator it(dir.empty() ? fs::path(".") : dir, ec), end; !ec && it != end; it.increment(ec)) {
      const std::string name = it->path().filename().string();
      const auto tmp = name.rfind(".tmp");
      if (name.size() > 1 && name[0] == '.' && tmp != std::string::npos && tmp > 1)
        out.emplace(dir / name.substr(1, tmp - 1), it->path());
    }
  }
  return out;
}

class Progress {
 public:
  Progress(bool enabled, std::size_t total) : enabled_(enabled), total_(total), start_(Clock::now()) {}
  void update(std::size_t done, long frame) {
    if (!enabled_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
    const double per = done > 0 ? elapsed / static_cast<double>(done) : 0.0;
    std::fprintf(stderr, "\r\033[Ksoftpbr: frame %ld, %zu/%zu done, %.2f s/frame, %.0f s left", frame, done, total_, per,
                 per * static_cast<double>(total_ - done));
    std::fflush(stderr);
  }
  ~Progress() {
    if (enabled_) std::fputs("\r\033[K", stderr);
  }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_;
  std::size_t total_;
  Clock::time_point start_;
};

}  // namespace

int run_render(const RenderArgs& a) {
  // 1. The command line alone: formats, frame list, output folders.
  std::vector<Format> formats;
  std::set<std::string> distinct;
  for (const std::string& o : a.outputs) {
    formats.push_back(output_format(o));
    has_frame_pattern(o);  // throws for several runs of '#'
    if (!distinct.insert(o).second) throw Error(kExitUsage, o + ": given twice as an output");
  }
  const FrameRange range = a.frames_opt->count() ? parse_frames(a.frames) : FrameRange{0, 0};
  const Shard shard = a.shard_opt->count() ? parse_shard(a.shard) : Shard{};
  if (range.last > range.first)
    for (const std::string& o : a.outputs)
      if (!has_frame_pattern(o))
        throw Error(kExitUsage, o + ": with several frames an output needs a run of '#' for the frame number (e.g. out_####.png)");
  std::set<fs::path> folders;
  for (const std::string& o : a.outputs) {
    check_writable(frame_path(o, range.first));
    folders.insert(fs::path(o).parent_path());
  }
  if (!(a.max_memory_mib > 0 && a.max_memory_mib <= 1e9))
    throw Error(kExitUsage, "--max-memory: expected a number of MiB in (0, 1e9], got " + std::to_string(a.max_memory_mib));
  const auto memory_limit = static_cast<std::uint64_t>(a.max_memory_mib * 1048576.0);

  // 2. The scene, with command-line overrides.
  pbr::SceneFile file;
  // A glTF model's images decode on a pool of the threads the render will use.
  const unsigned load_threads = a.threads_opt->count() ? static_cast<unsigned>(in_range("--threads", a.threads, 0, 1024)) : 0;
  if (is_gltf(a.scene)) {
    raster::ThreadPool pool(load_threads);
    file = gltf_scene(a, pool);
  } else {
    try {
      file = pbr::load_scene_file(a.scene, {memory_limit});
    } catch (const pbr::SceneFileError& e) {
      throw Error(kExitInput, e.what());
    }
  }
  if (!a.quiet)
    for (const std::string& w : file.warnings) std::fprintf(stderr, "softpbr: warning: %s\n", w.c_str());
  pbr::RenderSettings s = file.render;
  if (a.width_opt->count()) s.width = in_range("--width", a.width, 1, raster::kMaxTargetSize);
  if (a.height_opt->count()) s.height = in_range("--height", a.height, 1, raster::kMaxTargetSize);
  if (a.threads_opt->count()) s.threads = static_cast<unsigned>(in_range("--threads", a.threads, 0, 1024));
  if (a.tile_opt->count()) {
    s.tile_size = in_range("--tile-size", a.tile_size, raster::kMinTileSize, raster::kMaxTileSize);
    if (!raster::valid_tile_size(s.tile_size)) throw Error(kExitUsage, "--tile-size: expected an even size, got " + std::to_string(s.tile_size));
  }
  if (a.tonemap_opt->count()) {
    const auto op = pbr::tone_map_from_name(a.tonemap);
    if (!op) throw Error(kExitUsage, "--tonemap: expected one of none, reinhard, aces, neutral, got \"" + a.tonemap + "\"");
    s.output.tone_map = *op;
  }
  if (a.exposure_opt->count()) s.output.exposure = in_range("--exposure", a.exposure, -64.0f, 64.0f);
  if (a.msaa_opt->count()) {
    if (!raster::valid_sample_count(a.msaa)) throw Error(kExitUsage, "--msaa: expected 1, 4 or 8, got " + std::to_string(a.msaa));
    s.msaa = a.msaa;
  }

  // 3. Memory, before the target is allocated.
  const std::uint64_t physical = physical_memory();
  const std::uint64_t limit = physical ? std::min(memory_limit, physical) : memory_limit;
  const std::uint64_t needed = pbr::image_memory(s.width, s.height, s.msaa) + file.mesh_bytes + file.texture_bytes;
  if (needed > limit) {
    const bool from_cli = a.width_opt->count() || a.height_opt->count();
    const std::string where = from_cli ? "--width " + std::to_string(s.width) + " --height " + std::to_string(s.height)
                                       : a.scene + ": /render";
    throw Error(kExitInput, where + ": a " + std::to_string(s.width) + "x" + std::to_string(s.height) +
                                " render of this scene needs an estimated " + pbr::format_bytes(needed) +
                                ", over the limit of " + pbr::format_bytes(limit) +
                                (limit == memory_limit ? " (--max-memory)" : " (the machine's memory)"));
  }

  // 4. The frames of this shard.
  const long frame_count = shard_frame_count(range, shard);
  auto stale = stale_temporaries(folders);
  raster::Renderer renderer(raster::RendererOptions{s.threads, s.tile_size});
  if (renderer.threads() < renderer.requested_threads() && !a.quiet)
    std::fprintf(stderr, "softpbr: the system started %u of the %u threads asked for; rendering with %u (the same images)\n",
                 renderer.threads(), renderer.requested_threads(), renderer.threads());
  raster::Target target(s.width, s.height, s.msaa);
  Progress progress(!a.quiet && ::isatty(STDERR_FILENO), static_cast<std::size_t>(frame_count));
  std::size_t done = 0, skipped = 0;
  for (long j = 0; j < frame_count; ++j) {
    const long frame = shard_frame(range, shard, j);
    std::vector<std::string> paths;
    bool all_exist = true;
    for (const std::string& o : a.outputs) {
      paths.push_back(frame_path(o, frame));
      std::error_code ec;
      all_exist = all_exist && fs::is_regular_file(paths.back(), ec);
    }
    if (all_exist && !a.force && a.frames_opt->count()) {  // a single render always overwrites
      ++skipped;
      if (!a.quiet) std::printf("%s: exists, skipped\n", paths[0].c_str());
      progress.update(++done, frame);
      continue;
    }
    pbr::render(pbr::animate(file, frame), renderer, target);
    const std::uint64_t hash = raster::hash_colors(target);
    for (std::size_t i = 0; i < paths.size(); ++i) {
      for (auto [it, end] = stale.equal_range(fs::path(paths[i])); it != end; ++it) {
        std::error_code ignored;
        fs::remove(it->second, ignored);
      }
      try {
        if (formats[i] == Format::Png) image::write_png(paths[i], pbr::tone_map_to_rgba8(target, s.output));
        else if (formats[i] == Format::Hdr) pbr::write_hdr(paths[i], target, s.output.exposure);
        else pbr::write_exr(paths[i], target, s.output.exposure);
      } catch (const std::bad_alloc&) {
        throw;
      } catch (const std::exception& e) {
        throw Error(kExitOutput, e.what());
      }
      if (!a.quiet) std::printf("%s: %dx%d, hash %016llx\n", paths[i].c_str(), s.width, s.height, static_cast<unsigned long long>(hash));
    }
    std::fflush(stdout);
    progress.update(++done, frame);
  }
  if (!a.quiet && frame_count > 1)
    std::printf("%ld frames: %ld rendered, %zu skipped (already complete)\n", frame_count,
                frame_count - static_cast<long>(skipped), skipped);
  return kExitOk;
}

}  // namespace softpbr::cli
