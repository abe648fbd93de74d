// The render job (see render_job.h).
#include "softpbr/job/render_job.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <new>
#include <span>
#include <system_error>
#include <type_traits>
#include <utility>

#include "softpbr/dmath/dmath.h"
#include "softpbr/image/write.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/scene.h"

namespace softpbr::job {

namespace fs = std::filesystem;

Error::Error(Kind kind, std::string setting, std::string detail)
    : std::runtime_error(setting.empty() ? detail : setting + ": " + detail),
      kind_(kind),
      setting_(std::move(setting)),
      detail_(std::move(detail)) {}

std::string option_text(const Error& e) {
  if (e.setting().empty()) return e.detail();
  std::string option = e.setting();
  std::replace(option.begin(), option.end(), '_', '-');
  return "--" + option + ": " + e.detail();
}

namespace {

[[noreturn]] void bad_setting(const char* setting, std::string detail) {
  throw Error(Error::Kind::Setting, setting, std::move(detail));
}

template <class T>
std::string show_value(T v) {
  if constexpr (std::is_floating_point_v<T>) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
    return buf;
  } else {
    return std::to_string(v);
  }
}

template <class T>
void in_range(const char* setting, const std::optional<T>& value, T lo, T hi) {
  if (value && !(*value >= lo && *value <= hi))  // NaN too
    bad_setting(setting, "expected a value in [" + show_value(lo) + ", " + show_value(hi) + "], got " + show_value(*value));
}

bool lower_extension_is(const std::string& path, std::initializer_list<const char*> extensions) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return std::any_of(extensions.begin(), extensions.end(), [&](const char* e) { return ext == e; });
}

// The background setting: a mode, or a linear colour.
struct Background {
  enum class Kind { Environment, Blur, Transparent, Color } kind;
  glm::vec4 color{0.0f};
};
Background parse_background(const std::string& b) {
  if (b == "environment") return Background{Background::Kind::Environment};
  if (b == "blur") return Background{Background::Kind::Blur};
  if (b == "transparent") return Background{Background::Kind::Transparent};
  float rgb[3];
  char tail = 0;
  if (std::sscanf(b.c_str(), "%f,%f,%f%c", &rgb[0], &rgb[1], &rgb[2], &tail) != 3 || !std::isfinite(rgb[0]) ||
      !std::isfinite(rgb[1]) || !std::isfinite(rgb[2]) || rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0)
    bad_setting("background", "expected environment, blur, transparent or R,G,B (three numbers >= 0), got \"" + b + "\"");
  return Background{Background::Kind::Color, {rgb[0], rgb[1], rgb[2], 1.0f}};
}

// The settings of the image: given ones, or a scene's resolved values.
void check_image_settings(const Settings& s) {
  in_range("width", s.width, 1L, static_cast<long>(raster::kMaxTargetSize));
  in_range("height", s.height, 1L, static_cast<long>(raster::kMaxTargetSize));
  in_range("threads", s.threads, 0L, 1024L);
  if (s.tile_size && !(*s.tile_size >= raster::kMinTileSize && *s.tile_size <= raster::kMaxTileSize &&
                       raster::valid_tile_size(static_cast<int>(*s.tile_size))))
    bad_setting("tile_size", "expected an even size in [" + std::to_string(raster::kMinTileSize) + ", " +
                                 std::to_string(raster::kMaxTileSize) + "], got " + std::to_string(*s.tile_size));
  if (s.tonemap && !pbr::tone_map_from_name(*s.tonemap))
    bad_setting("tonemap", "expected one of none, reinhard, aces, neutral, got \"" + *s.tonemap + "\"");
  in_range("exposure", s.exposure, -64.0f, 64.0f);
  if (s.gamma && !(*s.gamma == 0.0f || (*s.gamma >= 0.1f && *s.gamma <= 10.0f)))
    bad_setting("gamma", "expected 0 (the sRGB curve) or a number in [0.1, 10], got " + show_value(*s.gamma));
  if (s.msaa && !(*s.msaa >= 1 && *s.msaa <= raster::kMaxSamples && raster::valid_sample_count(static_cast<int>(*s.msaa))))
    bad_setting("msaa", "expected 1, 4 or 8, got " + std::to_string(*s.msaa));
}

}  // namespace

void validate(const Settings& s) {
  check_image_settings(s);
  if (s.env_intensity && !(*s.env_intensity >= 0.0f && *s.env_intensity <= 1e6f))
    bad_setting("env_intensity", "expected a number in [0, 1e6], got " + show_value(*s.env_intensity));
  if (s.env_rotation && !std::isfinite(*s.env_rotation)) bad_setting("env_rotation", "expected a finite number of degrees");
  if (s.background) parse_background(*s.background);
  if (s.missing_images && *s.missing_images != "error" && *s.missing_images != "warn")
    bad_setting("missing-images", "expected error or warn, got \"" + *s.missing_images + "\"");
  if (s.occlusion && *s.occlusion != "on" && *s.occlusion != "off")
    bad_setting("occlusion", "expected on or off, got \"" + *s.occlusion + "\"");
  if (s.shadows && *s.shadows != "on" && *s.shadows != "off")
    bad_setting("shadows", "expected on or off, got \"" + *s.shadows + "\"");
  if (s.ground && *s.ground != "shadow" && *s.ground != "none")
    bad_setting("ground", "expected shadow or none, got \"" + *s.ground + "\"");
  if (s.pitch && !(*s.pitch >= -89.0f && *s.pitch <= 89.0f))
    bad_setting("pitch", "expected degrees in [-89, 89], got " + show_value(*s.pitch));
  if (s.yaw && !std::isfinite(*s.yaw)) bad_setting("yaw", "expected a finite number of degrees, got " + show_value(*s.yaw));
  if (s.time && !(*s.time >= -1e9 && *s.time <= 1e9))
    bad_setting("time", "expected a finite number of seconds in [-1e9, 1e9], got " + show_value(*s.time));
  if (s.animation && s.animation->empty()) bad_setting("animation", "expected an index or a name, got \"\"");
  if (s.fps && !(*s.fps > 0.0 && *s.fps <= 1000.0))
    bad_setting("fps", "expected frames per second in (0, 1000], got " + show_value(*s.fps));
  if (s.fps && s.time) bad_setting("fps", "frame f is the moment f / fps: give the frames' fps or one time, not both");
  if (s.camera && *s.camera < 0) bad_setting("camera", "expected an index >= 0, got " + std::to_string(*s.camera));
  if (s.variant && s.variant->empty()) bad_setting("variant", "expected a material variant's name or index, got \"\"");
  if (s.scene && s.scene->empty()) bad_setting("scene", "expected a scene's name or index, got \"\"");
  if (s.max_memory_mib && !(*s.max_memory_mib > 0 && *s.max_memory_mib <= 1e9))
    bad_setting("max_memory", "expected a number of MiB in (0, 1e9], got " + show_value(*s.max_memory_mib));
  for (const fs::path& r : s.roots) {
    std::error_code ec;
    if (!fs::is_directory(r, ec)) bad_setting("root", r.string() + " is not a folder");
  }
}

pbr::MissingImages missing_images(const Settings& s) {
  return s.missing_images == "warn" ? pbr::MissingImages::Warn : pbr::MissingImages::Error;
}

std::uint64_t requested_memory_limit(const Settings& s) {
  return s.max_memory_mib ? static_cast<std::uint64_t>(*s.max_memory_mib * 1048576.0) : pbr::kDefaultMemoryLimit;
}

namespace {

// At most this many moments are posed to frame an animation: a longer one is sampled at
// every k-th frame (k the smallest that fits), which may miss a pose between them.
constexpr long kMaxFramingPoses = 250;

// The union of the bounds of poseable `g` at the moments of frames 0, 1, … up to the first
// at or after the end of the animation (`animation`'s duration, or the longest of all):
// every frame f ≥ 0 is one of those poses (after its last key an animation holds it), so
// a camera framing them does not jump between frames (negative frames: the first key's
// pose, also frame 0's when the keys start at 0). `g` is left posed at frame 0.
pbr::Bounds animation_bounds(pbr::GltfScene& g, double fps, const std::string& animation, raster::ThreadPool& pool) {
  double duration = 0.0;
  for (std::size_t i = 0; i < g.animations.size(); ++i)
    if (animation.empty() || animation == std::to_string(i) || animation == g.animations[i].name)
      duration = std::max(duration, g.animations[i].duration);
  const double frames = std::ceil(duration * fps);  // duration ≤ 3.4e38 (a float key), fps ≤ 1000: finite
  const long last = frames >= static_cast<double>(kMaxFrame) ? kMaxFrame : static_cast<long>(frames);
  const long step = std::max(1L, (last + kMaxFramingPoses - 1) / kMaxFramingPoses);
  pbr::Bounds b = pbr::world_bounds(g.objects);  // frame 0 (loaded at 0 s)
  for (long f = step; f <= last; f += step) {
    g.pose(static_cast<double>(f) / fps, animation, &pool);
    b = pbr::merge(b, pbr::world_bounds(g.objects));
  }
  if (last % step != 0) {
    g.pose(static_cast<double>(last) / fps, animation, &pool);
    b = pbr::merge(b, pbr::world_bounds(g.objects));
  }
  g.pose(0.0, animation, &pool);
  return b;
}

}  // namespace

void pose_frame(const pbr::LoadedScene& loaded, const Settings& s, long frame, pbr::Scene& scene, raster::ThreadPool& pool) {
  if (!s.fps || loaded.poser == nullptr) return;
  pbr::GltfScene g;
  g.poser = loaded.poser;
  g.pose(static_cast<double>(frame) / *s.fps, s.animation.value_or(""), &pool);
  scene.objects = std::move(g.objects);
  if (!g.lights.empty()) scene.lights = std::move(g.lights);
  if (s.camera && static_cast<std::size_t>(*s.camera) < g.cameras.size())
    scene.camera = g.cameras[static_cast<std::size_t>(*s.camera)].camera;
}

// A glTF model as a scene (docs/scene-format.md, "glTF models"): pbr::gltf_scene_file with
// the settings' view (env "none": the light rig instead of the studio).
pbr::LoadedScene load_model(const std::string& input, const Settings& s, raster::ThreadPool& pool) {
  pbr::GltfScene g;
  std::optional<pbr::Bounds> frame_bounds;
  try {
    g = pbr::load_gltf(input, {.pool = &pool,
                               .memory_limit = requested_memory_limit(s),
                               .roots = s.roots,
                               .missing_images = missing_images(s),
                               .variant = s.variant.value_or(""),
                               .time = s.fps ? std::optional<double>(0.0) : s.time,
                               .animation = s.animation.value_or(""),
                               .poseable = s.fps.has_value(),
                               .scene_name = s.scene.value_or("")});
    if (s.fps) frame_bounds = animation_bounds(g, *s.fps, s.animation.value_or(""), pool);
  } catch (const std::bad_alloc&) {
    throw Error(Error::Kind::Memory, "",
                input + ": out of memory while loading it (the process's memory or address-space limit)");
  }
  pbr::GltfView view;
  if (s.width) view.width = static_cast<int>(*s.width);
  if (s.height) view.height = static_cast<int>(*s.height);
  view.width = std::clamp(view.width, 1, raster::kMaxTargetSize);  // validate() says so first
  view.height = std::clamp(view.height, 1, raster::kMaxTargetSize);
  if (s.yaw) view.yaw = *s.yaw;
  if (s.pitch) view.pitch = *s.pitch;
  if (s.camera) {
    if (*s.camera < 0 || static_cast<std::size_t>(*s.camera) >= g.cameras.size())  // validate() says so first when < 0
      bad_setting("camera", input + " has " + std::to_string(g.cameras.size()) + " cameras, no camera " +
                                std::to_string(*s.camera));
    view.camera = static_cast<int>(*s.camera);
  }
  view.environment = !s.env || *s.env != "none";
  view.pool = &pool;
  view.bounds = frame_bounds;
  std::vector<std::string> files = g.files;
  pbr::LoadedScene f;
  try {
    f = pbr::gltf_scene_file(std::move(g), view, input);
  } catch (const std::invalid_argument& e) {  // checked above
    throw Error(Error::Kind::Setting, "", e.what());
  }
  f.inputs = std::move(files);
  return f;
}

void apply_environment(pbr::LoadedScene& f, const Settings& a, raster::ThreadPool& pool) {
  pbr::Scene& s = f.scene;
  if (a.env) {
    if (*a.env == "none") {
      s.environment.map = nullptr;
      f.environment_bytes = 0;
      s.background_mode = pbr::BackgroundMode::Color;
    } else {
      if (!s.environment.map) s.background_mode = pbr::BackgroundMode::Environment;
      if (*a.env == "studio") {
        s.environment.map = pbr::Environment::studio();
      } else {
        f.inputs.push_back(*a.env);  // never an output (like the scene file, roots do not confine it)
        image::Limits limits;
        try {
          s.environment.map = pbr::load_environment(*a.env, {}, &pool, a.env_cache, limits, &f.warnings);
        } catch (const std::invalid_argument& e) {
          throw Error(Error::Kind::Input, "env", e.what());
        } catch (const std::runtime_error& e) {
          throw Error(Error::Kind::Input, "env", e.what());
        }
      }
      f.environment_bytes = s.environment.map->bytes();
    }
  }
  if (a.env_intensity) s.environment.intensity = *a.env_intensity;
  if (a.env_rotation) s.environment.rotation = *a.env_rotation;
  if (a.occlusion) s.environment.occlusion = *a.occlusion == "on";
  if (a.background) {
    const Background b = parse_background(*a.background);
    switch (b.kind) {
      case Background::Kind::Environment:
      case Background::Kind::Blur:
        if (!s.environment.map)
          throw Error(Error::Kind::Setting, "", "--background " + *a.background + ": the scene has no environment (give --env)");
        s.background_mode = b.kind == Background::Kind::Blur ? pbr::BackgroundMode::Blur : pbr::BackgroundMode::Environment;
        break;
      case Background::Kind::Transparent:
      case Background::Kind::Color:
        s.background_mode = pbr::BackgroundMode::Color;
        s.background = b.color;
        break;
    }
  }
}

void apply_shadows(pbr::Scene& scene, const Settings& a) {
  if (a.ground) scene.ground.shadow = *a.ground == "shadow";
  if (!a.shadows) return;
  for (pbr::Light& l : scene.lights) l.shadows = *a.shadows == "on";
}

pbr::LoadedScene load(const std::string& input, const Settings& s, raster::ThreadPool& pool) {
  pbr::LoadedScene file;
  if (lower_extension_is(input, {".gltf", ".glb"})) {
    file = load_model(input, s, pool);
  } else {
    if (s.variant)
      bad_setting("variant", "a glTF model's setting; in a scene file, a glTF object gives its own \"variant\"");
    if (s.fps) bad_setting("fps", "a glTF model's setting; a scene file's frames are its turntable's");
    if (s.scene) bad_setting("scene", "a glTF model's setting; in a scene file, a glTF object gives its own \"scene\"");
    file = pbr::load_scene_file(input, {.memory_limit = requested_memory_limit(s),
                                        .pool = &pool,
                                        .environment_cache = s.env_cache,
                                        .roots = s.roots,
                                        .missing_images = missing_images(s)});
  }
  apply_environment(file, s, pool);
  apply_shadows(file.scene, s);
  return file;
}

pbr::RenderSettings resolve(const pbr::RenderSettings& scene, const Settings& s) {
  pbr::RenderSettings r = scene;
  if (s.width) r.width = static_cast<int>(*s.width);
  if (s.height) r.height = static_cast<int>(*s.height);
  if (s.threads) r.threads = static_cast<unsigned>(*s.threads);
  if (s.tile_size) r.tile_size = static_cast<int>(*s.tile_size);
  if (s.tonemap) r.output.tone_map = pbr::tone_map_from_name(*s.tonemap).value_or(r.output.tone_map);
  if (s.exposure) r.output.exposure = *s.exposure;
  if (s.gamma) r.output.gamma = *s.gamma;
  if (s.msaa) r.msaa = static_cast<int>(*s.msaa);
  check_image_settings(s);
  // The result too (a scene's own values are checked by its loader; Python's may be any).
  Settings resolved;
  resolved.width = r.width;
  resolved.height = r.height;
  resolved.threads = static_cast<long>(r.threads);
  resolved.tile_size = r.tile_size;
  resolved.exposure = r.output.exposure;
  resolved.gamma = r.output.gamma;
  resolved.msaa = r.msaa;
  check_image_settings(resolved);
  return r;
}

MemoryEstimate estimate_memory(const pbr::LoadedScene& f, const pbr::RenderSettings& s) {
  std::uint64_t image = pbr::image_memory(s.width, s.height, s.msaa);
  if (f.scene.environment.map && f.scene.environment.occlusion) image += pbr::occlusion_memory(s.width, s.height);
  image += pbr::shadow_memory(f.scene);
  for (const pbr::Object& o : f.scene.objects)
    if (o.material.transmissive()) {
      image += pbr::transmission_memory(s.width, s.height);
      break;
    }
  return {image, f.mesh_bytes, f.texture_bytes, f.environment_bytes};
}

std::uint64_t physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page) : 0;
}

MemoryLimit memory_limit(std::uint64_t requested) {
  const std::uint64_t physical = physical_memory();
  if (physical != 0 && physical < requested) return {physical, true};
  return {requested, false};
}

void check_memory(const MemoryEstimate& estimate, const pbr::RenderSettings& s, const MemoryLimit& limit) {
  const std::uint64_t needed = estimate.total();
  if (needed > limit.bytes)
    throw Error(Error::Kind::Input, "",
                "a " + std::to_string(s.width) + "x" + std::to_string(s.height) + " render of this scene needs an estimated " +
                    pbr::format_bytes(needed) + ", over the limit of " + pbr::format_bytes(limit.bytes));
}

void render_into(const pbr::Scene& scene, const pbr::OutputSettings& output, raster::Renderer& renderer,
                 raster::Target& target, raster::Image8* rgba, raster::Target* linear) {
  // A PNG's image is tone mapped tile by tile on the renderer's threads, each tile right
  // after it is drawn (the same bytes as tone_map_to_rgba8 afterwards); with MSAA the linear
  // colour is the box resolve of each tile's samples, made while they are in cache.
  if (rgba != nullptr || linear != nullptr) pbr::render_outputs(scene, renderer, target, output, rgba, linear);
  else pbr::render(scene, renderer, target);
}

void Frame::render(const pbr::Scene& scene, const pbr::RenderSettings& s, raster::Renderer& renderer, Outputs outputs) {
  const bool resolve = outputs.linear && s.msaa > 1;
  if (!target_ || target_->width() != s.width || target_->height() != s.height || target_->samples() != s.msaa ||
      resolve != resolved_.has_value()) {
    target_.reset();  // the old one's memory first
    resolved_.reset();
    // With MSAA the samples are not kept (a transient target: each tile's are tone mapped
    // and resolved while in cache, never written back); `resolved_` holds the linear box
    // resolve.
    target_.emplace(s.width, s.height, s.msaa, &renderer.pool(), raster::SampleStorage::Transient);
    if (resolve) resolved_.emplace(s.width, s.height, 1, &renderer.pool());
  }
  render_into(scene, s.output, renderer, *target_, outputs.rgba8 ? &rgba_ : nullptr, resolve ? &*resolved_ : nullptr);
}

const raster::Target& Frame::linear() const {
  if (resolved_) return *resolved_;
  if (!target_ || target_->samples() != 1) throw std::logic_error("job::Frame::linear: the frame has no linear colour");
  return *target_;
}

raster::Target Frame::take_linear() {
  (void)linear();  // checks there is one
  raster::Target t = resolved_ ? std::move(*resolved_) : std::move(*target_);
  target_.reset();
  resolved_.reset();
  return t;
}

std::optional<Format> format_from_name(const std::string& name) {
  if (lower_extension_is(name, {".png"})) return Format::Png;
  if (lower_extension_is(name, {".hdr"})) return Format::Hdr;
  if (lower_extension_is(name, {".exr"})) return Format::Exr;
  return std::nullopt;
}

std::vector<std::uint8_t> encode(const Frame& frame, Format format, const pbr::OutputSettings& output,
                                 const std::string& name) {
  if (format == Format::Png) return image::encode_png(frame.rgba(), name);
  // The target's colour as float RGBA samples for the encoders (no copy), × 2^exposure as
  // pbr::write_hdr and write_exr apply it (dmath: the same bits everywhere).
  static_assert(sizeof(glm::vec4) == 4 * sizeof(float));
  const raster::Target& linear = frame.linear();
  const std::span<const glm::vec4> colors = linear.colors();
  const image::ImageViewF view{linear.width(), linear.height(),
                               std::span<const float>(reinterpret_cast<const float*>(colors.data()), colors.size() * 4)};
  const auto scale = static_cast<float>(dmath::exp2(output.exposure));
  return format == Format::Hdr ? image::encode_hdr(view, name, scale) : image::encode_exr(view, name, scale);
}

}  // namespace softpbr::job
