// Shadows (docs/design.md, "Shadows"): the depth-only draw writes the depths of the full
// pipeline; a sphere over a plane under a directional light darkens exactly the ellipse of
// the sphere projected along the light (within the filter's reach); a light moved past an
// occluder's edge un-shadows what lay below it; a lit sphere shows no acne (its lit pixels
// are the unshadowed ones but within the filter's reach of the terminator); a scene without
// occluders renders bit for bit as with shadows off; masked and blended casters cut out;
// cast_shadows and receive_shadows; point and spot lights; the same bits for every thread
// count, tile size, lane width, dispatch and sample count.
#include <cmath>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include <doctest/doctest.h>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

#include "softpbr/pbr/scene.h"
#include "softpbr/raster/raster.h"
#include "texture_helpers.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace test = softpbr::test;

namespace {

// --- The depth-only draw. ---

// A depth-only shader with PbrShader's clip positions.
struct DepthShader {
  using Vertex = pbr::MeshVertex;
  struct Varyings {};
  static constexpr bool kUsesDerivatives = false;
  static constexpr bool kDepthOnly = true;
  glm::mat4 model{1.0f};
  glm::mat4 view_projection{1.0f};
  glm::vec4 vertex(const Vertex& in, Varyings&) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    return view_projection * world;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>&) const { return glm::vec4(0.0f); }
};

// A full (colour) shader with the same clip positions: its normal's colour, in packets.
struct NormalShader {
  using Vertex = pbr::MeshVertex;
  struct Varyings {
    glm::vec3 normal;
  };
  static constexpr bool kUsesDerivatives = false;
  glm::mat4 model{1.0f};
  glm::mat4 view_projection{1.0f};
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    out.normal = in.normal;
    return view_projection * world;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return glm::vec4(f.v.normal, 1.0f); }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {p.v[0], p.v[1], p.v[2], F(1.0f)};
  }
};

// Alpha 1 left of x = cut, 0 right of it: a full shader, and the same alpha in a depth-only one.
struct CutShader {
  using Vertex = pbr::MeshVertex;
  struct Varyings {
    float x;
  };
  static constexpr bool kUsesDerivatives = false;
  glm::mat4 model{1.0f};
  glm::mat4 view_projection{1.0f};
  float cut = 0.0f;
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    const glm::vec4 world = model * glm::vec4(in.position, 1.0f);
    out.x = world.x;
    return view_projection * world;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    return glm::vec4(0.5f, 0.5f, 0.5f, f.v.x < cut ? 1.0f : 0.0f);
  }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    const F one(1.0f), zero(0.0f), half(0.5f);
    return {half, half, half, softpbr::simd::select(p.v[0] < F(cut), one, zero)};
  }
};
struct DepthCutShader : CutShader {
  static constexpr bool kDepthOnly = true;
};

struct Draw {
  pbr::Mesh mesh;
  glm::mat4 model;
};

std::vector<Draw> depth_scene() {
  std::vector<Draw> d;
  glm::mat4 t(1.0f);
  d.push_back({pbr::plane(6.0f, 6.0f, 3), t});
  t[3] = glm::vec4(0.3f, 0.8f, -0.2f, 1.0f);
  d.push_back({pbr::uv_sphere(0.7f, 48, 24), t});
  t = glm::mat4(0.8f);
  t[3] = glm::vec4(-1.1f, 0.5f, 0.6f, 1.0f);
  d.push_back({pbr::cube(1.0f), t});
  t[3] = glm::vec4(1.4f, 0.3f, 1.0f, 1.0f);
  d.push_back({pbr::torus(0.5f, 0.2f, 32, 16), t});
  return d;
}

glm::mat4 depth_view_projection() {
  pbr::Camera c;
  c.position = {2.5f, 3.0f, 4.0f};
  c.target = {0.0f, 0.3f, 0.0f};
  return c.projection(160.0f / 120.0f) * c.view();
}

// --- Scenes. ---

pbr::Object object(pbr::Mesh mesh, const glm::mat4& transform, glm::vec3 colour) {
  pbr::Object o;
  o.mesh = std::make_shared<pbr::Mesh>(std::move(mesh));
  o.material.base_color = colour;
  o.material.roughness = 0.6f;
  o.transform = transform;
  return o;
}

glm::mat4 at(glm::vec3 p) {
  glm::mat4 t(1.0f);
  t[3] = glm::vec4(p, 1.0f);
  return t;
}

constexpr int kSize = 200;
constexpr float kHalf = 2.2f;  // the orthographic view's half width
constexpr float kRadius = 0.5f;
const glm::vec3 kCentre(0.0f, 1.0f, 0.0f);

pbr::Light directional(glm::vec3 direction) {
  pbr::Light l;
  l.type = pbr::LightType::Directional;
  l.direction = direction;
  l.intensity = 3.0f;
  l.shadows = true;
  return l;
}

// A 4 × 4 plane seen straight from above (orthographic), with a sphere of radius 0.5 at
// (0, 1, 0) when `sphere`.
pbr::Scene sphere_over_plane(const pbr::Light& light, bool sphere = true) {
  pbr::Scene s;
  s.camera.position = {0.0f, 10.0f, 0.0f};
  s.camera.target = {0.0f, 0.0f, 0.0f};
  s.camera.up = {0.0f, 0.0f, -1.0f};
  s.camera.orthographic = true;
  s.camera.ymag = kHalf;
  s.objects.push_back(object(pbr::plane(4.0f, 4.0f, 4), glm::mat4(1.0f), glm::vec3(0.7f)));
  if (sphere) s.objects.push_back(object(pbr::uv_sphere(kRadius, 96, 48), at(kCentre), glm::vec3(0.8f, 0.3f, 0.2f)));
  s.lights = {light};
  return s;
}

pbr::Scene without_shadows(pbr::Scene s) {
  for (pbr::Light& l : s.lights) l.shadows = false;
  return s;
}

raster::Target render(const pbr::Scene& s, raster::RendererOptions options = {.threads = 2, .tile_size = 32}) {
  raster::Renderer renderer(options);
  raster::Target t(kSize, kSize);
  pbr::render(s, renderer, t);
  return t;
}

// The point of the plane y = 0 seen at pixel (x, y) of the view from above.
glm::vec3 plane_point(const pbr::Scene& s, int x, int y) {
  const glm::mat4 inv = glm::inverse(s.camera.projection(1.0f) * s.camera.view());
  const float nx = (static_cast<float>(x) + 0.5f) / kSize * 2.0f - 1.0f;
  const float ny = 1.0f - (static_cast<float>(y) + 0.5f) / kSize * 2.0f;
  const glm::vec4 p = inv * glm::vec4(nx, ny, 0.0f, 1.0f);
  return {p.x / p.w, 0.0f, p.z / p.w};
}

// The distance from the sphere's centre to the ray from q towards the light (unit `to_light`);
// a large number when the centre lies behind q.
float ray_distance(glm::vec3 q, glm::vec3 to_light) {
  const glm::vec3 c = kCentre - q;
  if (glm::dot(c, to_light) <= 0.0f) return 1e9f;
  return glm::length(glm::cross(c, to_light));
}

bool same_pixel(const raster::Target& a, const raster::Target& b, int x, int y) {
  const glm::vec4 p = a.color(x, y), q = b.color(x, y);
  return p.r == q.r && p.g == q.g && p.b == q.b && p.a == q.a;
}

float luminance(const raster::Target& t, int x, int y) {
  const glm::vec4 c = t.color(x, y);
  return c.r + c.g + c.b;
}

}  // namespace

TEST_CASE("shadows: the depth-only draw writes the depths of the full pipeline, bit for bit") {
  const std::vector<Draw> draws = depth_scene();
  const glm::mat4 vp = depth_view_projection();
  for (const int tile : {8, 16, 64}) {
    for (const unsigned threads : {1u, 3u}) {
      CAPTURE(tile);
      CAPTURE(threads);
      raster::Renderer renderer({.threads = threads, .tile_size = tile});
      raster::Target full(160, 120), depth = raster::Target::depth_only(160, 120), mixed(160, 120);
      renderer.begin_frame(full, raster::ClearValues{glm::vec4(0.25f), 1.0f});
      for (const Draw& d : draws) {
        NormalShader s;
        s.model = d.model;
        s.view_projection = vp;
        raster::DrawState state;
        state.cull = raster::Cull::Back;
        renderer.draw(s, d.mesh.vertices, d.mesh.indices, state);
      }
      renderer.end_frame();
      for (raster::Target* t : {&depth, &mixed}) {
        renderer.begin_frame(*t, raster::ClearValues{glm::vec4(0.25f), 1.0f});
        for (const Draw& d : draws) {
          DepthShader s;
          s.model = d.model;
          s.view_projection = vp;
          raster::DrawState state;
          state.cull = raster::Cull::Back;
          renderer.draw(s, d.mesh.vertices, d.mesh.indices, state);
        }
        renderer.end_frame();
      }
      CHECK(raster::hash_depths(depth) == raster::hash_depths(full));
      CHECK(raster::hash_depths(mixed) == raster::hash_depths(full));
      // On a target with colour, the depth-only draw leaves the colour as cleared.
      const raster::Target cleared = [&] {
        raster::Target c(160, 120);
        renderer.begin_frame(c, raster::ClearValues{glm::vec4(0.25f), 1.0f});
        renderer.end_frame();
        return c;
      }();
      CHECK(raster::hash_colors(mixed) == raster::hash_colors(cleared));
      // And something was drawn: the depth is not all the clear value.
      std::size_t written = 0;
      for (const float z : std::as_const(depth).depths()) written += z < 1.0f ? 1u : 0u;
      CHECK(written > 160u * 120u / 2u);
    }
  }
}

TEST_CASE("shadows: an alpha-tested depth-only draw keeps the depths the full pipeline keeps") {
  const std::vector<Draw> draws = depth_scene();
  const glm::mat4 vp = depth_view_projection();
  test::for_spread_of_render_configs(5, 32, [&](const raster::RendererOptions& options) {
    raster::Renderer renderer(options);
    raster::Target full(160, 120), depth = raster::Target::depth_only(160, 120);
    const auto draw_all = [&](auto shader, raster::Target& t) {
      renderer.begin_frame(t, raster::ClearValues{glm::vec4(0.0f), 1.0f});
      for (const Draw& d : draws) {
        shader.model = d.model;
        shader.view_projection = vp;
        shader.cut = 0.25f;
        raster::DrawState state;
        state.alpha_test = true;
        renderer.draw(shader, d.mesh.vertices, d.mesh.indices, state);
      }
      renderer.end_frame();
    };
    draw_all(CutShader{}, full);
    draw_all(DepthCutShader{}, depth);
    CHECK(raster::hash_depths(depth) == raster::hash_depths(full));
  });
}

TEST_CASE("shadows: a depth-only target refuses colour shaders, and has no colour to read") {
  raster::Renderer renderer({.threads = 1});
  raster::Target depth = raster::Target::depth_only(32, 32);
  CHECK(depth.is_depth_only());
  CHECK(std::as_const(depth).colors().empty());
  CHECK_THROWS_AS(raster::resolve_srgb8(depth), std::logic_error);
  const pbr::Mesh m = pbr::cube(1.0f);
  renderer.begin_frame(depth, raster::ClearValues{});
  CHECK_THROWS_AS(renderer.draw(CutShader{}, m.vertices, m.indices), std::invalid_argument);
  renderer.end_frame();
  raster::Target msaa(32, 32, 4);
  renderer.begin_frame(msaa, raster::ClearValues{});
  CHECK_THROWS_AS(renderer.draw(DepthShader{}, m.vertices, m.indices), std::invalid_argument);
  renderer.end_frame();
}

TEST_CASE("shadows: a sphere over a plane darkens exactly the ellipse of the sphere projected along the light") {
  for (const glm::vec3 direction : {glm::vec3(0.3f, -1.0f, -0.5f), glm::vec3(0.6f, -1.0f, 0.25f), glm::vec3(-1.0f, -0.9f, 0.0f)}) {
    CAPTURE(direction.x);
    CAPTURE(direction.z);
    const pbr::Scene on = sphere_over_plane(directional(direction));
    const raster::Target a = render(on), b = render(without_shadows(on));
    const glm::vec3 to_light = -glm::normalize(direction);
    // The filter's reach on the plane, as a distance from the sphere's centre to the ray
    // (texels of 4 × 4 world units / 2048, a few of them, plus a pixel of 0.022 and the
    // sphere's facets): pixels nearer the ellipse's edge than this are not judged.
    constexpr float kBand = 0.035f;
    int predicted = 0, wrong = 0, lit_exact = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const glm::vec3 q = plane_point(on, x, y);
        if (std::abs(q.x) > 1.95f || std::abs(q.z) > 1.95f) continue;  // the plane's edge
        // Pixels that see the sphere itself (from above: within its radius) are not the plane's.
        if (q.x * q.x + q.z * q.z < (kRadius + 0.03f) * (kRadius + 0.03f)) continue;
        const float d = ray_distance(q, to_light);
        if (std::abs(d - kRadius) < kBand) continue;
        if (d < kRadius) {
          ++predicted;
          if (!(luminance(a, x, y) < 0.5f * luminance(b, x, y))) ++wrong;
        } else {
          if (same_pixel(a, b, x, y)) ++lit_exact;
          else ++wrong;
        }
      }
    CAPTURE(predicted);
    CAPTURE(lit_exact);
    CHECK(wrong == 0);
    CHECK(predicted > 500);
  }
}

TEST_CASE("shadows: a light moved past an occluder's edge un-shadows the region below it") {
  // A box of side 0.6 at (0, 1, 0): x and z in [−0.3, 0.3], y in [0.7, 1.3]. The light comes
  // from −x at angle α from the vertical; the plane's points q with x in [0.35, 1.95] and
  // |z| < 0.25 are shadowed when their ray to the light, x(y) = q.x − y · tan α, crosses the
  // box's x range at the box's heights. Straight down (α = 0) every one of them is lit.
  pbr::Scene s = sphere_over_plane(directional({0.0f, -1.0f, 0.0f}), false);
  s.objects.push_back(object(pbr::cube(0.6f), at({0.0f, 1.0f, 0.0f}), glm::vec3(0.5f)));
  constexpr float kBand = 0.035f;
  for (const float degrees : {0.0f, 20.0f, 35.0f, 45.0f, 60.0f}) {
    CAPTURE(degrees);
    const double alpha = degrees * 3.14159265358979323846 / 180.0;
    const auto t = static_cast<float>(std::tan(alpha));
    s.lights[0].direction = {static_cast<float>(std::sin(alpha)), -static_cast<float>(std::cos(alpha)), 0.0f};
    const raster::Target a = render(s), off = render(without_shadows(s));
    int shadowed = 0, lit = 0, wrong = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const glm::vec3 q = plane_point(s, x, y);
        if (q.x < 0.35f || q.x > 1.95f || std::abs(q.z) > 0.25f) continue;
        // How far inside the box's x range the ray's crossing lies (negative: outside).
        const float inside = std::min(0.3f - (q.x - 1.3f * t), (q.x - 0.7f * t) + 0.3f);
        if (std::abs(inside) < kBand) continue;
        if (inside > 0.0f) {
          ++shadowed;
          if (!(luminance(a, x, y) < 0.5f * luminance(off, x, y))) ++wrong;
        } else {
          ++lit;
          if (!same_pixel(a, off, x, y)) ++wrong;
        }
      }
    CAPTURE(shadowed);
    CAPTURE(lit);
    CHECK(wrong == 0);
    if (degrees == 0.0f) CHECK(shadowed == 0);
    if (degrees == 45.0f) CHECK(shadowed > 300);
  }
}

TEST_CASE("shadows: a lit sphere has no acne: its pixels are the unshadowed ones but near the terminator") {
  // A sphere alone, seen from the front (orthographic), lit from the side and a little
  // behind: the terminator crosses the visible disc.
  for (const glm::vec3 direction : {glm::vec3(-1.0f, 0.0f, 0.0f), glm::vec3(-1.0f, -0.3f, 0.4f), glm::vec3(-0.2f, -1.0f, 0.3f)}) {
    CAPTURE(direction.x);
    CAPTURE(direction.y);
    pbr::Scene s;
    s.camera.position = {0.0f, 0.0f, 5.0f};
    s.camera.orthographic = true;
    s.camera.ymag = 1.2f;
    s.objects.push_back(object(pbr::uv_sphere(1.0f, 96, 48), glm::mat4(1.0f), glm::vec3(0.8f)));
    s.lights = {directional(direction)};
    const raster::Target a = render(s), b = render(without_shadows(s));
    const glm::vec3 to_light = -glm::normalize(direction);
    int differ = 0, far_from_terminator = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const float px = ((static_cast<float>(x) + 0.5f) / kSize * 2.0f - 1.0f) * 1.2f;
        const float py = (1.0f - (static_cast<float>(y) + 0.5f) / kSize * 2.0f) * 1.2f;
        const float r2 = px * px + py * py;
        if (r2 > 0.98f) continue;  // the rim: facets against the background
        const glm::vec3 n(px, py, std::sqrt(1.0f - r2));
        const float NoL = glm::dot(n, to_light);
        if (same_pixel(a, b, x, y)) continue;
        ++differ;
        // The filter's reach at the terminator: ~sqrt(2 · 6 texels / 2048 · 2.2 / radius) rad,
        // plus the facets' 2 · π/96 between the smooth and the flat normal.
        if (NoL > 0.25f) ++far_from_terminator;
      }
    CAPTURE(differ);
    CHECK(far_from_terminator == 0);
  }
}

TEST_CASE("shadows: a scene without occluders renders bit for bit as with shadows off") {
  pbr::Light spot;
  spot.type = pbr::LightType::Spot;
  spot.position = {0.5f, 2.0f, 0.5f};
  spot.direction = {-0.2f, -1.0f, -0.1f};
  spot.outer_cone = 0.7f;
  spot.intensity = 4.0f;
  spot.shadows = true;
  pbr::Light point;
  point.position = {-0.8f, 1.0f, 0.3f};
  point.intensity = 2.0f;
  point.shadows = true;
  pbr::Scene s = sphere_over_plane(directional({0.3f, -1.0f, 0.2f}), false);
  s.lights.push_back(spot);
  s.lights.push_back(point);
  const raster::Target a = render(s), b = render(without_shadows(s));
  CHECK(raster::hash_colors(a) == raster::hash_colors(b));
}

TEST_CASE("shadows: point and spot lights shadow what lies behind an occluder, and nothing else") {
  pbr::Light point;
  point.position = {0.0f, 0.6f, 0.0f};
  point.intensity = 2.0f;
  point.shadows = true;
  pbr::Light spot = point;
  spot.type = pbr::LightType::Spot;
  spot.direction = {1.0f, -0.4f, 0.0f};
  spot.outer_cone = 0.8f;
  for (const pbr::Light& light : {point, spot}) {
    CAPTURE(static_cast<int>(light.type));
    pbr::Scene s = sphere_over_plane(light, false);
    // A ball at (1, 0.35, 0) of radius 0.3: the ray from the light through its centre meets
    // the plane at x = 2.4 … beyond the plane; use a ball at (0.8, 0.35, 0): x = 1.92.
    s.objects.push_back(object(pbr::uv_sphere(0.2f, 48, 24), at({0.8f, 0.35f, 0.0f}), glm::vec3(0.5f)));
    const raster::Target a = render(s), b = render(without_shadows(s));
    int behind = 0, shadowed = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const glm::vec3 q = plane_point(s, x, y);
        if (std::abs(q.x) > 1.95f || std::abs(q.z) > 1.95f) continue;
        // The distance from the ball's centre to the segment from q to the light.
        const glm::vec3 to = light.position - q;
        const glm::vec3 c = glm::vec3(0.8f, 0.35f, 0.0f) - q;
        const float t = glm::dot(c, to) / glm::dot(to, to);
        if (q.x > 0.5f && q.x < 1.1f && std::abs(q.z) < 0.3f) continue;  // the ball itself, seen from above
        const float d = t <= 0.0f || t >= 1.0f ? 1e9f : glm::length(c - to * t);
        if (d < 0.12f) {
          ++behind;
          if (luminance(a, x, y) < 0.5f * luminance(b, x, y)) ++shadowed;
        } else if (d > 0.3f) {
          CHECK(same_pixel(a, b, x, y));
        }
      }
    CHECK(behind > 20);
    CHECK(shadowed == behind);
  }
}

TEST_CASE("shadows: masked and blended casters cast where their alpha keeps them, cast_shadows and receive_shadows") {
  const pbr::Light light = directional({0.0f, -1.0f, 0.0f});
  const auto with_material = [&](pbr::AlphaMode mode, float alpha) {
    pbr::Scene s = sphere_over_plane(light, true);
    s.objects[1].material.alpha_mode = mode;
    s.objects[1].material.alpha = alpha;
    return s;
  };
  // A masked sphere below its cutoff is drawn nowhere and casts nothing: the plane alone.
  const pbr::Scene masked_out = with_material(pbr::AlphaMode::Mask, 0.3f);
  const pbr::Scene plane_alone = sphere_over_plane(light, false);
  CHECK(raster::hash_colors(render(masked_out)) == raster::hash_colors(render(plane_alone)));
  // Opaque-enough casters: a masked sphere above its cutoff and a blended one of alpha 0.8
  // shadow the plane around their foot where the ellipse lies beyond their own disc — with
  // the light at 45° (the shadow then falls beside the sphere).
  struct Case {
    pbr::AlphaMode mode;
    float alpha;
    bool casts;
  };
  for (const Case& c : {Case{pbr::AlphaMode::Mask, 0.9f, true}, Case{pbr::AlphaMode::Blend, 0.8f, true},
                        Case{pbr::AlphaMode::Blend, 0.3f, false}}) {
    const bool expect = c.casts;
    const int mode = static_cast<int>(c.mode);
    CAPTURE(mode);
    CAPTURE(expect);
    pbr::Scene s = with_material(c.mode, c.alpha);
    s.lights[0].direction = {1.0f, -1.0f, 0.0f};
    const raster::Target a = render(s), b = render(without_shadows(s));
    // The point on the plane whose ray to the light passes through the centre: (1, 0, 0).
    const int x = static_cast<int>((1.0f + kHalf) / (2.0f * kHalf) * kSize), y = kSize / 2;
    CHECK((luminance(a, x, y) < 0.5f * luminance(b, x, y)) == expect);
  }
  // cast_shadows = false on the sphere, or receive_shadows = false on the plane: the plane as
  // without shadows.
  pbr::Scene s = sphere_over_plane(directional({1.0f, -1.0f, 0.0f}));
  const std::uint64_t off = raster::hash_colors(render(without_shadows(s)));
  pbr::Scene no_cast = s;
  no_cast.objects[1].cast_shadows = false;
  pbr::Scene no_receive = s;
  no_receive.objects[0].receive_shadows = false;
  no_receive.objects[1].receive_shadows = false;
  CHECK(raster::hash_colors(render(s)) != off);
  // The sphere still shadows itself where it is lit from within the filter's reach; with
  // cast_shadows off nothing casts at all.
  CHECK(raster::hash_colors(render(no_cast)) == off);
  CHECK(raster::hash_colors(render(no_receive)) == off);
}

TEST_CASE("shadows: the same bits for every thread count, tile size, lane width, dispatch and sample count") {
  pbr::Light spot;
  spot.type = pbr::LightType::Spot;
  spot.position = {1.0f, 2.5f, 0.5f};
  spot.direction = {-0.4f, -1.0f, -0.2f};
  spot.outer_cone = 0.6f;
  spot.intensity = 5.0f;
  spot.shadows = true;
  pbr::Light point;
  point.position = {-1.0f, 1.4f, 0.8f};
  point.intensity = 2.0f;
  point.shadows = true;
  pbr::Scene s = sphere_over_plane(directional({0.5f, -1.0f, 0.3f}));
  s.lights.push_back(spot);
  s.lights.push_back(point);
  s.camera.orthographic = false;
  s.camera.position = {2.0f, 3.0f, 3.5f};
  s.camera.up = {0.0f, 1.0f, 0.0f};
  s.objects[1].material.alpha_mode = pbr::AlphaMode::Mask;  // the textured shader and a masked caster
  s.objects[1].material.alpha = 0.9f;
  test::check_same_bits_for_every_config(s, kSize);
}
