// The ground's shadow catcher (Scene::ground; docs/design.md, "Ground"): a resting sphere
// stands on a contact shadow that is darkest at its foot and transparent at the square's
// edges; what hangs higher casts a fainter, wider shadow; a light's shadow map darkens the
// ground where the light is blocked; the image's alpha over a transparent background is
// the shadow; a scene without objects renders as without a ground; the same bits for every
// thread count, tile size, lane width, dispatch and sample count.
#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <doctest/doctest.h>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "softpbr/image/image.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"
#include "texture_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace test = softpbr::test;

namespace {

constexpr int kSize = 200;
constexpr float kHalf = 2.5f;  // the view from above: x and z in [−kHalf, kHalf]

glm::mat4 at(glm::vec3 p) {
  glm::mat4 t(1.0f);
  t[3] = glm::vec4(p, 1.0f);
  return t;
}

pbr::Object object(pbr::Mesh mesh, const glm::mat4& transform) {
  pbr::Object o;
  o.mesh = std::make_shared<pbr::Mesh>(std::move(mesh));
  o.material.base_color = glm::vec3(0.8f, 0.4f, 0.3f);
  o.transform = transform;
  return o;
}

// Seen straight from above (orthographic, −z at the top of the image), over a transparent
// background, with a ground shadow.
pbr::Scene from_above() {
  pbr::Scene s;
  s.camera.position = {0.0f, 10.0f, 0.0f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 0.0f, -1.0f};
  s.camera.orthographic = true;
  s.camera.ymag = kHalf;
  s.background = glm::vec4(0.0f);
  s.ground.shadow = true;
  return s;
}

raster::Target render(const pbr::Scene& s, raster::RendererOptions options = {.threads = 2, .tile_size = 32}) {
  raster::Renderer renderer(options);
  raster::Target t(kSize, kSize);
  pbr::render(s, renderer, t);
  return t;
}

// The image's alpha where the ground point (x, z) is seen.
float alpha_at(const raster::Target& t, float x, float z) {
  const auto px = static_cast<int>(std::floor((x + kHalf) / (2.0f * kHalf) * kSize));
  const auto py = static_cast<int>(std::floor((z + kHalf) / (2.0f * kHalf) * kSize));
  REQUIRE(px >= 0);
  REQUIRE(px < kSize);
  REQUIRE(py >= 0);
  REQUIRE(py < kSize);
  return t.color(px, py).a;
}

}  // namespace

TEST_CASE("ground: a resting sphere stands on a contact shadow, darkest at its foot, transparent at the edges") {
  pbr::Scene s = from_above();
  s.objects.push_back(object(pbr::uv_sphere(0.5f, 64, 32), at({0.0f, 0.5f, 0.0f})));
  const raster::Target t = render(s);
  // Inside the sphere's silhouette: the sphere (opaque).
  CHECK(alpha_at(t, 0.0f, 0.0f) == 1.0f);
  // Around it the shadow: dark near the sphere, fading outwards, then nothing at all.
  const float a1 = alpha_at(t, 0.53f, 0.0f), a2 = alpha_at(t, 0.65f, 0.0f), a3 = alpha_at(t, 0.72f, 0.0f);
  CHECK(a1 > 0.03f);
  CHECK(a1 > a2);
  CHECK(a2 > a3);
  CHECK(a1 < 0.7f);  // the ground is never more than darkness (0.7) opaque
  // Symmetric about the sphere's axis (the same in +x, −x, +z and −z within a pixel's step).
  CHECK(std::abs(alpha_at(t, -0.65f, 0.0f) - a2) < 0.1f);
  CHECK(std::abs(alpha_at(t, 0.0f, 0.65f) - a2) < 0.1f);
  // The square's edges and beyond: transparent (the square ends at 0.5 + 2 · 0.25 + a border).
  for (const float x : {-2.4f, -1.2f, 1.2f, 2.4f}) {
    CAPTURE(x);
    CHECK(alpha_at(t, x, 0.0f) == 0.0f);
    CHECK(alpha_at(t, 0.0f, x) == 0.0f);
  }
  // The colour where only the ground is: black over the transparent background.
  const auto px = static_cast<int>((0.53f + kHalf) / (2.0f * kHalf) * kSize);
  const glm::vec4 c = t.color(px, kSize / 2);
  CHECK(c.r == 0.0f);
  CHECK(c.g == 0.0f);
  CHECK(c.b == 0.0f);

  SUBCASE("darkness and softness") {
    pbr::Scene d = s;
    d.ground.darkness = 0.35f;
    const raster::Target half = render(d);
    CHECK(alpha_at(half, 0.53f, 0.0f) < a1);
    CHECK(alpha_at(half, 0.53f, 0.0f) > 0.0f);
    d = s;
    d.ground.darkness = 0.0f;
    const raster::Target none = render(d);
    CHECK(alpha_at(none, 0.53f, 0.0f) == 0.0f);
  }
}

TEST_CASE("ground: what hangs higher casts a fainter and wider shadow") {
  // A 0.5 × 0.5 plate facing up at height h, and a small cube at the ground (y = 0) far
  // from it, so that the ground is at 0 in both scenes and their bounds are alike.
  const auto scene = [](float h) {
    pbr::Scene s = from_above();
    s.objects.push_back(object(pbr::plane(0.5f, 0.5f, 1), at({0.0f, h, 0.0f})));
    s.objects.push_back(object(pbr::cube(0.2f), at({-1.2f, 0.1f, 0.0f})));
    s.objects.push_back(object(pbr::cube(0.2f), at({-1.2f, 0.7f, 0.0f})));  // the same height either way
    return s;
  };
  const raster::Target low = render(scene(0.05f)), high = render(scene(0.6f));
  // Just outside the plate's edge (x = 0.25): the low plate's shadow is darker.
  CHECK(alpha_at(low, 0.27f, 0.0f) > alpha_at(high, 0.27f, 0.0f));
  // Farther out: only the high plate's blurred shadow reaches.
  CHECK(alpha_at(high, 0.5f, 0.0f) > alpha_at(low, 0.5f, 0.0f));
  CHECK(alpha_at(high, 0.5f, 0.0f) > 0.0f);
}

TEST_CASE("ground: a light's shadow map darkens the ground where the light is blocked") {
  pbr::Scene s = from_above();
  s.objects.push_back(object(pbr::cube(0.2f), at({-1.2f, 0.1f, 0.0f})));  // the ground at y = 0
  s.objects.push_back(object(pbr::uv_sphere(0.4f, 48, 24), at({0.0f, 1.2f, 0.0f})));
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = {0.6f, -1.0f, 0.0f};  // the sphere's centre falls on (0.72, 0, 0)
  sun.intensity = 3.0f;
  sun.shadows = true;
  s.lights = {sun};
  const raster::Target shadowed = render(s);
  s.lights[0].shadows = false;
  const raster::Target unshadowed = render(s);
  CHECK(alpha_at(shadowed, 0.72f, 0.0f) > 0.6f);     // darkness · blocked (0.7 · 1)
  CHECK(alpha_at(unshadowed, 0.72f, 0.0f) < 0.2f);  // the contact shadow of a sphere 0.8 above the ground
  // Where the light reaches the ground both are the same contact shadow.
  CHECK(alpha_at(shadowed, -0.3f, 0.9f) == alpha_at(unshadowed, -0.3f, 0.9f));
}

TEST_CASE("ground: an environment's dominant light throws its shadow on the ground") {
  // A dark sky (0.05) with a small sun 45° up towards −x (equirect u = 0.25, v = 0.25).
  constexpr int kW = 64, kH = 32;
  std::vector<float> pixels(static_cast<std::size_t>(kW * kH * 4), 0.05f);
  for (int y = 7; y <= 9; ++y)
    for (int x = 15; x <= 17; ++x)
      for (int c = 0; c < 3; ++c) pixels[static_cast<std::size_t>((y * kW + x) * 4 + c)] = 200.0f;
  const auto sun = std::make_shared<const pbr::Environment>(
      softpbr::image::ImageViewF{kW, kH, pixels}, "sun", pbr::EnvironmentOptions{.size = 32});
  pbr::Scene s = from_above();
  s.objects.push_back(object(pbr::cube(0.2f), at({-1.5f, 0.1f, 0.0f})));  // the ground at y = 0
  s.objects.push_back(object(pbr::uv_sphere(0.4f, 48, 24), at({0.0f, 1.0f, 0.0f})));
  const raster::Target without = render(s);
  s.environment.map = sun;
  const raster::Target with = render(s);
  // The sphere's centre seen from the sun falls on (1, 0, 0): shadowed with the sun only.
  CHECK(alpha_at(with, 1.0f, 0.0f) > 0.5f);
  CHECK(alpha_at(without, 1.0f, 0.0f) < 0.15f);
  // On the sun's side of the sphere no shadow of it: both the faint edge of its contact
  // shadow (the squares differ: the sun's shadow widens the ground, so their texels too).
  CHECK(alpha_at(with, -0.7f, 0.0f) < 0.02f);
  CHECK(std::abs(alpha_at(with, -0.7f, 0.0f) - alpha_at(without, -0.7f, 0.0f)) < 0.01f);
}

TEST_CASE("ground: a scene without objects renders as without a ground, and a ground that is off changes nothing") {
  pbr::Scene s = from_above();
  const raster::Target a = render(s);
  s.ground.shadow = false;
  CHECK(raster::hash_colors(a) == raster::hash_colors(render(s)));
  s.objects.push_back(object(pbr::uv_sphere(0.5f, 32, 16), at({0.0f, 0.5f, 0.0f})));
  pbr::Scene dark = s;
  dark.ground.darkness = 0.9f;  // read only with the ground on
  CHECK(raster::hash_colors(render(s)) == raster::hash_colors(render(dark)));
}

TEST_CASE("ground: the same bits for every thread count, tile size, lane width, dispatch and sample count") {
  pbr::Scene s = from_above();
  s.camera.orthographic = false;
  s.camera.position = {1.5f, 2.0f, 3.0f};
  s.camera.up = {0.0f, 1.0f, 0.0f};
  s.objects.push_back(object(pbr::uv_sphere(0.5f, 48, 24), at({0.0f, 0.5f, 0.0f})));
  s.objects.push_back(object(pbr::torus(0.4f, 0.1f, 32, 16), at({0.9f, 0.8f, -0.3f})));
  s.objects[1].material.alpha_mode = pbr::AlphaMode::Mask;  // a cut-out caster (its textured shader)
  s.objects[1].material.alpha = 0.9f;
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = {0.4f, -1.0f, -0.3f};
  sun.intensity = 3.0f;
  sun.shadows = true;
  s.lights = {sun};
  test::check_same_bits_for_every_config(s, kSize);
}
