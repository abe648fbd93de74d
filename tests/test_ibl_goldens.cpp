// Golden images lit by environments (image-based lighting), and their bits across threads,
// tiles, lane widths and dispatch. Every golden was looked at before it was committed:
// mirror-like spheres reflect the map sharply and rough ones smoothly with no sparkle from
// the sun, dielectrics keep their colour, the background is the map (or its blur), and the
// glTF model matches its Khronos screenshot in everything the lighting does not change.
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>

#include "softpbr/golden/doctest_checks.h"

#include "softpbr/image/load.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"
#include "texture_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace test = softpbr::test;
namespace fs = std::filesystem;

namespace {

// ../shared beside the source tree, or the folder SOFTPBR_SHARED names (a worktree's build).
fs::path shared() {
  if (const char* s = std::getenv("SOFTPBR_SHARED")) return s;
  return fs::path(SOFTPBR_SOURCE_DIR) / ".." / "shared";
}

// The gallery's spheres (fewer segments: a smaller test), lit by `env` and its lights off:
// what the environment alone does to each metal and roughness.
pbr::Scene gallery_in(std::shared_ptr<const pbr::Environment> env, pbr::BackgroundMode background) {
  pbr::GalleryOptions o;
  o.segments = 32;
  pbr::Scene s = pbr::make_gallery(o);
  s.lights.clear();
  s.environment.map = std::move(env);
  s.background_mode = background;
  return s;
}

pbr::OutputSettings output() { return {0.0f, pbr::ToneMap::Aces, 0.0f}; }

std::shared_ptr<const pbr::Environment> shared_env(const char* file) {
  const fs::path p = shared() / "envmaps" / file;
  if (!fs::exists(p)) return nullptr;
  return pbr::load_environment(p);
}

}  // namespace

TEST_CASE("golden IBL images: the gallery and textured spheres in the built-in studio") {
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  {
    raster::Target t(320, 180);
    pbr::render(gallery_in(pbr::Environment::studio(), pbr::BackgroundMode::Environment), renderer, t);
    CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, output()), "goldens/ibl_gallery_studio");
    // Occlusion off: the image softpbr made before it had occlusion (this golden is that
    // image, kept), bit for bit.
    pbr::Scene off = gallery_in(pbr::Environment::studio(), pbr::BackgroundMode::Environment);
    off.environment.occlusion = false;
    pbr::render(off, renderer, t);
    CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, output()), "goldens/ibl_gallery_studio_no_occlusion");
  }
  {
    // Textured materials (TexturedPbrShader) with the point lights kept, a blurred background.
    pbr::Scene s = test::textured_spheres();
    s.environment.map = pbr::Environment::studio();
    s.environment.rotation = 60.0f;
    s.background_mode = pbr::BackgroundMode::Blur;
    raster::Target t(320, 200);
    pbr::render(s, renderer, t);
    CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, output()), "goldens/ibl_textured_blur");
  }
}

TEST_CASE("golden IBL images: spheres and a glTF model under both shared environments") {
  if (!fs::is_directory(shared() / "envmaps")) {
    MESSAGE("skipped: " << shared() / "envmaps" << " is absent");
    return;
  }
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  const fs::path bottle = shared() / "gltf" / "WaterBottle" / "glTF" / "WaterBottle.gltf";
  pbr::GltfScene model;
  const bool have_model = fs::exists(bottle);
  if (have_model) model = pbr::load_gltf(bottle, {.pool = &renderer.pool()});
  for (const auto& [file, name] : {std::pair{"venice_sunset_1k.hdr", "venice"}, std::pair{"studio_small_03_1k.hdr", "studio3"}}) {
    const std::string golden = name;
    CAPTURE(golden);
    const auto env = shared_env(file);
    REQUIRE(env != nullptr);
    raster::Target t(320, 180);
    pbr::render(gallery_in(env, pbr::BackgroundMode::Environment), renderer, t);
    CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, output()), "goldens/ibl_gallery_" + golden);
    if (!have_model) continue;
    pbr::Scene s;
    s.objects = model.objects;
    s.camera = pbr::framing_camera(pbr::world_bounds(s.objects), 1.0f, 0.0f, 0.0f);
    s.environment.map = env;
    s.background_mode = pbr::BackgroundMode::Blur;
    raster::Target m(240, 240);
    pbr::render(s, renderer, m);
    CHECK_RENDER_MATCHES(m, pbr::tone_map_to_rgba8(m, output()), "goldens/ibl_waterbottle_" + golden);
  }
}

TEST_CASE("IBL scenes have the same bits for every thread count, tile size, lane width and dispatch") {
  std::vector<std::pair<std::string, pbr::Scene>> scenes;
  scenes.emplace_back("gallery", gallery_in(pbr::Environment::studio(), pbr::BackgroundMode::Environment));
  pbr::Scene textured = test::textured_spheres();
  textured.environment.map = pbr::Environment::studio();
  textured.environment.rotation = 60.0f;
  textured.environment.multiscatter = false;
  textured.background_mode = pbr::BackgroundMode::Blur;
  scenes.emplace_back("textured", textured);
  for (const auto& entry : scenes) {
    // Not structured bindings: Clang 14 cannot capture them in a lambda.
    const std::string& label = entry.first;
    const pbr::Scene& scene = entry.second;
    CAPTURE(label);
    raster::Renderer reference_renderer({.threads = 1, .tile_size = 64, .lanes = 1, .dispatch = false});
    raster::Target reference(313, 177);  // partial edge tiles
    pbr::render(scene, reference_renderer, reference);
    const std::uint64_t color = raster::hash_colors(reference), depth = raster::hash_depths(reference);
    test::for_spread_of_render_configs(4, 32, [&](const raster::RendererOptions& options) {
      raster::Renderer r(options);
      raster::Target t(313, 177);
      pbr::render(scene, r, t);
      CHECK(raster::hash_colors(t) == color);
      CHECK(raster::hash_depths(t) == depth);
    });
  }
}

TEST_CASE("backgrounds: transparent leaves alpha 0 around the objects, an environment background needs a map") {
  pbr::Scene s = gallery_in(pbr::Environment::studio(), pbr::BackgroundMode::Color);
  s.background = {0.0f, 0.0f, 0.0f, 0.0f};
  raster::Renderer renderer({.threads = 2});
  raster::Target t(160, 90);
  pbr::render(s, renderer, t);
  const raster::Image8 im = pbr::tone_map_to_rgba8(t, output());
  CHECK(im.rgba[3] == 0);                                    // a corner: no object
  CHECK(im.rgba[(static_cast<std::size_t>(45) * 160 + 80) * 4 + 3] == 255);  // the middle sphere
  // Lit by the environment although the background is a colour.
  CHECK(im.rgba[(static_cast<std::size_t>(45) * 160 + 80) * 4 + 0] > 40);
  pbr::Scene no_map = s;
  no_map.environment.map = nullptr;
  no_map.background_mode = pbr::BackgroundMode::Blur;
  CHECK_THROWS_AS(pbr::render(no_map, renderer, t), std::invalid_argument);
  pbr::Scene bad = s;
  bad.environment.intensity = -1.0f;
  CHECK_THROWS_AS(pbr::render(bad, renderer, t), std::invalid_argument);
}
