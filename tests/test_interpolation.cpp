// Interpolation and per-pixel state: perspective-correct varyings against ray–plane
// intersections, screen-space derivatives, the depth tests, depth writes, premultiplied
// "over" blending, and helper lanes that never write.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "raster_helpers.h"
#include "softpbr/pbr/camera.h"

namespace {

namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;
namespace test = softpbr::test;

struct PlaneVertex {
  glm::vec3 position;
  glm::vec2 uv;
};

// mode 0: (u, v, 0, 1); mode 1: the coarse derivatives (ddx.u, ddy.u, ddx.v, ddy.v).
struct PlaneShader {
  using Vertex = PlaneVertex;
  struct Varyings {
    glm::vec2 uv;
  };
  glm::mat4 view_projection;
  int mode = 0;
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.uv = in.uv;
    return view_projection * glm::vec4(in.position, 1.0f);
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    if (mode == 0) return {f.v.uv.x, f.v.uv.y, 0.0f, 1.0f};
    return {f.ddx.uv.x, f.ddy.uv.x, f.ddx.uv.y, f.ddy.uv.y};
  }
};

// The ground plane y = 0 seen through a camera, with rays through pixel centres in double.
struct GroundView {
  int width, height;
  glm::mat4 view_projection;
  glm::dmat4 inverse;

  GroundView(int w, int h, glm::vec3 eye, glm::vec3 target)
      : width(w),
        height(h),
        view_projection(pbr::perspective(static_cast<float>(softpbr::dmath::radians(50.0)), static_cast<float>(w) / h,
                                         0.1f, 200.0f) *
                        pbr::look_at(eye, target, {0, 1, 0})),
        inverse(glm::inverse(glm::dmat4(view_projection))) {}

  // Where the ray through pixel position (px, py) meets the ground; false above the horizon.
  bool hit(double px, double py, glm::dvec3& out) const {
    const double nx = 2.0 * px / width - 1.0, ny = 1.0 - 2.0 * py / height;
    glm::dvec4 a = inverse * glm::dvec4(nx, ny, -1.0, 1.0), b = inverse * glm::dvec4(nx, ny, 1.0, 1.0);
    const glm::dvec3 near = glm::dvec3(a) / a.w, far = glm::dvec3(b) / b.w;
    if (!(near.y > 0 && far.y < 0)) return false;
    const double t = near.y / (near.y - far.y);
    out = near + t * (far - near);
    return true;
  }
};

// Renders `mesh` with the plane shader in `mode` into a target cleared to 0.
raster::Target render_plane(const GroundView& view, const std::vector<PlaneVertex>& vertices,
                            const std::vector<std::uint32_t>& indices, int mode) {
  raster::Renderer renderer({.threads = 2, .tile_size = 32});
  raster::Target target(view.width, view.height);
  target.clear({0, 0, 0, 0});
  renderer.begin_frame(target);
  renderer.draw(PlaneShader{view.view_projection, mode}, std::span<const PlaneVertex>(vertices), indices);
  renderer.end_frame();
  return target;
}

}  // namespace

TEST_CASE("perspective-correct varyings on a steeply foreshortened ground plane match the ray-plane intersection") {
  const GroundView view(192, 144, {0, 1, 0}, {0, 0.2f, -4});
  // Corners chosen on screen (1/256-exact pixel positions), placed on the plane by their
  // rays: the projected quad then snaps exactly where it was chosen. The far edge sits
  // about 18 units away, the near one below the bottom of the target.
  const double corners[4][2] = {{-30, 170}, {222, 170}, {130, 50}, {60, 50}};
  std::vector<PlaneVertex> on_screen;
  for (const auto& c : corners) {
    glm::dvec3 p{};
    REQUIRE(view.hit(c[0], c[1], p));
    on_screen.push_back({glm::vec3(p), {static_cast<float>(-p.z), static_cast<float>(p.x)}});
  }
  // A second quad reaching from behind the eye to far corners chosen the same way: the
  // near plane clips it. (Far corners must be exact: near the horizon one pixel spans
  // several units of u, so a 1/512-pixel snap would move u by ~1e-3 there.)
  std::vector<PlaneVertex> clipped;
  for (const glm::vec3 p : {glm::vec3{-12, 0, 3}, glm::vec3{12, 0, 3}}) clipped.push_back({p, {-p.z, p.x}});
  for (const auto& c : {std::array<double, 2>{176, 52}, std::array<double, 2>{16, 52}}) {
    glm::dvec3 p{};
    REQUIRE(view.hit(c[0], c[1], p));
    clipped.push_back({glm::vec3(p), {static_cast<float>(-p.z), static_cast<float>(p.x)}});
  }
  const std::vector<std::uint32_t> quad = {0, 1, 2, 0, 2, 3};

  for (const auto* vertices : {&on_screen, &clipped}) {
    const raster::Target t = render_plane(view, *vertices, quad, 0);
    int covered = 0, bad = 0;
    double worst = 0;
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x) {
        const glm::vec4 c = t.color(x, y);
        if (c.a == 0) continue;
        ++covered;
        glm::dvec3 p{};
        if (!view.hit(x + 0.5, y + 0.5, p)) {
          ++bad;  // drawn above the horizon
          continue;
        }
        const double eu = std::fabs(c.r - -p.z) / std::max(1.0, std::fabs(p.z));
        const double ev = std::fabs(c.g - p.x) / std::max(1.0, std::fabs(p.x));
        worst = std::max({worst, eu, ev});
        bad += eu > 2e-5 || ev > 2e-5;  // measured: a few 1e-6
      }
    MESSAGE("worst relative error of perspective-correct u, v: " << worst);
    CAPTURE(vertices == &clipped);
    CHECK(bad == 0);
    CHECK(covered > view.width * view.height / 4);
  }
}

TEST_CASE("coarse derivatives are per quad: equal on its four pixels, the differences of its top-left pixel's neighbours") {
  const GroundView view(128, 96, {0, 1, 0}, {0, 0.3f, -4});
  std::vector<PlaneVertex> tri;
  for (const glm::vec3 p : {glm::vec3{-8, 0, -1.5f}, glm::vec3{8, 0, -1.5f}, glm::vec3{0, 0, -25}})
    tri.push_back({p, {-p.z, p.x}});
  const std::vector<std::uint32_t> idx = {0, 1, 2};  // one triangle: every quad is inside it alone
  const raster::Target values = render_plane(view, tri, idx, 0);
  const raster::Target derivs = render_plane(view, tri, idx, 1);
  int quads = 0, wrong = 0;
  for (int y = 0; y + 1 < view.height; y += 2)
    for (int x = 0; x + 1 < view.width; x += 2) {
      const glm::vec4 v00 = values.color(x, y), v10 = values.color(x + 1, y), v01 = values.color(x, y + 1),
                      v11 = values.color(x + 1, y + 1);
      if (v00.a == 0 || v10.a == 0 || v01.a == 0 || v11.a == 0) continue;  // not fully covered
      ++quads;
      const glm::vec4 d = derivs.color(x, y);
      wrong += derivs.color(x + 1, y) != d || derivs.color(x, y + 1) != d || derivs.color(x + 1, y + 1) != d;
      wrong += d.x != v10.r - v00.r || d.y != v01.r - v00.r || d.z != v10.g - v00.g || d.w != v01.g - v00.g;
    }
  CHECK(wrong == 0);
  CHECK(quads > 200);
}

// Screen-linear varyings: u = a·x + b·y + c in pixel coordinates (w constant per draw).
struct LinearShader {
  using Vertex = std::array<float, 6>;  // clip x, y, z, w, u, v
  struct Varyings {
    float u, v;
  };
  int mode = 0;
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.u = in[4];
    out.v = in[5];
    return {in[0], in[1], in[2], in[3]};
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    if (mode == 0) return {f.v.u, f.v.v, 0, 1};
    return {f.ddx.u, f.ddy.u, f.ddx.v, f.ddy.v};
  }
};

TEST_CASE("derivatives of a screen-linear varying equal its per-pixel gradient everywhere, helper lanes included") {
  constexpr int kW = 64, kH = 48;
  struct Gradient {
    double au, bu, cu, av, bv, cv;
  };
  const Gradient gradients[] = {{0.75, -0.5, 3.0, -0.125, 0.25, -1.0}, {1.0 / 3.0, 0.1, -7.0, 0.0, -1.7, 20.0}};
  // Triangles of every size and slant, some reaching past the target.
  const test::Point triangles[][3] = {{{-10, -6}, {80, 5}, {20, 60}},
                                      {{3.2, 4.7}, {9.9, 5.1}, {4.0, 40.3}},
                                      {{30.5, 2.5}, {61.5, 45.5}, {2.5, 30.5}},
                                      {{10.1, 10.1}, {13.3, 11.2}, {11.0, 14.7}}};
  for (const Gradient& g : gradients)
    for (const auto& tri : triangles)
      for (const double w : {1.0, 2.5}) {
        std::vector<LinearShader::Vertex> verts;
        for (test::Point p : tri) {
          // On the 1/256 grid, so snapping keeps the gradient the vertices define.
          p = {std::round(p.x * 256) / 256, std::round(p.y * 256) / 256};
          const glm::vec4 c = test::pixel_to_clip(p.x, p.y, kW, kH, w);
          verts.push_back({c.x, c.y, c.z, c.w, static_cast<float>(g.au * p.x + g.bu * p.y + g.cu),
                           static_cast<float>(g.av * p.x + g.bv * p.y + g.cv)});
        }
        raster::Target values(kW, kH), derivs(kW, kH);
        for (raster::Target* t : {&values, &derivs}) {
          t->clear({0, 0, 0, 0});
          raster::Renderer renderer({.threads = 1, .tile_size = 16});
          renderer.begin_frame(*t);
          renderer.draw(LinearShader{t == &derivs ? 1 : 0}, std::span<const LinearShader::Vertex>(verts));
          renderer.end_frame();
        }
        int covered = 0, wrong = 0;
        double worst = 0;
        for (int y = 0; y < kH; ++y)
          for (int x = 0; x < kW; ++x) {
            if (values.color(x, y).a == 0) continue;
            ++covered;
            const double px = x + 0.5, py = y + 0.5;
            const glm::vec4 v = values.color(x, y), d = derivs.color(x, y);
            const double err[] = {v.r - (g.au * px + g.bu * py + g.cu), v.g - (g.av * px + g.bv * py + g.cv),
                                  d.x - g.au, d.y - g.bu, d.z - g.av, d.w - g.bv};
            for (double e : err) worst = std::max(worst, std::fabs(e));
            for (double e : err) wrong += std::fabs(e) > 1e-4;
          }
        CAPTURE(tri[0].x);
        CAPTURE(w);
        CAPTURE(worst);
        CHECK(wrong == 0);
        CHECK(covered > 0);
      }
}

// Four screen-linear varyings (a, b, c, d); the colour is (ddx.b, ddy.c, ddx.a, ddy.d).
// kMasked: kDerivativeMask names b and c only. Scalar: fragment() alone; packet: with
// fragment_packet too.
template <bool kMasked>
struct DerivativeMaskShader {
  using Vertex = std::array<float, 8>;  // clip x, y, z, w, a, b, c, d
  struct Varyings {
    float a, b, c, d;
  };
  static constexpr std::uint32_t kDerivativeMask =
      kMasked ? raster::varying_bits(offsetof(Varyings, b), 2 * sizeof(float)) : ~std::uint32_t{0};
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out = {in[4], in[5], in[6], in[7]};
    return {in[0], in[1], in[2], in[3]};
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {f.ddx.b, f.ddy.c, f.ddx.a, f.ddy.d}; }
};
template <bool kMasked>
struct DerivativeMaskPacketShader : DerivativeMaskShader<kMasked> {
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, typename DerivativeMaskShader<kMasked>::Varyings>& p) const {
    return {p.ddx[1], p.ddy[2], p.ddx[0], p.ddy[3]};
  }
};

TEST_CASE("kDerivativeMask: the named varyings get the same derivatives as without it, the others zero, at every width") {
  static_assert(raster::varying_bits(4, 8) == 0x6u && raster::varying_bits(0, 0) == 0u);
  static_assert(raster::kDerivativeMask<DerivativeMaskShader<true>> == 0x6u);
  constexpr int kW = 40, kH = 30;
  // Triangles with perspective (w per vertex), partly covered quads and one past the edge.
  const test::Point triangles[][3] = {{{-6, -3}, {47, 4}, {12, 35}}, {{3.2, 4.7}, {9.9, 5.1}, {4.0, 25.3}},
                                      {{20.5, 2.5}, {38.5, 28.5}, {2.5, 20.5}}};
  const float ws[3] = {1.0f, 2.0f, 3.5f};
  std::vector<DerivativeMaskShader<true>::Vertex> verts;
  for (const auto& tri : triangles)
    for (int i = 0; i < 3; ++i) {
      const glm::vec4 c = test::pixel_to_clip(tri[i].x, tri[i].y, kW, kH, ws[i]);
      const float x = static_cast<float>(tri[i].x), y = static_cast<float>(tri[i].y);
      verts.push_back({c.x, c.y, c.z, c.w, 0.5f * x - y, 2.0f * y + 0.25f * x, x * 0.125f + 3.0f, -y});
    }
  auto render = [&](auto shader, int lanes) {
    raster::Target t(kW, kH);
    t.clear({0, 0, 0, 0}, 1.0f);
    raster::Renderer renderer({.threads = 1, .tile_size = 16, .lanes = lanes});
    renderer.begin_frame(t);
    renderer.draw(shader, std::span<const DerivativeMaskShader<true>::Vertex>(verts),
                  raster::DrawState{.depth_test = raster::DepthTest::Always});
    renderer.end_frame();
    return t;
  };
  const raster::Target full = render(DerivativeMaskShader<false>{}, 0);
  int nonzero_full = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) nonzero_full += full.color(x, y).z != 0 && full.color(x, y).w != 0;
  CHECK(nonzero_full > 100);  // the unmasked shader does see a and d change
  for (const int lanes : {0, 1, 4, 8, 16}) {
    const raster::Target masked =
        lanes == 0 ? render(DerivativeMaskShader<true>{}, 1) : render(DerivativeMaskPacketShader<true>{}, lanes);
    CAPTURE(lanes);
    int wrong = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const glm::vec4 f = full.color(x, y), m = masked.color(x, y);
        wrong += m.x != f.x || m.y != f.y || m.z != 0.0f || m.w != 0.0f;
      }
    CHECK(wrong == 0);
  }
}

// A flat colour with depth from the clip position.
struct ColorShader {
  using Vertex = glm::vec4;
  struct Varyings {};
  glm::vec4 color;
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
  glm::vec4 fragment(const raster::Fragment<Varyings>&) const { return color; }
};

raster::Target draw_layers(const std::vector<std::vector<glm::vec4>>& layers, const std::vector<glm::vec4>& colors,
                           const std::vector<int>& order, raster::DrawState state, int tile = 16) {
  raster::Target target(48, 40);
  target.clear({0, 0, 0, 0}, 1.0f);
  raster::Renderer renderer({.threads = 2, .tile_size = tile});
  renderer.begin_frame(target);
  for (int i : order)
    renderer.draw(ColorShader{colors[i]}, std::span<const glm::vec4>(layers[i]), state);
  renderer.end_frame();
  return target;
}

TEST_CASE("with DepthTest::Less, overlapping triangles at different depths give the same image in every submission order") {
  // Three large overlapping triangles with sloped depths in separate ranges (NDC z) and a
  // w that varies per vertex; layer 0 is nearest.
  auto tri = [](glm::vec2 a, glm::vec2 b, glm::vec2 c, float z0, float z1, float z2) {
    const float w[3] = {1.0f, 2.0f, 3.0f};
    const glm::vec2 p[3] = {a, b, c};
    const float z[3] = {z0, z1, z2};
    std::vector<glm::vec4> out;
    for (int i = 0; i < 3; ++i) out.push_back({p[i].x * w[i], p[i].y * w[i], z[i] * w[i], w[i]});
    return out;
  };
  const std::vector<std::vector<glm::vec4>> layers = {
      tri({-0.9f, -0.8f}, {0.6f, -0.7f}, {-0.2f, 0.9f}, -0.6f, -0.5f, -0.4f),
      tri({-0.6f, 0.8f}, {-0.5f, -0.9f}, {0.9f, 0.1f}, -0.1f, 0.1f, 0.0f),
      tri({0.9f, 0.9f}, {-0.9f, 0.5f}, {0.2f, -0.9f}, 0.5f, 0.3f, 0.45f)};
  const std::vector<glm::vec4> colors = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
  std::vector<int> order = {0, 1, 2};
  raster::DrawState less;  // Less, depth writes on, replace
  const raster::Target reference = draw_layers(layers, colors, order, less);
  std::set<std::uint64_t> painter_hashes;
  raster::DrawState always;
  always.depth_test = raster::DepthTest::Always;
  int permutations = 0;
  do {
    for (const int tile : {8, 32}) {
      const raster::Target t = draw_layers(layers, colors, order, less, tile);
      CAPTURE(order[0]);
      CAPTURE(order[1]);
      CAPTURE(order[2]);
      CHECK(raster::hash_colors(t) == raster::hash_colors(reference));
      CHECK(raster::hash_depths(t) == raster::hash_depths(reference));
    }
    painter_hashes.insert(raster::hash_colors(draw_layers(layers, colors, order, always)));
    ++permutations;
  } while (std::next_permutation(order.begin(), order.end()));
  CHECK(permutations == 6);
  // The triangles really overlap: without the depth test the order shows.
  CHECK(painter_hashes.size() > 1);
  // Where all three overlap (the NDC origin), the nearest one is seen.
  CHECK(reference.color(24, 20) == glm::vec4(1, 0, 0, 1));
  CHECK(reference.depth(24, 20) < 0.3f);
}

TEST_CASE("at equal depth Less keeps the first triangle, LessEqual and Always let the second one through") {
  const std::vector<glm::vec4> tri = {{-0.8f, -0.8f, 0.2f, 1}, {0.8f, -0.7f, -0.3f, 1}, {0.0f, 0.9f, 0.5f, 1}};
  const std::vector<std::vector<glm::vec4>> layers = {tri, tri};
  const std::vector<glm::vec4> colors = {{1, 0, 0, 1}, {0, 1, 0, 1}};
  const struct {
    raster::DepthTest test;
    glm::vec4 seen;
  } cases[] = {{raster::DepthTest::Less, colors[0]},
               {raster::DepthTest::LessEqual, colors[1]},
               {raster::DepthTest::Always, colors[1]}};
  for (const auto& c : cases) {
    raster::DrawState state;
    state.depth_test = c.test;
    const raster::Target t = draw_layers(layers, colors, {0, 1}, state);
    int covered = 0, wrong = 0;
    for (int i = 0; i < 48 * 40; ++i) {
      const glm::vec4 px = t.colors()[i];
      if (px.a == 0) continue;
      ++covered;
      wrong += px != c.seen;
    }
    CAPTURE(static_cast<int>(c.test));
    CHECK(wrong == 0);
    CHECK(covered > 300);
  }
}

TEST_CASE("depth equals the window depth 0.5 + 0.5 z/w interpolated linearly in screen space") {
  constexpr int kW = 48, kH = 40;
  // z/w linear in screen space: z_ndc = 0.01·x − 0.02·y + 0.1 (pixel coordinates).
  const test::Point p[3] = {{-5, -3}, {60, 10}, {12, 55}};
  std::vector<glm::vec4> tri;
  const float w[3] = {1.0f, 0.5f, 4.0f};
  for (int i = 0; i < 3; ++i) {
    glm::vec4 c = test::pixel_to_clip(p[i].x, p[i].y, kW, kH, w[i]);
    c.z = static_cast<float>((0.01 * p[i].x - 0.02 * p[i].y + 0.1) * w[i]);
    tri.push_back(c);
  }
  const raster::Target t = draw_layers({tri}, {{1, 1, 1, 1}}, {0}, raster::DrawState{});
  int covered = 0, wrong = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (t.color(x, y).a == 0) {
        wrong += t.depth(x, y) != 1.0f;  // untouched
        continue;
      }
      ++covered;
      const double expected = 0.5 + 0.5 * (0.01 * (x + 0.5) - 0.02 * (y + 0.5) + 0.1);
      wrong += std::fabs(t.depth(x, y) - expected) > 1e-6;
    }
  CHECK(wrong == 0);
  CHECK(covered > 500);
}

TEST_CASE("depth_write=false leaves the depth buffer untouched and later draws still test against the old depth") {
  const std::vector<glm::vec4> near = {{-0.8f, -0.8f, -0.5f, 1}, {0.8f, -0.7f, -0.5f, 1}, {0.0f, 0.9f, -0.5f, 1}};
  const std::vector<glm::vec4> far = {{-0.9f, -0.9f, 0.5f, 1}, {0.9f, -0.8f, 0.5f, 1}, {0.0f, 0.95f, 0.5f, 1}};
  raster::Target target(48, 40);
  target.clear({0, 0, 0, 0}, 1.0f);
  const std::uint64_t cleared_depth = raster::hash_depths(target);
  raster::Renderer renderer({.threads = 2, .tile_size = 8});
  raster::DrawState no_write;
  no_write.depth_write = false;
  renderer.begin_frame(target);
  renderer.draw(ColorShader{{1, 0, 0, 1}}, std::span<const glm::vec4>(near), no_write);
  renderer.draw(ColorShader{{0, 1, 0, 1}}, std::span<const glm::vec4>(far), no_write);
  renderer.end_frame();
  CHECK(raster::hash_depths(target) == cleared_depth);
  // The far triangle was drawn over the near one: nothing held it back.
  CHECK(target.color(24, 20) == glm::vec4(0, 1, 0, 1));
  // With writes on, the near triangle's depth lands and blocks the far one.
  renderer.begin_frame(target);
  renderer.draw(ColorShader{{1, 0, 0, 1}}, std::span<const glm::vec4>(near));
  renderer.draw(ColorShader{{0, 0, 1, 1}}, std::span<const glm::vec4>(far));
  renderer.end_frame();
  CHECK(raster::hash_depths(target) != cleared_depth);
  CHECK(target.color(24, 20) == glm::vec4(1, 0, 0, 1));
  CHECK(target.depth(24, 20) == 0.25f);
}

TEST_CASE("Blend::Over computes src + dst * (1 - src.a) exactly") {
  const std::vector<glm::vec4> full = {{-3, -3, 0, 1}, {3, -3, 0, 1}, {0, 3, 0, 1}};
  raster::Target target(10, 6);
  target.clear({0.25f, 0.5f, 0.75f, 1.0f});
  raster::DrawState over;
  over.blend = raster::Blend::Over;
  over.depth_test = raster::DepthTest::Always;
  raster::Renderer renderer({.threads = 1, .tile_size = 8});
  renderer.begin_frame(target);
  renderer.draw(ColorShader{{0.125f, 0.25f, 0.0625f, 0.5f}}, std::span<const glm::vec4>(full), over);
  renderer.end_frame();
  // (0.125 + 0.25·0.5, 0.25 + 0.5·0.5, 0.0625 + 0.75·0.5, 0.5 + 1·0.5): all exact in float.
  for (const glm::vec4& c : target.colors()) CHECK(c == glm::vec4(0.25f, 0.5f, 0.4375f, 1.0f));
  // A second layer over the first, and a fully transparent one that adds light.
  renderer.begin_frame(target);
  renderer.draw(ColorShader{{0.5f, 0.0f, 0.25f, 0.75f}}, std::span<const glm::vec4>(full), over);
  renderer.draw(ColorShader{{0.0625f, 0.0f, 0.0f, 0.0f}}, std::span<const glm::vec4>(full), over);
  renderer.end_frame();
  for (const glm::vec4& c : target.colors()) CHECK(c == glm::vec4(0.625f, 0.125f, 0.359375f, 1.0f));
}

// Writes its fragment's position and depth, one pixel at a time or in packets.
struct PositionShader {
  using Vertex = glm::vec4;
  struct Varyings {};
  glm::vec4 vertex(const Vertex& in, Varyings&) const { return in; }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {f.pos.x, f.pos.y, f.depth, 1.0f}; }
};
struct PositionPacketShader : PositionShader {
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {p.pos_x, p.pos_y, p.depth, F(1.0f)};
  }
};

template <class S>
void helper_lanes_never_write(int lanes) {
  constexpr int kW = 16, kH = 12;
  raster::Renderer renderer({.threads = 1, .tile_size = 8, .lanes = lanes});
  // One pixel at every position in its 2×2 quad, and at the target's last row and column.
  const int pixels[][2] = {{4, 4}, {5, 4}, {4, 5}, {5, 5}, {7, 7}, {8, 8}, {15, 11}, {0, 0}};
  for (const auto& px : pixels) {
    const double cx = px[0] + 0.5, cy = px[1] + 0.5;
    std::vector<glm::vec4> tri = {test::pixel_to_clip(cx - 0.3, cy - 0.3, kW, kH),
                                  test::pixel_to_clip(cx + 0.35, cy - 0.2, kW, kH),
                                  test::pixel_to_clip(cx, cy + 0.4, kW, kH)};
    for (glm::vec4& v : tri) v.z = -0.5f;
    raster::Target target(kW, kH);
    target.clear({0, 0, 0, 0}, 1.0f);
    renderer.begin_frame(target);
    renderer.draw(S{}, std::span<const glm::vec4>(tri));
    renderer.end_frame();
    int colours = 0, depths = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        colours += target.color(x, y) != glm::vec4(0, 0, 0, 0);
        depths += target.depth(x, y) != 1.0f;
      }
    CAPTURE(lanes);
    CAPTURE(px[0]);
    CAPTURE(px[1]);
    CHECK(colours == 1);
    CHECK(depths == 1);
    CHECK(target.color(px[0], px[1]) == glm::vec4(static_cast<float>(cx), static_cast<float>(cy), 0.25f, 1.0f));
    CHECK(target.depth(px[0], px[1]) == 0.25f);
  }
}

TEST_CASE("helper lanes never write: a one-pixel triangle changes exactly one colour and one depth") {
  helper_lanes_never_write<PositionShader>(0);
  // In packets, the lanes that pad a packet are discarded too.
  for (const int lanes : {1, 4, 8, 16}) helper_lanes_never_write<PositionPacketShader>(lanes);
}
