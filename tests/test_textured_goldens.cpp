// Golden images of textured scenes, and their bits across threads, tiles, lane widths and
// dispatch. The goldens were committed after looking at them: no seam at the wrap, no
// shimmer between mip levels, the floor's checkers fading evenly into grey at the horizon
// (sharper there with anisotropic filtering), holes cut cleanly by the alpha mask.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include "softpbr/golden/doctest_checks.h"

#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/textured_shading.h"
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
  int samples = 1;  // MSAA
};

std::vector<TexturedScene> textured_scenes() {
  return {
      {"textured_floor_trilinear", 320, 180, [] { return test::textured_floor(1); }},
      {"textured_floor_aniso16", 320, 180, [] { return test::textured_floor(16); }},
      {"textured_spheres", 320, 200, test::textured_spheres},
      {"alpha_modes", 320, 200, test::alpha_modes},
      // The fence's MASK material with alpha to coverage: holes with smooth rims.
      {"msaa4_alpha_modes", 320, 200, test::alpha_modes, 4},
  };
}

}  // namespace

TEST_CASE("golden textured images: every scene hashes to its committed golden, bit for bit") {
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  for (const TexturedScene& g : textured_scenes()) {
    CAPTURE(g.name);
    raster::Target target(g.width, g.height, g.samples);
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
    raster::Target reference(g.width - 7, g.height - 3, g.samples);  // partial edge tiles
    pbr::render(scene, reference_renderer, reference);
    const std::uint64_t color = raster::hash_colors(reference), depth = raster::hash_depths(reference);
    test::for_spread_of_render_configs(3, 0, [&](const raster::RendererOptions& options) {
      raster::Renderer r(options);
      raster::Target t(g.width - 7, g.height - 3, g.samples);
      pbr::render(scene, r, t);
      CHECK(raster::hash_colors(t) == color);
      CHECK(raster::hash_depths(t) == depth);
    });
  }
}

TEST_CASE("alpha to coverage (MASK at 4x and 8x): the holes' rims get partial coverage, uniform pixels are the 1x image's") {
  const pbr::Scene scene = test::alpha_modes();
  constexpr int kW = 320, kH = 200;
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  raster::Target one(kW, kH);
  pbr::render(scene, renderer, one);
  // The fence's cream (r ≥ g ≥ b, g and b not far below): no other object has it.
  const auto cream = [](glm::vec4 c) { return c.g <= c.r && c.g > 0.8f * c.r && c.b < c.g && c.b > 0.4f * c.g && c.r > 0.05f; };
  // The fence's box at 1x, less 3 pixels: its pane's silhouette lies outside.
  int x0 = kW, y0 = kH, x1 = -1, y1 = -1;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      if (cream(one.color(x, y))) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  REQUIRE(x1 - x0 > 40);
  REQUIRE(y1 - y0 > 40);
  x0 += 3, y0 += 3, x1 -= 3, y1 -= 3;
  int rims_at_1x = 0;  // pixels of the box whose 4-neighbourhood has both fence and hole
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      if (cream(one.color(x, y)) != cream(one.color(x + 1, y)) || cream(one.color(x, y)) != cream(one.color(x, y + 1))) ++rims_at_1x;
  for (const int n : {4, 8}) {
    CAPTURE(n);
    raster::Target multi(kW, kH, n);
    pbr::render(scene, renderer, multi);
    int partial = 0, differ = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        bool same = true;
        int fence = 0;
        for (int s = 0; s < n; ++s) {
          same = same && multi.sample_color(x, y, s) == multi.sample_color(x, y, 0);
          fence += cream(multi.sample_color(x, y, s)) ? 1 : 0;
        }
        // Every sample kept (sharpened alpha ≥ the last threshold, so alpha ≥ cutoff) or
        // none (alpha < cutoff): what the alpha test gives at 1x.
        if (same && !(multi.sample_color(x, y, 0) == one.color(x, y))) ++differ;
        // Inside the pane a pixel partly fence, partly hole is on a hole's rim.
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1 && fence > 0 && fence < n) ++partial;
      }
    MESSAGE(n << "x: " << partial << " partly covered pixels inside the fence (" << rims_at_1x
              << " rim pixels at 1x), " << differ << " uniform pixels differ from 1x");
    // The 1x image cuts each rim hard; here most rim pixels are partly covered.
    CHECK(partial > rims_at_1x / 2);
    CHECK(differ == 0);
  }
}

TEST_CASE("alpha to coverage of a constant alpha (no alpha texture) keeps all samples or none, as 1x does, even at the cutoff") {
  // glTF: alpha ≥ alphaCutoff renders opaque. A MASK material without a base colour texture
  // has one alpha over each pixel (no edge to smooth), so at 4× and 8× it must keep every
  // sample or none, like the 1× alpha test — also at alpha exactly the cutoff (glTF's
  // default 0.5 with a factor of 0.5) and a hair either side of it, where a ramp around
  // the cutoff would keep about half of each pixel's samples. So the frame must be, bit
  // for bit, the frame with the pane at alpha 1 (alpha ≥ cutoff) or without it (below).
  constexpr int kW = 160, kH = 100;
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  pbr::Scene scene = test::alpha_modes();
  REQUIRE(scene.objects[1].material.alpha_mode == pbr::AlphaMode::Mask);
  scene.objects[1].material.base_color_texture = {};
  scene.objects[1].material.alpha_cutoff = 0.5f;
  scene.objects[1].material.alpha = 1.0f;
  pbr::Scene without = scene;
  without.objects.erase(without.objects.begin() + 1);
  for (const int n : {1, 4, 8}) {
    CAPTURE(n);
    raster::Target with_pane(kW, kH, n), without_pane(kW, kH, n);
    pbr::render(scene, renderer, with_pane);
    pbr::render(without, renderer, without_pane);
    REQUIRE(raster::hash_colors(with_pane) != raster::hash_colors(without_pane));
    for (const float alpha : {0.5f, std::nextafter(0.5f, 1.0f), 0.5001f, std::nextafter(0.5f, 0.0f), 0.4999f, 0.25f}) {
      INFO("alpha ", static_cast<double>(alpha));
      pbr::Scene s = scene;
      s.objects[1].material.alpha = alpha;
      raster::Target t(kW, kH, n);
      pbr::render(s, renderer, t);
      const raster::Target& expected = alpha >= 0.5f ? with_pane : without_pane;
      CHECK(raster::hash_colors(t) == raster::hash_colors(expected));
      CHECK(raster::hash_depths(t) == raster::hash_depths(expected));
    }
  }
}

TEST_CASE("textured_streams: UV set 0 alone without a normal map, a second UV set or vertex colours") {
  pbr::Material m;
  m.base_color_texture.texture = test::srgb_texture(test::checker_image(8, 2));
  m.occlusion_texture.texture = m.base_color_texture.texture;
  m.emissive_texture.texture = m.base_color_texture.texture;
  m.metallic_roughness_texture.texture = m.base_color_texture.texture;
  m.base_color_texture.transform.rotation = 0.5f;
  const auto streams = [](const pbr::Material& mat, bool colors) {
    return pbr::textured_streams(pbr::prepare_textured_material(mat), colors);
  };
  CHECK(streams(m, false) == pbr::TexturedStreams::Uv0);
  CHECK(streams(pbr::Material{}, false) == pbr::TexturedStreams::Uv0);
  CHECK(streams(m, true) == pbr::TexturedStreams::All);
  for (pbr::TextureSlot pbr::Material::*slot : {&pbr::Material::base_color_texture, &pbr::Material::metallic_roughness_texture,
                                                 &pbr::Material::occlusion_texture, &pbr::Material::emissive_texture}) {
    pbr::Material uv1 = m;
    (uv1.*slot).uv_set = 1;
    CHECK(streams(uv1, false) == pbr::TexturedStreams::All);
    (uv1.*slot).texture = nullptr;  // an empty slot's UV set is not read
    CHECK(streams(uv1, false) == pbr::TexturedStreams::Uv0);
  }
  pbr::Material normal = m;
  normal.normal_texture.texture = m.base_color_texture.texture;
  CHECK(streams(normal, false) == pbr::TexturedStreams::All);
}

TEST_CASE("the UV-set-0 textured shader gives the full shader's bits: each scene again with white vertex colours") {
  // White vertex colours (factors × 1) change nothing in the image but make render() draw
  // every textured object with TexturedPbrShader instead of TexturedUv0PbrShader.
  for (const TexturedScene& g : textured_scenes()) {
    CAPTURE(g.name);
    const pbr::Scene scene = g.build();
    pbr::Scene full = scene;
    int textured = 0;
    for (pbr::Object& o : full.objects) {
      const pbr::Material& mat = o.material;
      const bool uses_textured = mat.textured() || mat.alpha_mode != pbr::AlphaMode::Opaque || mat.double_sided || mat.unlit;
      if (!uses_textured) continue;
      REQUIRE(pbr::textured_streams(pbr::prepare_textured_material(mat), false) == pbr::TexturedStreams::Uv0);
      auto mesh = std::make_shared<pbr::Mesh>(*o.mesh);
      mesh->colors.assign(mesh->vertices.size(), glm::vec4(1.0f));
      o.mesh = mesh;
      ++textured;
    }
    REQUIRE(textured > 0);
    for (const int lanes : {1, 8, 16}) {
      CAPTURE(lanes);
      raster::Renderer renderer({.threads = 2, .tile_size = 32, .lanes = lanes});
      raster::Target lean(g.width, g.height, g.samples), all(g.width, g.height, g.samples);
      pbr::render(scene, renderer, lean);
      pbr::render(full, renderer, all);
      CHECK(raster::hash_colors(lean) == raster::hash_colors(all));
      CHECK(raster::hash_depths(lean) == raster::hash_depths(all));
    }
  }
}
