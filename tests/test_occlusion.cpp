// Screen-space ambient occlusion of the environment's light (docs/design.md, "Image-based
// lighting"): an open plane is not occluded (the image is the one without occlusion, bit
// for bit), a box on a plane darkens the plane at its foot and not far from it, occlusion
// off renders what softpbr rendered before it existed, and the occluded image has the same
// bits for every thread count, tile size, lane width, dispatch and sample count.
#include <cstdint>
#include <memory>

#include <doctest/doctest.h>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"
#include "texture_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace test = softpbr::test;

namespace {

pbr::Object object(pbr::Mesh mesh, const glm::mat4& transform, glm::vec3 colour) {
  pbr::Object o;
  o.mesh = std::make_shared<pbr::Mesh>(std::move(mesh));
  o.material.base_color = colour;
  o.material.roughness = 0.6f;
  o.transform = transform;
  return o;
}

// A grey plane 8 × 8 seen from above at 40°, lit by the built-in studio alone; with a unit
// box standing on it at the origin when `box`.
pbr::Scene plane_scene(bool box) {
  pbr::Scene s;
  s.camera.position = {0.0f, 3.5f, 4.2f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.objects.push_back(object(pbr::plane(8.0f, 8.0f, 4), glm::mat4(1.0f), glm::vec3(0.7f)));
  if (box) {
    glm::mat4 t(1.0f);
    t[3] = glm::vec4(0.0f, 0.5f, 0.0f, 1.0f);
    s.objects.push_back(object(pbr::cube(1.0f), t, glm::vec3(0.8f, 0.3f, 0.2f)));
  }
  s.lights.clear();
  s.environment.map = pbr::Environment::studio();
  s.background_mode = pbr::BackgroundMode::Environment;
  return s;
}

constexpr int kWidth = 200, kHeight = 150;

// The pixel a world point falls in.
glm::ivec2 pixel_of(const pbr::Scene& s, glm::vec3 p) {
  const glm::mat4 vp = s.camera.projection(static_cast<float>(kWidth) / static_cast<float>(kHeight)) * s.camera.view();
  const glm::vec4 c = vp * glm::vec4(p, 1.0f);
  const float x = (c.x / c.w * 0.5f + 0.5f) * kWidth, y = (0.5f - c.y / c.w * 0.5f) * kHeight;
  return {static_cast<int>(x), static_cast<int>(y)};
}

float luminance(const raster::Target& t, glm::ivec2 p) {
  const glm::vec4 c = t.color(p.x, p.y);
  return c.r + c.g + c.b;
}

}  // namespace

TEST_CASE("occlusion: an open plane is not occluded, the image is the one without occlusion bit for bit") {
  for (const bool orthographic : {false, true}) {
    CAPTURE(orthographic);
    pbr::Scene on = plane_scene(false);
    on.camera.orthographic = orthographic;
    on.camera.ymag = 2.0f;
    pbr::Scene off = on;
    off.environment.occlusion = false;
    raster::Renderer renderer({.threads = 2, .tile_size = 32});
    raster::Target a(kWidth, kHeight), b(kWidth, kHeight);
    pbr::render(on, renderer, a);
    pbr::render(off, renderer, b);
    CHECK(raster::hash_colors(a) == raster::hash_colors(b));
    CHECK(raster::hash_depths(a) == raster::hash_depths(b));
  }
}

TEST_CASE("occlusion: an orthographic camera darkens the foot of a box as a perspective one does") {
  pbr::Scene on = plane_scene(true);
  on.camera.orthographic = true;
  on.camera.ymag = 2.0f;
  pbr::Scene off = on;
  off.environment.occlusion = false;
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  raster::Target a(kWidth, kHeight), b(kWidth, kHeight);
  pbr::render(on, renderer, a);
  pbr::render(off, renderer, b);
  const glm::mat4 vp = on.camera.projection(static_cast<float>(kWidth) / static_cast<float>(kHeight)) * on.camera.view();
  const glm::vec4 c = vp * glm::vec4(0.0f, 0.0f, 0.54f, 1.0f);
  const glm::ivec2 p(static_cast<int>((c.x * 0.5f + 0.5f) * kWidth), static_cast<int>((0.5f - c.y * 0.5f) * kHeight));
  CHECK(luminance(a, p) < 0.9f * luminance(b, p));
}

TEST_CASE("occlusion: a box on a plane darkens the plane at its foot, not far from it") {
  const pbr::Scene on = plane_scene(true);
  pbr::Scene off = on;
  off.environment.occlusion = false;
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  raster::Target a(kWidth, kHeight), b(kWidth, kHeight);
  pbr::render(on, renderer, a);
  pbr::render(off, renderer, b);
  // In front of the box, just off the face the camera sees (screen-space occlusion knows
  // only what the camera sees: the feet of the faces turned away are not darkened).
  for (const glm::vec3 foot : {glm::vec3(-0.3f, 0.0f, 0.54f), glm::vec3(0.0f, 0.0f, 0.54f), glm::vec3(0.3f, 0.0f, 0.54f)}) {
    const glm::ivec2 p = pixel_of(on, foot);
    CAPTURE(p.x);
    CAPTURE(p.y);
    CHECK(luminance(a, p) < 0.9f * luminance(b, p));
  }
  // Far from the box the plane is as without occlusion.
  for (const glm::vec3 far : {glm::vec3(2.0f, 0.0f, 0.5f), glm::vec3(-2.0f, 0.0f, 1.0f), glm::vec3(0.0f, 0.0f, 1.8f)}) {
    const glm::ivec2 p = pixel_of(on, far);
    CAPTURE(p.x);
    CAPTURE(p.y);
    REQUIRE((p.x >= 0 && p.x < kWidth && p.y >= 0 && p.y < kHeight));
    CHECK(luminance(a, p) == luminance(b, p));
  }
  // The box's top, facing the open sky, is not occluded either.
  const glm::ivec2 top = pixel_of(on, glm::vec3(0.0f, 1.0f, 0.0f));
  CHECK(luminance(a, top) == luminance(b, top));
}

TEST_CASE("occlusion: the same bits for every thread count, tile size, lane width, dispatch and sample count") {
  for (const int samples : {1, 4}) {
    CAPTURE(samples);
    // The box on the plane, and textured spheres (TexturedPbrShader) over a floor.
    pbr::Scene textured = test::textured_spheres();
    textured.environment.map = pbr::Environment::studio();
    textured.background_mode = pbr::BackgroundMode::Blur;
    pbr::Scene box = plane_scene(true);
    for (const pbr::Scene* scene : {&box, &textured}) {
      raster::Renderer reference_renderer({.threads = 1, .tile_size = 64, .lanes = 1, .dispatch = false});
      raster::Target reference(211, 137, samples);  // partial edge tiles
      pbr::render(*scene, reference_renderer, reference);
      const std::uint64_t color = raster::hash_colors(reference);
      test::for_spread_of_render_configs(samples == 1 ? 3 : 5, 32, [&](const raster::RendererOptions& options) {
        raster::Renderer r(options);
        raster::Target t(211, 137, samples);
        pbr::render(*scene, r, t);
        CHECK(raster::hash_colors(t) == color);
      });
    }
  }
}
