// Golden images of the PBR scenes: any bit difference in the float colour buffer fails.
//
// Each scene's golden is tests/goldens/NAME.hash (64-bit FNV-1a of the float RGBA buffer,
// raster::hash_colors) with NAME.png beside it to look at. To accept an intended change,
// look at the new images, then run:  SOFTPBR_UPDATE_GOLDENS=1 ./scripts/test -R golden
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/obj.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/dmath.h"
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

std::string hex(std::uint64_t h) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

TEST_CASE("golden PBR images: every scene hashes to its committed golden, bit for bit") {
  const fs::path goldens = fs::path(SOFTPBR_SOURCE_DIR) / "tests" / "goldens";
  const fs::path actual_dir = fs::path(SOFTPBR_BINARY_DIR) / "golden-actual";
  const bool update = std::getenv("SOFTPBR_UPDATE_GOLDENS") && std::string(std::getenv("SOFTPBR_UPDATE_GOLDENS")) == "1";
  fs::create_directories(actual_dir);
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  for (const GoldenScene& g : golden_scenes()) {
    CAPTURE(g.name);
    raster::Target target(g.width, g.height);
    pbr::render(g.build(), renderer, target);
    const std::string got = hex(raster::hash_colors(target));
    const raster::Image8 image = pbr::tone_map_to_rgba8(target, g.output);
    const fs::path hash_file = goldens / (g.name + ".hash");
    if (update) {
      raster::write_png(goldens / (g.name + ".png"), image);
      std::ofstream(hash_file) << got << "\n";
      MESSAGE("updated golden " << g.name << " = " << got);
      continue;
    }
    std::string expected;
    std::ifstream(hash_file) >> expected;
    if (got != expected) raster::write_png(actual_dir / (g.name + ".png"), image);
    CHECK_MESSAGE(got == expected, "golden " << g.name << ": hash " << got << ", expected "
                           << (expected.empty() ? "(missing " + hash_file.string() + ")" : expected)
                           << ". The image is " << (actual_dir / (g.name + ".png")).string()
                           << "; if the change is intended, look at it and regenerate with "
                              "SOFTPBR_UPDATE_GOLDENS=1 ./scripts/test -R golden");
  }
}

TEST_CASE("the PBR gallery has the same bits at every SIMD lane width, thread count and tile size") {
  pbr::GalleryOptions o;
  o.rows = {"gold", "copper", "plastic_red"};
  o.segments = 32;
  const pbr::Scene scene = pbr::make_gallery(o);
  std::uint64_t reference = 0;
  struct Config {
    int lanes;
    unsigned threads;
    int tile;
  };
  const Config configs[] = {{1, 1, 64}, {4, 2, 64}, {8, 3, 32}, {16, 8, 16}, {0, 2, 128}, {4, 1, 8}, {16, 2, 256}};
  for (const Config& c : configs) {
    CAPTURE(c.lanes);
    CAPTURE(c.threads);
    CAPTURE(c.tile);
    raster::Renderer renderer({.threads = c.threads, .tile_size = c.tile, .lanes = c.lanes});
    raster::Target target(333, 187);
    pbr::render(scene, renderer, target);
    const std::uint64_t h = raster::hash_colors(target) ^ (raster::hash_depths(target) * 31);
    if (reference == 0) reference = h;
    CHECK(h == reference);
  }
}
