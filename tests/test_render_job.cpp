// The render job (softpbr::job, render_job.h) that the command, the Python module and the
// viewer share: its one set of setting messages, its memory estimate by field, and that it
// renders the bits the command's golden hashes and PNGs hold.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <doctest/doctest.h>

#include "shared_assets.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/image/load.h"
#include "softpbr/job/render_job.h"
#include "softpbr/loaders/format_bytes.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/pool.h"
#include "softpbr/raster/raster.h"

namespace job = softpbr::job;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

const fs::path kSource = fs::path(SOFTPBR_SOURCE_DIR);

// validate()'s error for `s` as Python words it and as the command does, or "" twice.
std::pair<std::string, std::string> errors_of(const job::Settings& s) {
  try {
    job::validate(s);
  } catch (const job::Error& e) {
    CHECK(e.kind() == job::Error::Kind::Setting);
    return {e.what(), job::option_text(e)};
  }
  return {"", ""};
}

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "render_job_tests" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("render job: every setting is checked with one message, named as Python's keyword or the command's option") {
  using P = std::pair<std::string, std::string>;
  CHECK(errors_of({}) == P{"", ""});
  CHECK(errors_of({.width = 0}) == P{"width: expected a value in [1, 16384], got 0", "--width: expected a value in [1, 16384], got 0"});
  CHECK(errors_of({.height = 20000}).first == "height: expected a value in [1, 16384], got 20000");
  CHECK(errors_of({.msaa = 3}) == P{"msaa: expected 1, 4 or 8, got 3", "--msaa: expected 1, 4 or 8, got 3"});
  CHECK(errors_of({.tonemap = "filmic"}).first == "tonemap: expected one of none, reinhard, aces, neutral, got \"filmic\"");
  CHECK(errors_of({.exposure = 100.0f}).first == "exposure: expected a value in [-64, 64], got 100");
  CHECK(errors_of({.exposure = NAN}).second == "--exposure: expected a value in [-64, 64], got nan");
  CHECK(errors_of({.gamma = 0.05f}) == P{"gamma: expected 0 (the sRGB curve) or a number in [0.1, 10], got 0.05",
                                        "--gamma: expected 0 (the sRGB curve) or a number in [0.1, 10], got 0.05"});
  CHECK(errors_of({.gamma = 0.0f}).first.empty());
  CHECK(errors_of({.gamma = 2.2f}).first.empty());
  CHECK(errors_of({.threads = -1}).second == "--threads: expected a value in [0, 1024], got -1");
  // The range and the parity of a tile size: one message, the separator '_' or '-'.
  CHECK(errors_of({.tile_size = 7}) == P{"tile_size: expected an even size in [8, 4096], got 7",
                                         "--tile-size: expected an even size in [8, 4096], got 7"});
  CHECK(errors_of({.tile_size = 4}).first == "tile_size: expected an even size in [8, 4096], got 4");
  CHECK(errors_of({.yaw = INFINITY}).second == "--yaw: expected a finite number of degrees, got inf");
  CHECK(errors_of({.pitch = 90.0f}).second == "--pitch: expected degrees in [-89, 89], got 90");
  CHECK(errors_of({.env_intensity = -1.0f}).second == "--env-intensity: expected a number in [0, 1e6], got -1");
  CHECK(errors_of({.env_rotation = NAN}).second == "--env-rotation: expected a finite number of degrees");
  CHECK(errors_of({.occlusion = "yes"}).second == "--occlusion: expected on or off, got \"yes\"");
  CHECK(errors_of({.shadows = "yes"}).second == "--shadows: expected on or off, got \"yes\"");
  CHECK(errors_of({.shadows = "yes"}).first == "shadows: expected on or off, got \"yes\"");
  CHECK(errors_of({.background = "pink"}).second ==
        "--background: expected environment, blur, transparent or R,G,B (three numbers >= 0), got \"pink\"");
  CHECK(errors_of({.background = "0.1,0.2,0.3"}).first.empty());
  CHECK(errors_of({.camera = -1}).second == "--camera: expected an index >= 0, got -1");
  CHECK(errors_of({.max_memory_mib = 0.0}).second == "--max-memory: expected a number of MiB in (0, 1e9], got 0");
  CHECK(errors_of({.roots = {"/no/such/folder"}}).second == "--root: /no/such/folder is not a folder");
}

TEST_CASE("render job: resolve() puts the settings over the scene's and checks the scene's own values too") {
  pbr::RenderSettings scene;
  const pbr::RenderSettings r = job::resolve(scene, {.width = 64, .msaa = 4, .tonemap = "aces", .gamma = 2.2f});
  CHECK(r.width == 64);
  CHECK(r.height == scene.height);
  CHECK(r.msaa == 4);
  CHECK(r.output.tone_map == pbr::ToneMap::Aces);
  CHECK(r.output.gamma == 2.2f);
  scene.tile_size = 7;  // Python's Scene.tile_size = 7 is only refused when it renders
  CHECK_THROWS_WITH_AS(job::resolve(scene, {}), "tile_size: expected an even size in [8, 4096], got 7", job::Error);
  CHECK(job::resolve(scene, {.tile_size = 16}).tile_size == 16);
}

TEST_CASE("render job: the memory estimate has the image, meshes, textures and environment in their own fields") {
  raster::ThreadPool pool(2);
  // Textures: textured.json's images, counted as texture bytes, none as mesh bytes.
  const std::string textured = (kSource / "examples/scenes/textured.json").string();
  const pbr::LoadedScene t = job::load(textured, {}, pool);
  const pbr::RenderSettings ts = job::resolve(t.render, {.width = 100, .height = 50, .msaa = 4});
  const job::MemoryEstimate m = job::estimate_memory(t, ts);
  CHECK(m.image == pbr::image_memory(100, 50, 4));
  CHECK(m.texture == t.texture_bytes);
  CHECK(m.texture > 0);
  CHECK(m.mesh == t.mesh_bytes);
  CHECK(m.environment == 0);
  CHECK(m.total() == m.image + m.mesh + m.texture + m.environment);
  // The environment: the scene file's, then --env studio / none over it.
  const fs::path dir = scratch("memory");
  std::ofstream(dir / "env.json") << R"({"environment": {}, "objects": [{"mesh": {"type": "cube"}}]})";
  const std::string env_scene = (dir / "env.json").string();
  const pbr::LoadedScene e = job::load(env_scene, {}, pool);
  const std::uint64_t studio = pbr::Environment::studio()->bytes();
  CHECK(job::estimate_memory(e, e.render).environment == studio);
  // The occlusion's buffers, counted with the image while occlusion is on.
  const pbr::RenderSettings& er = e.render;
  CHECK(job::estimate_memory(e, er).image == pbr::image_memory(er.width, er.height, er.msaa) + pbr::occlusion_memory(er.width, er.height));
  CHECK(job::estimate_memory(job::load(env_scene, {.occlusion = "off"}, pool), er).image ==
        pbr::image_memory(er.width, er.height, er.msaa));
  // The shadow maps: a directional light's 2048² depths with --shadows on (lights.json's
  // three lights: spot, directional, point — 16 + 16 + 24 MiB), none with off or by default.
  const std::string lights = (kSource / "examples/scenes/lights.json").string();
  const pbr::LoadedScene l = job::load(lights, {}, pool);
  const pbr::RenderSettings& lr = l.render;
  CHECK(job::estimate_memory(l, lr).image == pbr::image_memory(lr.width, lr.height, lr.msaa));
  const pbr::LoadedScene lit = job::load(lights, {.shadows = "on"}, pool);
  CHECK(pbr::shadow_memory(lit.scene) == (std::uint64_t{16 + 16 + 24} << 20));
  CHECK(job::estimate_memory(lit, lr).image == pbr::image_memory(lr.width, lr.height, lr.msaa) + (std::uint64_t{56} << 20));
  CHECK(job::estimate_memory(job::load(lights, {.shadows = "off"}, pool), lr).image ==
        pbr::image_memory(lr.width, lr.height, lr.msaa));
  CHECK(e.mesh_bytes < studio);  // the cube alone
  CHECK(job::estimate_memory(job::load(env_scene, {.env = "none"}, pool), e.render).environment == 0);
  CHECK(job::estimate_memory(job::load(env_scene, {.env = "studio"}, pool), e.render).environment == studio);
  // A glTF model: the studio it is lit by as environment bytes, its draws as mesh bytes.
  const std::string boxes = (kSource / "examples/viewer/tests/boxes.gltf").string();
  const pbr::LoadedScene g = job::load(boxes, {.width = 64, .height = 64}, pool);
  CHECK(g.environment_bytes == studio);
  CHECK(g.mesh_bytes > 0);
  CHECK(g.mesh_bytes < studio);
  CHECK(g.render.width == 64);
  // Over the limit: one message; the limit is bounded by the machine's memory.
  const job::MemoryLimit small{1000, false};
  const std::string over =
      "a 100x50 render of this scene needs an estimated " + pbr::format_bytes(m.total()) + ", over the limit of 1000 B";
  CHECK_THROWS_WITH_AS(job::check_memory(m, ts, small), over.c_str(), job::Error);
  CHECK_NOTHROW(job::check_memory(m, ts, job::memory_limit(pbr::kDefaultMemoryLimit)));
  if (const std::uint64_t physical = job::physical_memory()) {
    CHECK(job::memory_limit(physical * 2).machine);
    CHECK(job::memory_limit(physical * 2).bytes == physical);
    CHECK_FALSE(job::memory_limit(physical / 2).machine);
  }
}

TEST_CASE("render job: a setting the input cannot take, and an environment that cannot be read") {
  raster::ThreadPool pool(2);
  const std::string boxes = (kSource / "examples/viewer/tests/boxes.gltf").string();
  try {
    job::load(boxes, {.camera = 3}, pool);
    FAIL("camera 3 of a model without cameras loaded");
  } catch (const job::Error& e) {
    CHECK(e.kind() == job::Error::Kind::Setting);
    CHECK(job::option_text(e) == "--camera: " + boxes + " has 0 cameras, no camera 3");
  }
  const fs::path dir = scratch("input");
  std::ofstream(dir / "plain.json") << R"({"objects": [{"mesh": {"type": "cube"}}]})";
  CHECK_THROWS_WITH_AS(job::load((dir / "plain.json").string(), {.background = "blur"}, pool),
                       "--background blur: the scene has no environment (give --env)", job::Error);
  try {
    job::load((dir / "plain.json").string(), {.env = (dir / "missing.hdr").string()}, pool);
    FAIL("a missing environment file loaded");
  } catch (const job::Error& e) {
    CHECK(e.kind() == job::Error::Kind::Input);
    CHECK(e.setting() == "env");
  }
}

TEST_CASE("render job: the command's golden hash and PNG of lights.json") {
  // cli/tests/scenes.hashes and cli/tests/goldens/lights.png: what `softpbr render` wrote
  // before the job existed (640x400, 2 threads, 64-pixel tiles).
  std::ifstream hashes(kSource / "cli/tests/scenes.hashes");
  std::string name, want;
  while (hashes >> name >> want && name != "lights") {}
  REQUIRE(name == "lights");
  raster::ThreadPool pool(2);
  const job::Settings settings{.threads = 2, .tile_size = 64};
  const pbr::LoadedScene file = job::load((kSource / "examples/scenes/lights.json").string(), settings, pool);
  const pbr::RenderSettings s = job::resolve(file.render, settings);
  raster::Renderer renderer({s.threads, s.tile_size});
  job::Frame frame;
  frame.render(pbr::animate(file, 0), s, renderer, {.rgba8 = true, .linear = true});
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(raster::hash_colors(frame.linear())));
  CHECK(std::string(hex) == want);
  const std::vector<std::uint8_t> png = job::encode(frame, job::Format::Png, s.output, "lights.png");
  const auto golden = softpbr::image::load_png(kSource / "cli/tests/goldens/lights.png");
  CHECK(softpbr::image::load_png(png, "lights.png").rgba == golden.rgba);
}

TEST_CASE("render job: a frame with MSAA is pbr::render_outputs' image and resolve, the target kept between frames") {
  pbr::GalleryOptions options;
  options.segments = 12;
  const pbr::Scene scene = pbr::make_gallery(options);
  raster::Renderer renderer({.threads = 2, .tile_size = 16});
  pbr::RenderSettings s;
  s.width = 96;
  s.height = 54;
  s.msaa = 4;
  s.output = pbr::gallery_output();
  // As the command and Python rendered before: a transient target, the resolve beside it.
  raster::Target samples(s.width, s.height, s.msaa, &renderer.pool(), raster::SampleStorage::Transient);
  raster::Target resolve(s.width, s.height);
  raster::Image8 want;
  pbr::render_outputs(scene, renderer, samples, s.output, &want, &resolve);
  job::Frame frame;
  for (int i = 0; i < 2; ++i) {
    frame.render(scene, s, renderer, {.rgba8 = true, .linear = true});
    CHECK(frame.rgba().rgba == want.rgba);
    CHECK(raster::hash_colors(frame.linear()) == raster::hash_colors(resolve));
  }
  // Only the image (Python's render(), the viewer): no linear colour is kept.
  frame.render(scene, s, renderer, {.rgba8 = true});
  CHECK(frame.rgba().rgba == want.rgba);
  CHECK_THROWS_AS(frame.linear(), std::logic_error);
  // Only the linear colour (Python's render_hdr): taken out of the frame.
  frame.render(scene, s, renderer, {.linear = true});
  const raster::Target taken = frame.take_linear();
  CHECK(raster::hash_colors(taken) == raster::hash_colors(resolve));
}

// ---- Animated models (issue 50) ---------------------------------------------------------

TEST_CASE("animated frames (fps): frame i is the model at i/F, the camera framing the union of every frame's bounds") {
  const fs::path file = shared_assets::folder() / "gltf" / "Fox" / "glTF-Binary" / "Fox.glb";
  if (!fs::is_regular_file(file)) {
    MESSAGE("skipped: Fox is absent");
    return;
  }
  job::Settings s;
  s.fps = 10.0;
  s.animation = "Walk";
  s.width = 64;
  s.height = 48;
  s.env = "none";
  raster::ThreadPool pool(2);
  const pbr::LoadedScene f = job::load(file.string(), s, pool);
  REQUIRE(f.poser != nullptr);
  // The camera: framing_camera of the union of the bounds at 0, 0.1, … up to the first
  // moment at or after the animation's end, each loaded from the file alone.
  double duration = 0.0;
  for (const pbr::GltfAnimation& a : pbr::load_gltf(file).animations)
    if (a.name == "Walk") duration = a.duration;
  REQUIRE(duration > 0.3);
  pbr::Bounds all = pbr::world_bounds(pbr::load_gltf(file, {.time = 0.0, .animation = "Walk"}).objects);
  const pbr::Bounds first = all;
  for (long k = 1; k <= static_cast<long>(std::ceil(duration * 10.0)); ++k)
    all = pbr::merge(all, pbr::world_bounds(pbr::load_gltf(file, {.time = static_cast<double>(k) / 10.0, .animation = "Walk"}).objects));
  CHECK(!(all.min == first.min && all.max == first.max));  // the walk reaches beyond frame 0's bounds
  const pbr::Camera expected = pbr::framing_camera(all, 64.0f / 48.0f, 0.0f, static_cast<float>(softpbr::dmath::radians(15.0)));
  CHECK(f.scene.camera.position == expected.position);
  CHECK(f.scene.camera.target == expected.target);
  CHECK(f.scene.camera.far == expected.far);
  // Frame 3: the model loaded at 0.3 s, bit for bit; the camera does not move.
  for (const long frame : {3L, 0L, 3L}) {
    CAPTURE(frame);
    pbr::Scene scene = f.scene;
    job::pose_frame(f, s, frame, scene, pool);
    const pbr::GltfScene loaded = pbr::load_gltf(file, {.time = static_cast<double>(frame) / 10.0, .animation = "Walk"});
    REQUIRE(scene.objects.size() == loaded.objects.size());
    for (std::size_t i = 0; i < loaded.objects.size(); ++i) {
      CAPTURE(i);
      const pbr::Mesh& a = *scene.objects[i].mesh;
      const pbr::Mesh& b = *loaded.objects[i].mesh;
      REQUIRE(a.vertices.size() == b.vertices.size());
      CHECK(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(pbr::MeshVertex)) == 0);
      CHECK(std::memcmp(&scene.objects[i].transform, &loaded.objects[i].transform, sizeof(glm::mat4)) == 0);
    }
    CHECK(scene.camera.position == f.scene.camera.position);
  }
  // Settings: fps in (0, 1000], and not with a time.
  for (const double bad : {0.0, -1.0, 1001.0, std::nan("")}) {
    job::Settings b;
    b.fps = bad;
    CHECK_THROWS_AS(job::validate(b), job::Error);
  }
  job::Settings both;
  both.fps = 24.0;
  both.time = 1.0;
  CHECK_THROWS_WITH_AS(job::validate(both),
                       "fps: frame f is the moment f / fps: give the frames' fps or one time, not both", job::Error);
}
