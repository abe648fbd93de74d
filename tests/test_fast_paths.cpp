// Fast paths of the renderer against their plain definitions: the table-driven 8-bit
// encoder (ToneMapper) against a binary search over the thresholds, tone mapping fused
// into the frame (render_rgba8) against render() + tone_map_to_rgba8(), and packets that
// fill across triangles against the scalar shader where triangles of one draw overlap.
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

std::uint8_t binary_search_code(const std::array<float, 255>& t, float v) {
  if (!(v >= t[0])) return 0;
  return static_cast<std::uint8_t>(std::upper_bound(t.begin(), t.end(), v) - t.begin());
}

}  // namespace

TEST_CASE("ToneMapper's 8-bit code equals a binary search over the thresholds at and around every threshold") {
  for (const float gamma : {0.0f, 2.2f, 1.0f, 2.4f, 0.5f}) {
    CAPTURE(gamma);
    const pbr::ToneMapper mapper({0.0f, pbr::ToneMap::None, gamma});
    const std::array<float, 255> t = pbr::transfer_thresholds(gamma);
    std::vector<float> values = {0.0f, -0.0f, 1.0f, 0.5f, std::numeric_limits<float>::denorm_min(),
                                 std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                                 -1.0f, 2.0f, 1e9f};
    for (const float x : t)
      for (int step = -3; step <= 3; ++step) {
        float v = x;
        for (int i = 0; i < std::abs(step); ++i) v = std::nextafter(v, step < 0 ? 0.0f : 2.0f);
        values.push_back(v);
      }
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 200000; ++i) values.push_back(unit(rng) * unit(rng));
    int mismatches = 0;
    for (const float v : values) mismatches += mapper.encode(v) != binary_search_code(t, v);
    CHECK(mismatches == 0);
  }
}

TEST_CASE("render_rgba8 gives the bytes of render() then tone_map_to_rgba8 for every tone map, thread count and tile size") {
  pbr::GalleryOptions o;
  o.rows = {"gold", "plastic_red"};
  o.columns = 3;
  o.segments = 24;
  pbr::Scene scene = pbr::make_gallery(o);
  scene.camera.position = {0.0f, 0.0f, 3.5f};  // the 3 × 2 spheres fill the view
  raster::Target target(150, 94);
  for (const pbr::ToneMap op : {pbr::ToneMap::None, pbr::ToneMap::Reinhard, pbr::ToneMap::Aces, pbr::ToneMap::Neutral}) {
    const pbr::OutputSettings out{0.5f, op, op == pbr::ToneMap::Reinhard ? 2.2f : 0.0f};
    raster::Renderer reference_renderer({.threads = 1});
    pbr::render(scene, reference_renderer, target);
    const raster::Image8 reference = pbr::tone_map_to_rgba8(target, out);
    std::size_t lit = 0;
    for (std::size_t i = 0; i < reference.rgba.size(); i += 4) lit += reference.rgba[i] > 10;
    CHECK(lit > 1000);
    for (const unsigned threads : {1u, 2u, 3u})
      for (const int tile : {8, 64})
        for (const std::size_t budget : {std::size_t{0}, std::size_t{1}}) {  // one pass; a pass per draw
        raster::Renderer r({.threads = threads, .tile_size = tile, .geometry_budget = budget});
        CAPTURE(budget);
        raster::Image8 image;
        pbr::render_rgba8(scene, r, target, out, image);
        CAPTURE(threads);
        CAPTURE(tile);
        CHECK(image.width == reference.width);
        CHECK(image.height == reference.height);
        CHECK(image.rgba == reference.rgba);
      }
  }
}

namespace {

// Overlapping translucent triangles in one draw: lanes of a packet come from several
// triangles, some covering the same pixel, blended in submission order.
struct OverlapShader {
  struct Vertex {
    glm::vec4 position;
    glm::vec4 color;  // premultiplied
  };
  struct Varyings {
    glm::vec4 color;
  };
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.color = in.color;
    return in.position;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const Varyings& v = f.v;
    return {v.color.r * (1.0f + f.ddx.color.r), v.color.g, v.color.b + (f.front_facing ? 0.0f : 0.25f), v.color.a};
  }
};
struct OverlapPacketShader : OverlapShader {
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return {p.v[0] * (F(1.0f) + p.ddx[0]), p.v[1], p.v[2] + F(p.front_facing ? 0.0f : 0.25f), p.v[3]};
  }
};

}  // namespace

TEST_CASE("packets filled across overlapping triangles of one draw give the scalar bits (over, less-equal, both facings)") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> pos(-1.0f, 1.0f), unit(0.0f, 1.0f);
  std::vector<OverlapShader::Vertex> vertices;
  for (int i = 0; i < 3000; ++i) {  // small triangles, many on the same pixels
    const glm::vec2 c{pos(rng), pos(rng)};
    const float a = 0.2f + 0.6f * unit(rng);
    const glm::vec4 color{unit(rng) * a, unit(rng) * a, unit(rng) * a, a};
    const float z = pos(rng);
    for (int k = 0; k < 3; ++k)
      vertices.push_back({{c.x + 0.06f * pos(rng), c.y + 0.06f * pos(rng), z + 0.1f * pos(rng), 1.0f}, color});
  }
  for (const auto depth : {raster::DepthTest::Always, raster::DepthTest::LessEqual}) {
    raster::DrawState st;
    st.blend = raster::Blend::Over;
    st.depth_test = depth;
    raster::Target t(97, 61);
    auto draw = [&](auto shader, raster::Renderer& r) {
      r.begin_frame(t, raster::ClearValues{{0.1f, 0.1f, 0.1f, 1.0f}, 1.0f});
      r.draw(shader, std::span<const OverlapShader::Vertex>(vertices), st);
      r.end_frame();
      return std::pair{raster::hash_colors(t), raster::hash_depths(t)};
    };
    raster::Renderer scalar({.threads = 1, .tile_size = 64, .lanes = 1});
    const auto reference = draw(OverlapShader{}, scalar);
    for (const int lanes : {1, 4, 8, 16})
      for (const unsigned threads : {1u, 2u})
        for (const bool dispatch : {false, true}) {
        raster::Renderer r({.threads = threads, .tile_size = 16, .lanes = lanes, .dispatch = dispatch});
        CAPTURE(dispatch);
        CAPTURE(lanes);
        CAPTURE(threads);
        CHECK(draw(OverlapPacketShader{}, r) == reference);
      }
  }
}

namespace {

// A packet shader with per-draw uniforms (raster/shader.h, packet_uniforms): counts how
// often the renderer builds them and colours by them, so a renderer that skipped them, or
// built them per packet, fails below.
struct UniformsShader {
  using Vertex = glm::vec4;  // clip-space position
  struct Varyings {
    float x;
  };
  glm::vec2 tint{0.25f, 0.75f};
  std::atomic<int>* builds = nullptr;

  template <class F>
  struct Uniforms {
    F r, g;
  };
  template <class F>
  Uniforms<F> packet_uniforms() const {
    builds->fetch_add(1, std::memory_order_relaxed);
    return {F(tint.x), F(tint.y * 2.0f)};
  }
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.x = in.x;
    return in;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {tint.x * f.v.x, tint.y * 2.0f, 0.0f, 1.0f}; }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p, const Uniforms<F>& u) const {
    return {u.r * p.v[0], u.g, F(0.0f), F(1.0f)};
  }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return fragment_packet(p, packet_uniforms<F>());
  }
};

}  // namespace

TEST_CASE("a packet shader's uniforms are built once per draw and tile and shade every packet of it") {
  static_assert(raster::PacketUniformsFor<UniformsShader, float>);
  static_assert(raster::PacketUniformsFor<UniformsShader, softpbr::simd::Vec<4>>);
  const std::vector<glm::vec4> quad{{-1, -1, 0, 1}, {1, -1, 0, 1}, {1, 1, 0, 1},
                                    {-1, -1, 0, 1}, {1, 1, 0, 1},  {-1, 1, 0, 1}};
  constexpr int kWidth = 128, kHeight = 96, kTile = 32;
  constexpr int kTiles = (kWidth / kTile) * (kHeight / kTile);
  const auto render = [&](raster::Renderer& r, int draws, std::atomic<int>& builds) {
    raster::Target t(kWidth, kHeight);
    r.begin_frame(t, raster::ClearValues{{0, 0, 0, 0}, 1.0f});
    UniformsShader s;
    s.builds = &builds;
    for (int d = 0; d < draws; ++d)
      r.draw(s, std::span<const glm::vec4>(quad), raster::DrawState{.depth_test = raster::DepthTest::Always});
    r.end_frame();
    return t;
  };
  std::atomic<int> scalar_builds{0};
  raster::Renderer scalar({.threads = 1, .tile_size = kTile, .lanes = 1});
  const raster::Target reference = render(scalar, 1, scalar_builds);
  // The colour is the uniforms' (g = 2 · 0.75) and r = 0.25 x at every pixel.
  CHECK(reference.colors()[0].g == 1.5f);
  CHECK(reference.colors()[kWidth * kHeight - 1].r == doctest::Approx(0.25 * (2.0 * (kWidth - 0.5) / kWidth - 1.0)));
  for (const int lanes : {1, 4, 8, 16})
    for (const unsigned threads : {1u, 2u}) {
      CAPTURE(lanes);
      CAPTURE(threads);
      std::atomic<int> builds{0};
      raster::Renderer r({.threads = threads, .tile_size = kTile, .lanes = lanes});
      const raster::Target t = render(r, 3, builds);
      CHECK(raster::hash_colors(t) == raster::hash_colors(reference));
      // Once per draw and tile: 3 × 12, against 3 × 128 · 96 / lanes packets.
      CHECK(builds.load() == 3 * kTiles);
    }
}
