// A user's render tests: each renders a small scene and checks it against a golden PNG
// shipped in goldens/, exactly (softpbr renders the same bits on every build).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <softpbr/golden/doctest_checks.h>

#include <glm/glm.hpp>
#include <softpbr/pbr/gallery.h>
#include <softpbr/pbr/scene.h>
#include <softpbr/pbr/tonemap.h>
#include <softpbr/raster/raster.h>

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

// Two materials, three roughness values: a 3x2 corner of the PBR gallery.
pbr::Scene two_materials() {
  pbr::GalleryOptions options;
  options.rows = {"gold", "plastic_blue"};
  options.columns = 3;
  options.first_roughness = 0.2f;
  options.last_roughness = 0.8f;
  options.segments = 32;
  pbr::Scene scene = pbr::make_gallery(options);
  scene.camera.position = {0.0f, 0.0f, 3.5f};
  return scene;
}

TEST_CASE("the two-material scene looks as it did when its golden was accepted") {
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  raster::Target target(160, 112);
  pbr::render(two_materials(), renderer, target);
  const raster::Image8 image = pbr::tone_map_to_rgba8(target, pbr::gallery_output());
  CHECK_IMAGE_MATCHES(image, "goldens/two_materials.png");
}

TEST_CASE("the scene renders the same with any thread count and tile size, so one golden serves them all") {
  struct Config {
    unsigned threads;
    int tile;
  };
  for (const Config c : {Config{1, 16}, {2, 32}, {3, 128}}) {
    CAPTURE(c.threads);
    CAPTURE(c.tile);
    raster::Renderer renderer({.threads = c.threads, .tile_size = c.tile});
    raster::Target target(160, 112);
    pbr::render(two_materials(), renderer, target);
    CHECK_IMAGE_MATCHES(pbr::tone_map_to_rgba8(target, pbr::gallery_output()), "goldens/two_materials.png");
  }
}
