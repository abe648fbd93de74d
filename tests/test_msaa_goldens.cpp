// MSAA golden images and bit-exactness: the gallery and a thin-line scene at 4× and 8×
// (goldens/msaa*.hash + .png), the same bits across threads, tile sizes, lane widths and
// dispatch, pixels the same as the 1-sample image wherever all their samples agree, and the
// two resolves (tone map each sample, or resolve linear first) measured on the gallery.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "softpbr/golden/doctest_checks.h"

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

// 60 spokes from the centre and 9 nearly horizontal wires, 0.004 to 0.02 units wide
// (0.3 to 1.6 pixels at 320×240): lines thinner than a pixel, edges at every angle.
pbr::Scene thin_lines() {
  pbr::Scene s;
  auto mesh = std::make_shared<pbr::Mesh>();
  const glm::vec3 n(0, 0, 1);
  auto quad = [&](glm::vec2 a, glm::vec2 b, float width) {
    const glm::vec2 d = b - a;
    const float len = std::sqrt(d.x * d.x + d.y * d.y);  // correctly rounded (IEEE)
    const glm::vec2 side = glm::vec2(-d.y, d.x) * (0.5f * width / len);
    const auto base = static_cast<std::uint32_t>(mesh->vertices.size());
    for (const glm::vec2 p : {a - side, b - side, b + side, a + side}) mesh->vertices.push_back({{p.x, p.y, 0.0f}, n, {0, 0}});
    for (const std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh->indices.push_back(base + i);
  };
  for (int k = 0; k < 60; ++k) {
    const double angle = 2.0 * softpbr::dmath::kPi * k / 60.0 + 0.013;
    const float c = static_cast<float>(softpbr::dmath::cos(angle)), sn = static_cast<float>(softpbr::dmath::sin(angle));
    const glm::vec2 dir(c, sn);
    quad(dir * 0.12f, dir * 1.15f, 0.004f + 0.016f * static_cast<float>(k % 5) / 4.0f);
  }
  for (int k = 0; k < 9; ++k) {
    const float y = -1.3f + 0.06f * static_cast<float>(k);
    quad({-1.6f, y}, {1.6f, y + 0.02f + 0.01f * static_cast<float>(k)}, 0.003f + 0.002f * static_cast<float>(k));
  }
  pbr::Material m;
  m.base_color = {0.95f, 0.8f, 0.4f};
  m.metallic = 0.0f;
  m.roughness = 0.3f;
  s.objects.push_back({mesh, m, glm::mat4(1.0f)});
  pbr::Light l;
  l.position = {0.5f, 0.8f, 1.2f};
  l.intensity = 6.0f;
  s.lights.push_back(l);
  s.camera.position = {0.0f, 0.0f, 3.2f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.background = {0.02f, 0.025f, 0.04f, 1.0f};
  return s;
}

}  // namespace

TEST_CASE("MSAA golden images: the gallery and the thin-line scene at 4x and 8x, bit for bit") {
  raster::Renderer renderer({.threads = 0, .tile_size = 64});
  struct Golden {
    std::string name;
    int width, height;
    pbr::Scene scene;
  };
  const std::vector<Golden> goldens = {{"gallery", 640, 360, pbr::make_gallery()}, {"thin_lines", 320, 240, thin_lines()}};
  for (const Golden& g : goldens)
    for (const int n : {4, 8}) {
      CAPTURE(g.name);
      CAPTURE(n);
      raster::Target target(g.width, g.height, n);
      pbr::render(g.scene, renderer, target);
      CHECK_RENDER_MATCHES(target, pbr::tone_map_to_rgba8(target, pbr::gallery_output()),
                           "goldens/msaa" + std::to_string(n) + "_" + g.name);
    }
}

TEST_CASE("MSAA gallery: the same bits with 1, 2, 3 and 8 threads, tile sizes 8 to 256, every lane width, dispatch on and off") {
  const pbr::Scene scene = pbr::make_gallery();
  constexpr int kW = 333, kH = 187;
  struct Config {
    unsigned threads;
    int tile, lanes;
    bool dispatch;
  };
  const Config configs[] = {{1, 64, 1, false}, {2, 8, 4, true},   {3, 16, 8, true},  {8, 32, 16, true},
                            {2, 128, 0, true}, {1, 256, 16, false}, {3, 62, 8, false}};
  for (const int n : {4, 8}) {
    CAPTURE(n);
    std::uint64_t color = 0, depth = 0;
    raster::Image8 reference_image;
    bool first = true;
    for (const Config& c : configs) {
      CAPTURE(c.threads);
      CAPTURE(c.tile);
      CAPTURE(c.lanes);
      CAPTURE(c.dispatch);
      raster::Renderer renderer({.threads = c.threads, .tile_size = c.tile, .lanes = c.lanes, .dispatch = c.dispatch});
      raster::Target target(kW, kH, n);
      raster::Image8 image;
      // render_rgba8 resolves and encodes each tile right after drawing it; the whole-image
      // tone_map_to_rgba8 must give the same bytes.
      pbr::render_rgba8(scene, renderer, target, pbr::gallery_output(), image);
      CHECK(image.rgba == pbr::tone_map_to_rgba8(target, pbr::gallery_output()).rgba);
      if (first) {
        color = raster::hash_colors(target);
        depth = raster::hash_depths(target);
        reference_image = image;
        first = false;
      }
      CHECK(raster::hash_colors(target) == color);
      CHECK(raster::hash_depths(target) == depth);
      CHECK(image.rgba == reference_image.rgba);
      // A transient target (no samples kept, none written back): the same bytes. The
      // gallery's 169k triangles go over the default geometry budget (several passes, so
      // the target's planes are made); without a budget the frame is one pass, drawn in
      // blocks alone unless a tile is too large for one.
      for (const std::size_t budget : {raster::RendererOptions{}.geometry_budget, std::size_t{0}}) {
        CAPTURE(budget);
        raster::Renderer r({.threads = c.threads, .tile_size = c.tile, .lanes = c.lanes, .dispatch = c.dispatch,
                            .geometry_budget = budget});
        raster::Target transient(kW, kH, n, nullptr, raster::SampleStorage::Transient);
        raster::Image8 transient_image;
        pbr::render_rgba8(scene, r, transient, pbr::gallery_output(), transient_image);
        CHECK(transient_image.rgba == reference_image.rgba);
        CHECK((transient.allocated_bytes() == 0) == (budget == 0 && c.tile * c.tile * n <= 64 * 64 * 8));
      }
    }
    // A frame rasterized in several passes (a geometry budget of 1 byte flushes every
    // draw): each later pass loads a tile's samples back from the target into the block.
    for (const int tile : {64, 30, 256}) {
      CAPTURE(tile);
      raster::Renderer renderer({.threads = 2, .tile_size = tile, .geometry_budget = 1});
      raster::Target target(kW, kH, n);
      raster::Image8 image;
      pbr::render_rgba8(scene, renderer, target, pbr::gallery_output(), image);
      CHECK(raster::hash_colors(target) == color);
      CHECK(raster::hash_depths(target) == depth);
      CHECK(image.rgba == reference_image.rgba);
      // A transient target's frame in several passes keeps its samples in planes made for it.
      raster::Target transient(kW, kH, n, nullptr, raster::SampleStorage::Transient);
      pbr::render_rgba8(scene, renderer, transient, pbr::gallery_output(), image);
      CHECK(image.rgba == reference_image.rgba);
      CHECK(transient.allocated_bytes() == raster::Target::bytes(kW, kH, n));
    }
  }
}

TEST_CASE("render_outputs: the PNG bytes and the linear box resolve of a kept or transient target, per tile") {
  const pbr::Scene scene = pbr::make_gallery();
  constexpr int kW = 200, kH = 120;
  for (const int n : {1, 4, 8}) {
    CAPTURE(n);
    raster::Renderer reference_renderer({.threads = 1, .tile_size = 64});
    raster::Target kept(kW, kH, n);
    pbr::render(scene, reference_renderer, kept);
    const raster::Target want = raster::resolve_box(kept);  // a copy at n = 1
    const raster::Image8 want_image = pbr::tone_map_to_rgba8(kept, pbr::gallery_output());
    for (const int tile : {16, 64, 256})
      for (const raster::SampleStorage storage : {raster::SampleStorage::Kept, raster::SampleStorage::Transient}) {
        CAPTURE(tile);
        CAPTURE(static_cast<int>(storage));
        raster::Renderer r({.threads = 2, .tile_size = tile, .geometry_budget = 0});
        raster::Target target(kW, kH, n, nullptr, storage);
        raster::Target linear(kW, kH);
        raster::Image8 image;
        pbr::render_outputs(scene, r, target, pbr::gallery_output(), &image, &linear);
        CHECK(image.rgba == want_image.rgba);
        CHECK(raster::hash_colors(linear) == raster::hash_colors(want));
        CHECK(raster::hash_depths(linear) == raster::hash_depths(want));
        raster::Target only_linear(kW, kH);
        pbr::render_outputs(scene, r, target, pbr::gallery_output(), nullptr, &only_linear);
        CHECK(raster::hash_colors(only_linear) == raster::hash_colors(want));
        // Tiles no triangle reaches (tile 16: the gallery's corners) are the background's resolve.
        CHECK(std::memcmp(&std::as_const(linear).color(0, 0), &want.color(0, 0), sizeof(glm::vec4)) == 0);
      }
    raster::Target wrong(kW, kH - 1);
    CHECK_THROWS_AS(pbr::render_outputs(scene, reference_renderer, kept, pbr::gallery_output(), nullptr, &wrong),
                    std::invalid_argument);
    raster::Target multisampled(kW, kH, 4);
    CHECK_THROWS_AS(pbr::render_outputs(scene, reference_renderer, kept, pbr::gallery_output(), nullptr, &multisampled),
                    std::invalid_argument);
  }
}

TEST_CASE("MSAA shades once per pixel at its centre: where all samples agree, the pixel is the 1-sample image's, bit for bit") {
  const pbr::Scene scene = pbr::make_gallery();
  constexpr int kW = 320, kH = 180;
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  raster::Target one(kW, kH);
  pbr::render(scene, renderer, one);
  for (const int n : {4, 8}) {
    CAPTURE(n);
    raster::Target multi(kW, kH, n);
    pbr::render(scene, renderer, multi);
    const raster::Target resolved = raster::resolve_box(multi);
    int agree = 0, edges = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        bool same = true;
        for (int s = 1; s < n; ++s) same = same && multi.sample_color(x, y, s) == multi.sample_color(x, y, 0);
        if (!same) {
          ++edges;
          continue;
        }
        ++agree;
        // Equal samples resolve to exactly their value (the pairwise sum).
        CHECK(resolved.color(x, y) == multi.sample_color(x, y, 0));
      }
    // Edges: the 35 silhouettes, and the spheres' inner triangle edges, where the samples on
    // either side take two triangles' colours (each shaded at the same centre).
    CHECK(edges > 1000);
    CHECK(agree > kW * kH * 3 / 4);
    // The agreeing pixels equal the 1× image: a triangle that covers (and wins the depth
    // test at) all of a pixel's samples covers (and wins at) its centre, which lies inside
    // the samples' convex hull (a sliver between samples could break this; the gallery
    // has none).
    int differ = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        bool same = true;
        for (int s = 1; s < n; ++s) same = same && multi.sample_color(x, y, s) == multi.sample_color(x, y, 0);
        if (same && !(multi.sample_color(x, y, 0) == one.color(x, y))) ++differ;
      }
    MESSAGE(n << "x: " << edges << " edge pixels, " << agree << " uniform, " << differ << " of them differ from 1x");
    CHECK(differ == 0);
  }
}

TEST_CASE("MSAA resolves, measured on the gallery's highlights: tone mapping each sample vs resolving linear radiance") {
  // The two resolves agree bit for bit wherever a pixel's samples agree; at edges the
  // linear resolve lets a bright sample dominate the pixel (a highlight's edge stays
  // aliased, a dark surface in front of it gets a bright rim), while the tone-mapped
  // resolve is the coverage-weighted mean of the displayed colours. The figures go to
  // docs/design.md (MSAA).
  raster::Renderer renderer({.threads = 2, .tile_size = 64});
  constexpr int kW = 640, kH = 360;
  for (const float exposure : {0.0f, 2.0f}) {
    pbr::OutputSettings tone_mapped = pbr::gallery_output(), linear = pbr::gallery_output();
    tone_mapped.exposure = linear.exposure = exposure;
    tone_mapped.resolve = pbr::Resolve::ToneMapped;
    linear.resolve = pbr::Resolve::Linear;
    raster::Target target(kW, kH, 4);
    pbr::render(pbr::make_gallery(), renderer, target);
    const raster::Image8 a = pbr::tone_map_to_rgba8(target, tone_mapped), b = pbr::tone_map_to_rgba8(target, linear);
    int edges = 0, off8 = 0, brighter = 0, darker = 0, worst = 0;
    double sum = 0.0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        bool same = true;
        for (int s = 1; s < 4; ++s) same = same && target.sample_color(x, y, s) == target.sample_color(x, y, 0);
        const std::size_t i = (static_cast<std::size_t>(y) * kW + x) * 4;
        if (same) {
          for (int c = 0; c < 4; ++c) CHECK(a.rgba[i + c] == b.rgba[i + c]);
          continue;
        }
        ++edges;
        int d = 0;
        for (int c = 0; c < 3; ++c) d += static_cast<int>(b.rgba[i + c]) - static_cast<int>(a.rgba[i + c]);
        d /= 3;
        sum += std::abs(d);
        worst = std::max(worst, std::abs(d));
        off8 += std::abs(d) > 8;
        brighter += d > 8;
        darker += d < -8;
      }
    MESSAGE("exposure " << exposure << ": " << edges << " edge pixels; linear resolve vs tone-mapped: mean |diff| "
                        << sum / edges << " levels, max " << worst << ", " << 100.0 * off8 / edges
                        << "% more than 8 levels off (" << brighter << " brighter, " << darker << " darker)");
    CHECK(edges > 2000);
    CHECK(brighter >= darker);  // the linear resolve's bias: bright samples dominate
    if (exposure > 0.0f) CHECK(brighter > 0);
  }
}

TEST_CASE("scene files: render.msaa takes 1, 4 or 8 and render.resolve a resolve name, the memory estimate counts the samples") {
  const auto parse = [](const std::string& render) {
    return pbr::parse_scene_file(R"({"objects": [], "render": )" + render + "}", "s.json", ".");
  };
  CHECK(parse("{}").render.msaa == 1);
  CHECK(parse(R"({"msaa": 4})").render.msaa == 4);
  CHECK(parse(R"({"msaa": 8})").render.msaa == 8);
  CHECK(parse("{}").render.output.resolve == pbr::Resolve::ToneMapped);
  CHECK(parse(R"({"resolve": "linear"})").render.output.resolve == pbr::Resolve::Linear);
  for (const std::string bad : {R"({"msaa": 2})", R"({"msaa": 16})", R"({"msaa": "4"})", R"({"resolve": "box"})"}) {
    CAPTURE(bad);
    try {
      parse(bad);
      FAIL("expected a SceneFileError");
    } catch (const pbr::SceneFileError& e) {
      const std::string what = e.what();
      CHECK(what.find("s.json: /render/") == 0);
    }
  }
  CHECK(pbr::image_memory(1920, 1080, 4) == pbr::image_memory(1920, 1080) + 1920ull * 1080 * 4 * 20);
  CHECK(pbr::image_memory(1920, 1080, 8) > pbr::image_memory(1920, 1080, 4));
}
