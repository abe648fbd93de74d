// Normal mapping: the tangent frame's orientation (T along +u, B towards image-up = −v, as
// glTF's normal textures are authored), the normal scale, and mirrored tangents.
#include <doctest/doctest.h>

#include <cmath>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace image = softpbr::image;

namespace {

// A tangent-space normal map of a plateau across u (axis 0) or v (axis 1): flat outside
// [0.25, 0.75], and at its edges slopes whose normals tilt by ±45° along the axis — the
// rising edge (at 0.25) towards −axis, the falling edge (at 0.75) towards +axis.
image::Image8 plateau_normals(int size, int axis) {
  image::Image8 im;
  im.width = im.height = size;
  im.rgba.resize(static_cast<std::size_t>(size) * size * 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const int t = axis == 0 ? x : y;
      // +1: the normal leans towards +axis in texture space (for v: down the image).
      const int lean = (t >= size / 4 - 4 && t < size / 4 + 4) ? -1 : (t >= 3 * size / 4 - 4 && t < 3 * size / 4 + 4) ? 1 : 0;
      // Encoded (n + 1)/2; 45° → components ±0.7071, 0.7071. The green channel is image-up,
      // i.e. −v: a lean towards +v is green below 0.5.
      const int tilt = lean * 90;  // ≈ 0.7071 · 127.5
      std::uint8_t* p = &im.rgba[(static_cast<std::size_t>(y) * size + x) * 4];
      p[0] = static_cast<std::uint8_t>(128 + (axis == 0 ? tilt : 0));
      p[1] = static_cast<std::uint8_t>(128 - (axis == 1 ? tilt : 0));
      p[2] = static_cast<std::uint8_t>(lean != 0 ? 218 : 255);
      p[3] = 255;
    }
  return im;
}

struct Rendered {
  raster::Target target{96, 96};
  glm::mat4 view_projection;
  // Brightness (red channel) where the plane's point (u, v) lands.
  float at(float u, float v) const {
    const glm::vec4 clip = view_projection * glm::vec4(2.0f * u - 1.0f, 0.0f, 2.0f * v - 1.0f, 1.0f);
    const int x = static_cast<int>((clip.x / clip.w * 0.5f + 0.5f) * 96.0f);
    const int y = static_cast<int>((0.5f - clip.y / clip.w * 0.5f) * 96.0f);
    return target.color(x, y).r;
  }
};

// The unit plane (u along +x, v along +z) seen from straight above with image-up = −z, so
// the picture is oriented like the texture; lit by a directional light from `from`.
Rendered render_plane(const image::Image8& normals, glm::vec3 from, float w = 1.0f, float scale = 1.0f) {
  pbr::Scene s;
  auto plane = std::make_shared<pbr::Mesh>(pbr::plane(2.0f, 2.0f, 1));
  plane->tangents.assign(plane->vertices.size(), glm::vec4(1.0f, 0.0f, 0.0f, w));
  pbr::Material m;
  m.base_color = {0.8f, 0.8f, 0.8f};
  m.roughness = 1.0f;
  m.normal_texture.texture = std::make_shared<const raster::Texture>(normals, raster::ColorSpace::Linear);
  m.normal_texture.sampler.mag_filter = m.normal_texture.sampler.min_filter = raster::Filter::Nearest;
  m.normal_scale = scale;
  s.objects.push_back({plane, m, glm::mat4(1.0f)});
  pbr::Light sun;
  sun.type = pbr::LightType::Directional;
  sun.direction = -glm::normalize(from);
  sun.intensity = 3.0f;
  s.lights.push_back(sun);
  s.ambient = glm::vec3(0.0f);
  s.camera.position = {0.0f, 3.0f, 0.0f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 0.0f, -1.0f};
  Rendered r;
  raster::Renderer renderer({.threads = 1});
  pbr::render(s, renderer, r.target);
  r.view_projection = s.camera.projection(1.0f) * s.camera.view();
  return r;
}

}  // namespace

TEST_CASE("a plateau lit from +u brightens on its right (falling) edge and darkens on its left") {
  const Rendered r = render_plane(plateau_normals(64, 0), {1.0f, 1.0f, 0.0f});
  const float flat = r.at(0.5f, 0.5f), left = r.at(0.25f, 0.5f), right = r.at(0.75f, 0.5f);
  CAPTURE(flat);
  CAPTURE(left);
  CAPTURE(right);
  CHECK(right > flat * 1.2f);  // the normal turns towards the light: cos 0° vs cos 45°
  CHECK(left < flat * 0.5f);   // turned away: cos 90°
  // Lit from −u instead, the two edges swap.
  const Rendered l = render_plane(plateau_normals(64, 0), {-1.0f, 1.0f, 0.0f});
  CHECK(l.at(0.25f, 0.5f) > l.at(0.5f, 0.5f) * 1.2f);
  CHECK(l.at(0.75f, 0.5f) < l.at(0.5f, 0.5f) * 0.5f);
}

TEST_CASE("the normal map's green channel points image-up (towards −v)") {
  // Lit from −v (−z, the top of the picture): the edge whose normal leans towards −v — the
  // rising edge at v = 0.25 — brightens.
  const Rendered r = render_plane(plateau_normals(64, 1), {0.0f, 1.0f, -1.0f});
  CHECK(r.at(0.5f, 0.25f) > r.at(0.5f, 0.5f) * 1.2f);
  CHECK(r.at(0.5f, 0.75f) < r.at(0.5f, 0.5f) * 0.5f);
  // A mirrored tangent frame (w = −1) flips the bitangent: the edges swap.
  const Rendered m = render_plane(plateau_normals(64, 1), {0.0f, 1.0f, -1.0f}, -1.0f);
  CHECK(m.at(0.5f, 0.75f) > m.at(0.5f, 0.5f) * 1.2f);
  CHECK(m.at(0.5f, 0.25f) < m.at(0.5f, 0.5f) * 0.5f);
}

TEST_CASE("normal_scale 0 flattens the map") {
  const Rendered r = render_plane(plateau_normals(64, 0), {1.0f, 1.0f, 0.0f}, 1.0f, 0.0f);
  CHECK(r.at(0.75f, 0.5f) == doctest::Approx(r.at(0.5f, 0.5f)).epsilon(2e-3));  // only the view direction differs
  CHECK(r.at(0.25f, 0.5f) == doctest::Approx(r.at(0.5f, 0.5f)).epsilon(2e-3));  // only the view direction differs
}
