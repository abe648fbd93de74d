// Golden images of the PBR scenes: any bit difference in the float colour buffer fails.
//
// Each scene's golden is tests/goldens/NAME.hash (XXH3-64 of the float RGBA buffer,
// raster::hash_colors) with NAME.png beside it, checked with CHECK_RENDER_MATCHES
// (softpbr/golden/doctest_checks.h). On failure the actual, diff and side-by-side images are in
// build/golden-output/goldens/. To accept an intended change, look at the new images, then
// run:  SOFTPBR_UPDATE_GOLDENS=1 ./scripts/test -R golden
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/golden/doctest_checks.h"

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

struct GoldenScene {
  std::string name;
  int width, height;
  std::function<pbr::Scene()> build;
  pbr::OutputSettings output = pbr::gallery_output();
};

pbr::Scene single_sphere(const pbr::Material& m) {
  pbr::GalleryOptions o;
  o.rows = {"gold"};
  o.columns = 1;
  pbr::Scene s = pbr::make_gallery(o);
  s.objects[0].material = m;
  s.objects[0].transform = glm::scale(glm::mat4(1.0f), glm::vec3(2.5f));  // radius 1
  s.camera.position = {0.0f, 0.0f, 3.4f};
  return s;
}

pbr::Scene grazing_light() {
  // A glossy plane lit by one point light skimming it from the left, seen from the right
  // at a low angle: the mirror direction of the grazing light, where Fresnel → 1.
  pbr::Scene s;
  auto plane = std::make_shared<pbr::Mesh>();
  const glm::vec3 n(0, 1, 0);
  plane->vertices = {{{-2, 0, -2}, n, {0, 0}}, {{-2, 0, 2}, n, {0, 1}}, {{2, 0, 2}, n, {1, 1}}, {{2, 0, -2}, n, {1, 0}}};
  plane->indices = {0, 1, 2, 0, 2, 3};
  pbr::Material m;
  m.base_color = {0.6f, 0.6f, 0.65f};
  m.roughness = 0.35f;
  s.objects.push_back({plane, m, glm::mat4(1.0f)});
  pbr::Light l;
  l.position = {-3.0f, 0.05f, 0.0f};
  l.intensity = 20.0f;
  s.lights.push_back(l);
  s.camera.position = {3.0f, 0.35f, 1.0f};
  s.camera.target = {-0.5f, 0.0f, 0.0f};
  s.camera.fovy = static_cast<float>(softpbr::dmath::radians(50.0));
  return s;
}

std::vector<GoldenScene> golden_scenes() {
  std::vector<GoldenScene> scenes;
  scenes.push_back({"gallery", 640, 360, [] { return pbr::make_gallery(); }});
  scenes.push_back({"gallery_spot", 640, 360, [] {
                      pbr::GalleryOptions o;
                      const auto spot = pbr::load_obj(fs::path(SOFTPBR_SOURCE_DIR) / "assets/models/spot/spot_triangulated.obj");
                      o.mesh = std::make_shared<pbr::Mesh>(pbr::merge_shapes(spot));
                      return pbr::make_gallery(o);
                    }});
  scenes.push_back({"metal_vs_dielectric", 240, 160, [] {
                      pbr::GalleryOptions o;
                      o.rows = {"silver", "plastic_blue"};
                      o.columns = 3;
                      o.first_roughness = 0.0f;
                      o.last_roughness = 1.0f;
                      pbr::Scene s = pbr::make_gallery(o);
                      s.camera.position = {0.0f, 0.0f, 4.0f};
                      return s;
                    }});
  scenes.push_back({"grazing_light", 200, 150, grazing_light});
  for (const pbr::NamedMaterial& p : pbr::material_presets())
    scenes.push_back({"preset_" + std::string(p.name), 96, 96, [m = p.material] { return single_sphere(m); }});
  return scenes;
}

}  // namespace

TEST_CASE("golden PBR images: every scene hashes to its committed golden, bit for bit") {
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  for (const GoldenScene& g : golden_scenes()) {
    CAPTURE(g.name);
    raster::Target target(g.width, g.height);
    pbr::render(g.build(), renderer, target);
    CHECK_RENDER_MATCHES(target, pbr::tone_map_to_rgba8(target, g.output), "goldens/" + g.name);
  }
}

TEST_CASE("the PBR gallery has the same bits with 1, 2, 3 and 8 threads, every tile size from 8 to 256 and every SIMD lane width") {
  // The whole default gallery (5 materials x 7 roughness values, 64-segment spheres) at a
  // size that is a multiple of no tile size, so edge tiles are partial.
  const pbr::Scene scene = pbr::make_gallery();
  constexpr int kW = 333, kH = 187;
  const unsigned threads[] = {1, 2, 3, 8};
  const int tiles[] = {8, 16, 32, 64, 128, 256};
  const int lanes[] = {0, 1, 4, 8, 16};  // 0: the widest the CPU runs; cycled over the grid
  std::uint64_t reference_color = 0, reference_depth = 0;
  int config = 0;
  for (const unsigned t : threads)
    for (const int tile : tiles) {
      const int lane = lanes[config++ % 5];
      CAPTURE(t);
      CAPTURE(tile);
      CAPTURE(lane);
      raster::Renderer renderer({.threads = t, .tile_size = tile, .lanes = lane});
      raster::Target target(kW, kH);
      pbr::render(scene, renderer, target);
      const std::uint64_t color = raster::hash_colors(target), depth = raster::hash_depths(target);
      if (config == 1) {
        reference_color = color;
        reference_depth = depth;
        // Not trivially equal: the 35 spheres cover more than an eighth of the frame (18%).
        int covered = 0;
        for (const float d : target.depths()) covered += d < 1.0f;
        REQUIRE(covered > kW * kH / 8);
      }
      CHECK(color == reference_color);
      CHECK(depth == reference_depth);
    }
  CHECK(config == 24);
}
