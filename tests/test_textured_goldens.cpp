// Golden images of textured scenes, and their bits across threads, tiles, lane widths and
// dispatch. The goldens were committed after looking at them: no seam at the wrap, no
// shimmer between mip levels, the floor's checkers fading evenly into grey at the horizon
// (sharper there with anisotropic filtering), holes cut cleanly by the alpha mask.
#include <functional>
#include <string>

#include "softpbr/golden/doctest_checks.h"

#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"
#include "texture_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace test = softpbr::test;

namespace {

struct TexturedScene {
  std::string name;
  int width, height;
  std::function<pbr::Scene()> build;
};

std::vector<TexturedScene> textured_scenes() {
  return {
      {"textured_floor_trilinear", 320, 180, [] { return test::textured_floor(1); }},
      {"textured_floor_aniso16", 320, 180, [] { return test::textured_floor(16); }},
      {"textured_spheres", 320, 200, test::textured_spheres},
      {"alpha_modes", 320, 200, test::alpha_modes},
  };
}

}  // namespace

TEST_CASE("golden textured images: every scene hashes to its committed golden, bit for bit") {
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  for (const TexturedScene& g : textured_scenes()) {
    CAPTURE(g.name);
    raster::Target target(g.width, g.height);
    pbr::render(g.build(), renderer, target);
    CHECK_RENDER_MATCHES(target, pbr::tone_map_to_rgba8(target, pbr::gallery_output()), "goldens/" + g.name);
  }
}

TEST_CASE("textured scenes have the same bits for every thread count, tile size, lane width and dispatch") {
  for (const TexturedScene& g : textured_scenes()) {
    CAPTURE(g.name);
    const pbr::Scene scene = g.build();
    // The reference: one thread, the scalar fragment() path (lanes = 1 calls the packet
    // code with F = float), the build's own code.
    raster::Renderer reference_renderer({.threads = 1, .tile_size = 64, .lanes = 1, .dispatch = false});
    raster::Target reference(g.width - 7, g.height - 3);  // partial edge tiles
    pbr::render(scene, reference_renderer, reference);
    const std::uint64_t color = raster::hash_colors(reference), depth = raster::hash_depths(reference);
    test::for_spread_of_render_configs(3, 0, [&](const raster::RendererOptions& options) {
      raster::Renderer r(options);
      raster::Target t(g.width - 7, g.height - 3);
      pbr::render(scene, r, t);
      CHECK(raster::hash_colors(t) == color);
      CHECK(raster::hash_depths(t) == depth);
    });
  }
}
