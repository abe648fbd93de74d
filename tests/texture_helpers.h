// Procedural test textures and the textured scenes of the golden and determinism suites.
// Images are made with integer arithmetic only, so they are the same bytes everywhere.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/texture.h"

namespace softpbr::test {

// Calls fn(options) for a spread of the thread (1–3) × tile (8, 32, 64) × lane width (1, 4,
// 8, 16) × dispatch grid: every `stride`-th configuration, and 16 dispatched lanes (at tile
// `wide_tile` only, or at every tile when it is 0). Callers CAPTURE what they need; the
// configuration is captured here.
template <class Fn>
void for_spread_of_render_configs(int stride, int wide_tile, Fn&& fn) {
  int config = 0;
  for (const unsigned threads : {1u, 2u, 3u})
    for (const int tile : {8, 32, 64})
      for (const int lanes : {1, 4, 8, 16})
        for (const bool dispatch : {false, true}) {
          const bool wide = lanes == 16 && dispatch && (wide_tile == 0 || tile == wide_tile);
          if (++config % stride != 0 && !wide) continue;
          CAPTURE(threads);
          CAPTURE(tile);
          CAPTURE(lanes);
          CAPTURE(dispatch);
          fn(softpbr::raster::RendererOptions{.threads = threads, .tile_size = tile, .lanes = lanes, .dispatch = dispatch});
        }
}

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

// A w × h image of random bytes (colour and alpha), the same for the same seed.
// Renders `scene` into a size × size target of 1 and of 4 samples under each configuration
// for_spread_of_render_configs(4, 32, …) gives: every colour hash of a sample count must
// be its first one's.
inline void check_same_bits_for_every_config(const pbr::Scene& scene, int size) {
  for (const int samples : {1, 4}) {
    CAPTURE(samples);
    std::uint64_t reference = 0;
    bool first = true;
    for_spread_of_render_configs(4, 32, [&](const raster::RendererOptions& options) {
      raster::Renderer renderer(options);
      raster::Target t(size, size, samples);
      pbr::render(scene, renderer, t);
      const std::uint64_t h = raster::hash_colors(t);
      if (first) reference = h, first = false;
      CHECK(h == reference);
    });
  }
}

inline image::Image8 random_image8(int w, int h, unsigned seed) {
  image::Image8 im;
  im.width = w;
  im.height = h;
  im.rgba.resize(static_cast<std::size_t>(w) * h * 4);
  std::mt19937 rng(seed);
  for (auto& x : im.rgba) x = static_cast<std::uint8_t>(rng() & 0xff);
  return im;
}

// A `size`² checkerboard of `squares`² squares in two sRGB colours, with a thin red line
// on the first row and column of every square (so aliasing and mip levels show).
inline image::Image8 checker_image(int size, int squares) {
  image::Image8 im;
  im.width = im.height = size;
  im.rgba.resize(static_cast<std::size_t>(size) * size * 4);
  const int cell = size / squares;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * size + x) * 4];
      const bool dark = ((x / cell) + (y / cell)) % 2 == 1;
      const bool line = x % cell == 0 || y % cell == 0;
      p[0] = line ? 220 : (dark ? 40 : 230);
      p[1] = line ? 30 : (dark ? 60 : 220);
      p[2] = line ? 30 : (dark ? 90 : 200);
      p[3] = 255;
    }
  return im;
}

// A UV map: red grows with u, green with v (v = 0 at the top row), a white grid every
// 1/8 and a blue marker in the top-left eighth, so orientation is visible.
inline image::Image8 uv_grid_image(int size) {
  image::Image8 im;
  im.width = im.height = size;
  im.rgba.resize(static_cast<std::size_t>(size) * size * 4);
  const int cell = size / 8;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * size + x) * 4];
      const bool grid = x % cell < 2 || y % cell < 2;
      const bool marker = x < cell && y < cell;
      p[0] = grid ? 255 : static_cast<std::uint8_t>(x * 255 / (size - 1));
      p[1] = grid ? 255 : static_cast<std::uint8_t>(y * 255 / (size - 1));
      p[2] = grid ? 255 : (marker ? 255 : 40);
      p[3] = 255;
    }
  return im;
}

// White with round holes of alpha 0 (a fence of dots), alpha ramping at their rims.
inline image::Image8 holes_image(int size, int holes) {
  image::Image8 im;
  im.width = im.height = size;
  im.rgba.resize(static_cast<std::size_t>(size) * size * 4);
  const int cell = size / holes;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * size + x) * 4];
      const int dx = x % cell - cell / 2, dy = y % cell - cell / 2;
      const int r2 = dx * dx + dy * dy, rr = (cell * 3 / 8) * (cell * 3 / 8);
      p[0] = 250;
      p[1] = 240;
      p[2] = 200;
      p[3] = r2 < rr ? 0 : 255;
    }
  return im;
}

inline std::shared_ptr<const raster::Texture> srgb_texture(const image::Image8& im) {
  return std::make_shared<const raster::Texture>(im, raster::ColorSpace::Srgb);
}

// A checkered floor seen at a grazing angle out to the horizon: minification by every
// level, strongly anisotropic in the distance. `anisotropy` 1 is plain trilinear.
inline pbr::Scene textured_floor(int anisotropy) {
  pbr::Scene s;
  auto floor = std::make_shared<pbr::Mesh>(pbr::plane(60.0f, 60.0f, 4));
  pbr::Material m;
  m.base_color = {1.0f, 1.0f, 1.0f};
  m.roughness = 0.8f;
  m.base_color_texture.texture = srgb_texture(checker_image(256, 8));
  m.base_color_texture.sampler.max_anisotropy = anisotropy;
  m.base_color_texture.transform.scale = {30.0f, 30.0f};
  s.objects.push_back({floor, m, glm::mat4(1.0f)});
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = {-0.3f, -1.0f, -0.4f};
  sun.intensity = 2.0f;
  s.lights.push_back(sun);
  s.ambient = {0.25f, 0.25f, 0.25f};
  s.background = {0.45f, 0.6f, 0.85f, 1.0f};
  s.camera.position = {0.0f, 1.2f, 6.0f};
  s.camera.target = {0.0f, 0.0f, -20.0f};
  s.camera.fovy = static_cast<float>(dmath::radians(55.0));
  return s;
}

// UV-mapped spheres near and far, turned different ways, and a cube: textures on curved
// surfaces across several mip levels, the sphere's seam, and which way is up.
inline pbr::Scene textured_spheres() {
  pbr::Scene s;
  const auto grid = srgb_texture(uv_grid_image(256));
  auto sphere = std::make_shared<pbr::Mesh>(pbr::uv_sphere(1.0f, 48, 24));
  auto cube = std::make_shared<pbr::Mesh>(pbr::cube(1.4f));
  pbr::Material m;
  m.base_color = {1.0f, 1.0f, 1.0f};
  m.roughness = 0.45f;
  m.base_color_texture.texture = grid;
  m.base_color_texture.sampler.max_anisotropy = 4;
  auto at = [](glm::vec3 p, float yaw_degrees, float scale) {
    glm::mat4 t = glm::translate(glm::mat4(1.0f), p);
    t = glm::rotate(t, static_cast<float>(dmath::radians(yaw_degrees)), glm::vec3(0, 1, 0));
    return glm::scale(t, glm::vec3(scale));
  };
  s.objects.push_back({sphere, m, at({-1.6f, 0.0f, 0.0f}, 0.0f, 1.0f)});
  s.objects.push_back({sphere, m, at({0.9f, 0.2f, -3.0f}, 180.0f, 1.0f)});
  s.objects.push_back({sphere, m, at({3.5f, 0.6f, -12.0f}, 90.0f, 1.0f)});
  pbr::Material mc = m;
  mc.metallic = 0.0f;
  mc.base_color_texture.transform.rotation = static_cast<float>(dmath::radians(20.0));
  s.objects.push_back({cube, mc, at({1.5f, -0.6f, 0.8f}, 35.0f, 0.8f)});
  pbr::Light key;
  key.position = {-3.0f, 4.0f, 5.0f};
  key.intensity = 40.0f;
  s.lights.push_back(key);
  pbr::Light fill;
  fill.position = {5.0f, 1.0f, 2.0f};
  fill.intensity = 10.0f;
  s.lights.push_back(fill);
  s.ambient = {0.15f, 0.15f, 0.15f};
  s.camera.position = {0.0f, 0.6f, 5.0f};
  s.camera.target = {0.4f, 0.0f, -2.0f};
  return s;
}

// Alpha modes: a fence of holes (mask) and a tinted glass pane (blend) in front of a red
// sphere, and a double-sided leaf seen from behind.
inline pbr::Scene alpha_modes() {
  pbr::Scene s;
  auto sphere = std::make_shared<pbr::Mesh>(pbr::uv_sphere(1.0f, 48, 24));
  auto pane = std::make_shared<pbr::Mesh>(pbr::plane(2.0f, 2.0f, 1));
  pbr::Material red;
  red.base_color = {0.8f, 0.1f, 0.08f};
  red.roughness = 0.35f;
  s.objects.push_back({sphere, red, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -1.5f))});
  // The plane faces +y: stand it up facing the camera (+z).
  const glm::mat4 upright = glm::rotate(glm::mat4(1.0f), static_cast<float>(dmath::radians(90.0)), glm::vec3(1, 0, 0));
  pbr::Material fence;
  fence.base_color = {1.0f, 1.0f, 1.0f};
  fence.alpha_mode = pbr::AlphaMode::Mask;
  fence.alpha_cutoff = 0.5f;
  fence.base_color_texture.texture = srgb_texture(holes_image(128, 4));
  fence.base_color_texture.sampler.wrap_u = fence.base_color_texture.sampler.wrap_v = raster::Wrap::Repeat;
  fence.base_color_texture.transform.scale = {2.0f, 2.0f};
  s.objects.push_back({pane, fence, glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f, 0.0f, 0.0f)) * upright});
  pbr::Material glass;
  glass.base_color = {0.3f, 0.6f, 1.0f};
  glass.roughness = 0.1f;
  glass.alpha = 0.4f;
  glass.alpha_mode = pbr::AlphaMode::Blend;
  s.objects.push_back({pane, glass, glm::translate(glm::mat4(1.0f), glm::vec3(1.2f, 0.0f, 0.5f)) * upright});
  pbr::Material leaf;
  leaf.base_color = {0.2f, 0.7f, 0.15f};
  leaf.double_sided = true;
  const glm::mat4 backwards = glm::rotate(glm::mat4(1.0f), static_cast<float>(dmath::radians(-90.0)), glm::vec3(1, 0, 0));
  s.objects.push_back({pane, leaf, glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.6f, -0.5f)) *
                                        glm::scale(glm::mat4(1.0f), glm::vec3(0.5f)) * backwards});
  pbr::Light key;
  key.position = {2.0f, 3.0f, 4.0f};
  key.intensity = 30.0f;
  s.lights.push_back(key);
  pbr::Light back;
  back.position = {0.0f, 2.0f, -4.0f};
  back.intensity = 15.0f;
  s.lights.push_back(back);
  s.ambient = {0.2f, 0.2f, 0.2f};
  s.background = {0.1f, 0.1f, 0.12f, 1.0f};
  s.camera.position = {0.0f, 0.3f, 4.5f};
  return s;
}

}  // namespace softpbr::test
