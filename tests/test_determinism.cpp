// Determinism (docs/design.md, "Determinism"): the same scene gives the same colour and depth bits with any
// thread count, tile size and packet lane width, frame after frame, and with two
// renderers at once.
#include <atomic>
#include <cstdint>
#include <cstring>
#include <random>
#include <thread>
#include <utility>
#include <vector>

#include <doctest/doctest.h>
#include <glm/glm.hpp>

#include "raster_helpers.h"
#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/simd/simd.h"

namespace {

namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;

constexpr int kW = 250, kH = 166;  // a multiple of no tile size: edge tiles are partial

// Lit, checkered by uv with a filter width from the uv derivatives: 8 varyings, and every
// pixel depends on its quad's neighbours.
struct TexturedShader {
  using Vertex = pbr::MeshVertex;
  struct Varyings {
    glm::vec3 normal;
    glm::vec2 uv;
    glm::vec3 world;
  };
  glm::mat4 view_projection;
  glm::vec3 offset;
  glm::vec3 light;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.normal = in.normal;
    out.uv = in.uv * 8.0f;
    out.world = in.position + offset;
    return view_projection * glm::vec4(out.world, 1.0f);
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const glm::vec2 width = glm::abs(f.ddx.uv) + glm::abs(f.ddy.uv);
    const glm::vec2 cell = glm::fract(f.v.uv) - 0.5f;
    const float checker = (cell.x * cell.y > 0.0f ? 1.0f : 0.2f) / (1.0f + width.x + width.y);
    const glm::vec3 n = glm::normalize(f.v.normal);
    const glm::vec3 to_light = glm::normalize(light - f.v.world);
    const float lambert = glm::max(glm::dot(n, to_light), 0.0f);
    return {checker * lambert, lambert, f.front_facing ? 0.25f : 0.75f, 1.0f};
  }
};

// Random world-space triangles with a colour each, drawn translucent.
struct TintShader {
  struct Vertex {
    glm::vec3 position;
    glm::vec4 color;  // premultiplied
  };
  struct Varyings {
    glm::vec4 color;
    float depth_tint;
  };
  glm::mat4 view_projection;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.color = in.color;
    const glm::vec4 clip = view_projection * glm::vec4(in.position, 1.0f);
    out.depth_tint = clip.w;
    return clip;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const float fade = 1.0f / (1.0f + 0.1f * f.v.depth_tint + glm::abs(f.ddx.depth_tint));
    return f.v.color * fade;
  }
};

// The same lit shading written once against a lane type F (float or simd::Vec<N>): the
// scalar shader calls it with float, the packet shader with the renderer's lane width.
template <class F>
raster::Color<F> lit(const F* v, const F* ddx, const F* ddy, glm::vec3 light, bool front) {
  using softpbr::simd::select;
  auto abs = [](F x) { return select(x < F(0.0f), -x, x); };
  // v: normal (3), uv (2), world position (3).
  const F width = abs(ddx[3]) + abs(ddy[3]) + abs(ddx[4]) + abs(ddy[4]);
  const F pattern = v[3] * v[4] / (F(1.0f) + v[3] * v[3] + width);
  const F n_len = softpbr::simd::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const F lx = F(light.x) - v[5], ly = F(light.y) - v[6], lz = F(light.z) - v[7];
  const F l_len = softpbr::simd::sqrt(lx * lx + ly * ly + lz * lz);
  const F cosine = (v[0] * lx + v[1] * ly + v[2] * lz) / (n_len * l_len);
  const F lambert = softpbr::simd::max(cosine, F(0.0f));
  return {pattern * lambert, lambert, F(front ? 0.25f : 0.75f), F(1.0f)};
}

struct LitShader {
  using Vertex = pbr::MeshVertex;
  using Varyings = TexturedShader::Varyings;
  glm::mat4 view_projection;
  glm::vec3 offset;
  glm::vec3 light;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    return TexturedShader{view_projection, offset, light}.vertex(in, out);
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const auto v = raster::varyings_to_floats(f.v), dx = raster::varyings_to_floats(f.ddx),
               dy = raster::varyings_to_floats(f.ddy);
    const raster::Color<float> c = lit<float>(v.data(), dx.data(), dy.data(), light, f.front_facing);
    return {c.r, c.g, c.b, c.a};
  }
};

// LitShader plus fragment_packet(): shaded in packets of RendererOptions::lanes pixels.
struct LitPacketShader : LitShader {
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return lit<F>(p.v, p.ddx, p.ddy, light, p.front_facing);
  }
};
static_assert(raster::PacketShaderFor<LitPacketShader, float> &&
              raster::PacketShaderFor<LitPacketShader, softpbr::simd::Vec<4>>);
static_assert(!raster::PacketShaderFor<LitShader, float>);

TEST_CASE("lanes = 0 runs the widest kernel the CPU has when dispatching, the build's width otherwise") {
  const raster::Renderer plain({.threads = 1, .dispatch = false});
  CHECK(plain.isa() == softpbr::simd::Isa::Baseline);
  CHECK(plain.lanes() == softpbr::simd::kNativeWidth);
  const raster::Renderer dispatched({.threads = 1});
  CHECK(dispatched.isa() == softpbr::simd::cpu_isa());
  const int expected = softpbr::simd::cpu_isa() == softpbr::simd::Isa::Avx512 ? 16
                       : softpbr::simd::cpu_isa() == softpbr::simd::Isa::Avx2 ? 8
                                                                               : softpbr::simd::kNativeWidth;
  CHECK(dispatched.lanes() == expected);
  MESSAGE("this CPU's packet kernels: " << dispatched.lanes() << " lanes, isa " << static_cast<int>(dispatched.isa()));
}

TEST_CASE("a request for more lanes than a target has runs the widest copy compiled that the CPU runs") {
  namespace d = raster::detail;
  using softpbr::simd::Isa;
  constexpr int kWide = d::kBaselineMaxWidth;  // 4, or the build's native 8 or 16
  CHECK(kWide == (softpbr::simd::kNativeWidth > 4 ? softpbr::simd::kNativeWidth : 4));
  // Without dispatch: the baseline copy, at most kWide lanes (wider ones are not compiled).
  CHECK((d::tile_kernel<16, 1, LitPacketShader>(Isa::Baseline) == &d::baseline::raster_tile<kWide, 1, LitPacketShader>));
  CHECK((d::tile_kernel<8, 4, LitPacketShader>(Isa::Baseline) ==
        &d::baseline::raster_tile<(kWide < 8 ? kWide : 8), 4, LitPacketShader>));
  CHECK((d::tile_kernel<4, 8, LitPacketShader>(Isa::Baseline) == &d::baseline::raster_tile<4, 8, LitPacketShader>));
  CHECK((d::tile_kernel<1, 1, LitPacketShader>(Isa::Avx512) == &d::baseline::raster_tile<1, 1, LitPacketShader>));
#if SOFTPBR_SIMD_X86_TARGETS
  // With them: 16 lanes on AVX-512, 8 on AVX2 (for a request of 16 too).
  CHECK((d::tile_kernel<16, 1, LitPacketShader>(Isa::Avx512) == &d::avx512::raster_tile<16, 1, LitPacketShader>));
  CHECK((d::tile_kernel<16, 4, LitPacketShader>(Isa::Avx2) == &d::avx2::raster_tile<8, 4, LitPacketShader>));
  CHECK((d::tile_kernel<8, 1, LitPacketShader>(Isa::Avx512) == &d::avx2::raster_tile<8, 1, LitPacketShader>));
  CHECK((d::tile_kernel<0, 1, LitShader>(Isa::Avx2) == &d::avx2::raster_tile<0, 1, LitShader>));
#endif
}

struct Scene {
  glm::mat4 view_projection;
  pbr::Mesh sphere;
  std::vector<glm::vec3> offsets;
  std::vector<TintShader::Vertex> opaque, translucent;
  int near_crossing = 0;  // random triangles the near plane cuts
};

Scene make_scene() {
  Scene s;
  const glm::vec3 eye{0.0f, 0.4f, 3.0f};
  const glm::mat4 view = pbr::look_at(eye, {0, 0, 0}, {0, 1, 0});
  s.view_projection = pbr::perspective(0.9f, static_cast<float>(kW) / kH, 0.1f, 50.0f) * view;
  s.sphere = pbr::uv_sphere(0.6f, 40, 20);
  // The last sphere straddles the near plane.
  s.offsets = {{-0.9f, 0.0f, 0.0f}, {0.8f, 0.3f, -1.0f}, {0.0f, -0.5f, 0.8f}, {0.3f, 0.2f, 2.75f}};
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> pos(-2.5f, 2.5f), depth(-4.0f, 4.0f), spread(-0.6f, 0.6f), unit(0.0f, 1.0f);
  for (int i = 0; i < 1500; ++i) {
    const glm::vec3 c{pos(rng), pos(rng), depth(rng)};
    bool crosses = false;
    const float a = 0.3f + 0.6f * unit(rng);
    const glm::vec4 color{unit(rng) * a, unit(rng) * a, unit(rng) * a, a};
    auto& list = i % 3 == 0 ? s.translucent : s.opaque;
    float zs[3];
    for (int k = 0; k < 3; ++k) {
      const glm::vec3 p = c + glm::vec3(spread(rng), spread(rng), spread(rng)) * (i % 10 == 0 ? 4.0f : 1.0f);
      zs[k] = (view * glm::vec4(p, 1.0f)).z;
      list.push_back({p, color});
    }
    for (int k = 0; k < 3; ++k) crosses |= (zs[k] > -0.1f) != (zs[(k + 1) % 3] > -0.1f);
    s.near_crossing += crosses;
  }
  return s;
}

// Several draws with different shader types and states: spheres culled, opaque random
// triangles, translucent ones blended over without depth writes.
void draw_scene(const Scene& s, raster::Renderer& r, raster::Target& t) {
  t.clear({0.1f, 0.1f, 0.1f, 1.0f});
  r.begin_frame(t);
  raster::DrawState culled;
  culled.cull = raster::Cull::Back;
  for (std::size_t i = 0; i < s.offsets.size(); ++i) {
    raster::DrawState st = i == 2 ? raster::DrawState{} : culled;  // one sphere draws its inside too
    r.draw(TexturedShader{s.view_projection, s.offsets[i], {2, 3, 4}}, std::span<const pbr::MeshVertex>(s.sphere.vertices),
           s.sphere.indices, st);
  }
  raster::DrawState lequal;
  lequal.depth_test = raster::DepthTest::LessEqual;
  r.draw(TintShader{s.view_projection}, std::span<const TintShader::Vertex>(s.opaque), lequal);
  raster::DrawState over;
  over.blend = raster::Blend::Over;
  over.depth_write = false;
  r.draw(TintShader{s.view_projection}, std::span<const TintShader::Vertex>(s.translucent), over);
  r.end_frame();
}

// Only the spheres: a different frame for a reused renderer.
void draw_spheres(const Scene& s, raster::Renderer& r, raster::Target& t) {
  t.clear({0, 0, 0, 1});
  r.begin_frame(t);
  for (const glm::vec3& o : s.offsets)
    r.draw(TexturedShader{s.view_projection, o * 0.5f, {-2, 3, 1}}, std::span<const pbr::MeshVertex>(s.sphere.vertices),
           s.sphere.indices);
  r.end_frame();
}

// Spheres through the lane-typed shader, scalar or in packets, blended over the random
// triangles.
template <class S>
void draw_lit(const Scene& s, raster::Renderer& r, raster::Target& t) {
  t.clear({0, 0, 0, 1});
  r.begin_frame(t);
  r.draw(TintShader{s.view_projection}, std::span<const TintShader::Vertex>(s.opaque));
  raster::DrawState over;
  over.blend = raster::Blend::Over;
  for (const glm::vec3& o : s.offsets) {
    S shader{};
    static_cast<LitShader&>(shader) = LitShader{s.view_projection, o, {1, 2, 3}};
    r.draw(shader, std::span<const pbr::MeshVertex>(s.sphere.vertices), s.sphere.indices, over);
  }
  r.end_frame();
}

using Hashes = std::pair<std::uint64_t, std::uint64_t>;
Hashes hashes(const raster::Target& t) { return {raster::hash_colors(t), raster::hash_depths(t)}; }

Hashes render_once(const Scene& s, unsigned threads, int tile) {
  raster::Renderer r({.threads = threads, .tile_size = tile});
  raster::Target t(kW, kH);
  draw_scene(s, r, t);
  return hashes(t);
}

}  // namespace

TEST_CASE("the scene is not trivial: thousands of triangles, some cut by the near plane, most pixels drawn") {
  const Scene s = make_scene();
  CHECK(s.sphere.triangle_count() * s.offsets.size() + (s.opaque.size() + s.translucent.size()) / 3 > 5000);
  CHECK(s.near_crossing > 20);
  raster::Renderer r({.threads = 2, .tile_size = 64});
  raster::Target t(kW, kH);
  draw_scene(s, r, t);
  int drawn = 0;
  for (const glm::vec4& c : t.colors()) drawn += c != glm::vec4(0.1f, 0.1f, 0.1f, 1.0f);
  CHECK(drawn > kW * kH / 2);
}

TEST_CASE("colour and depth hashes are the same for 1, 2, 3 and 8 threads and every tile size") {
  const Scene s = make_scene();
  const Hashes reference = render_once(s, 1, 64);
  for (const unsigned threads : {1u, 2u, 3u, 8u})
    for (const int tile : {8, 16, 24, 32, 64, 128, 256}) {
      const Hashes h = render_once(s, threads, tile);
      CAPTURE(threads);
      CAPTURE(tile);
      CHECK(h.first == reference.first);
      CHECK(h.second == reference.second);
    }
}

TEST_CASE("a reused renderer gives the same bits frame after frame, whatever it drew in between") {
  const Scene s = make_scene();
  const Hashes reference = render_once(s, 1, 32);
  for (const unsigned threads : {1u, 3u}) {
    raster::Renderer r({.threads = threads, .tile_size = 32});
    raster::Target t(kW, kH), other(kW, kH);
    Hashes spheres{};
    for (int frame = 0; frame < 4; ++frame) {
      draw_scene(s, r, t);
      CAPTURE(frame);
      CHECK(hashes(t) == reference);
      draw_spheres(s, r, other);
      if (frame == 0) spheres = hashes(other);
      CHECK(hashes(other) == spheres);
    }
    CHECK(spheres != reference);  // the frame in between really was different
  }
}

TEST_CASE("two renderers drawing at the same time in two threads give the reference bits") {
  const Scene s = make_scene();
  const Hashes reference = render_once(s, 1, 64);
  std::vector<Hashes> results[2];
  bool failed[2] = {false, false};
  auto work = [&](int which) {
    try {
      raster::Renderer r({.threads = 2, .tile_size = which == 0 ? 16 : 128});
      raster::Target t(kW, kH);
      for (int frame = 0; frame < 3; ++frame) {
        draw_scene(s, r, t);
        results[which].push_back(hashes(t));
      }
    } catch (...) {
      failed[which] = true;
    }
  };
  std::thread a(work, 0), b(work, 1);
  a.join();
  b.join();
  CHECK_FALSE(failed[0]);
  CHECK_FALSE(failed[1]);
  for (const auto& list : results) {
    CHECK(list.size() == 3);
    for (const Hashes& h : list) CHECK(h == reference);
  }
}

TEST_CASE("packet shading gives the scalar shader's bits at every lane width, thread count and tile size") {
  const Scene s = make_scene();
  raster::Target t(kW, kH);
  raster::Renderer scalar_renderer({.threads = 1, .tile_size = 64, .lanes = 1});
  draw_lit<LitShader>(s, scalar_renderer, t);
  const Hashes reference = hashes(t);
  int covered = 0;
  for (const glm::vec4& c : t.colors()) covered += c.g > 0.0f;
  CHECK(covered > kW * kH / 10);
  for (const int lanes : {0, 1, 4, 8, 16})
    for (const unsigned threads : {1u, 3u})
      for (const int tile : {16, 64})
        for (const bool dispatch : {false, true}) {  // the build's code, then AVX2 / AVX-512 kernels
        raster::Renderer r({.threads = threads, .tile_size = tile, .lanes = lanes, .dispatch = dispatch});
        CAPTURE(dispatch);
        CAPTURE(lanes);
        CAPTURE(threads);
        CAPTURE(tile);
        draw_lit<LitPacketShader>(s, r, t);
        CHECK(hashes(t) == reference);
        draw_lit<LitShader>(s, r, t);  // lanes do not matter to a scalar shader
        CHECK(hashes(t) == reference);
      }
}

TEST_CASE("rasterizing in several passes (a small geometry budget) gives the one-pass bits") {
  const Scene s = make_scene();
  for (const unsigned threads : {1u, 3u}) {
    raster::Renderer one_pass({.threads = threads, .tile_size = 32, .geometry_budget = 0});
    raster::Target t(kW, kH);
    draw_scene(s, one_pass, t);
    const Hashes reference = hashes(t);
    for (const std::size_t budget : {std::size_t{1}, std::size_t{200} << 10}) {  // after every draw; now and then
      raster::Renderer r({.threads = threads, .tile_size = 32, .geometry_budget = budget});
      CAPTURE(threads);
      CAPTURE(budget);
      draw_scene(s, r, t);
      CHECK(hashes(t) == reference);
      draw_lit<LitPacketShader>(s, r, t);  // and a second frame on the same renderer
      raster::Renderer fresh({.threads = threads, .tile_size = 32, .geometry_budget = 0});
      raster::Target u(kW, kH);
      draw_lit<LitPacketShader>(s, fresh, u);
      CHECK(hashes(t) == hashes(u));
    }
  }
}

TEST_CASE("Renderer::flush mid-frame gives the one-pass bits, and its callback sees every tile once") {
  // draw_scene's draws with a flush after the spheres (as pbr::render's transmission pass
  // flushes after the opaque objects), on 1 and 4 samples, kept and transient targets.
  const Scene s = make_scene();
  const auto draw = [&](raster::Renderer& r, raster::Target& t, bool flush, std::size_t* tiles) {
    r.begin_frame(t, raster::ClearValues{{0.1f, 0.1f, 0.1f, 1.0f}, 1.0f});
    raster::DrawState culled;
    culled.cull = raster::Cull::Back;
    for (const glm::vec3& o : s.offsets)
      r.draw(TexturedShader{s.view_projection, o, {2, 3, 4}}, std::span<const pbr::MeshVertex>(s.sphere.vertices),
             s.sphere.indices, culled);
    std::atomic<std::size_t> seen{0};
    if (flush) r.flush([&](const raster::TileRect&, bool, const raster::TargetPixels&) { seen.fetch_add(1); });
    raster::DrawState over;
    over.blend = raster::Blend::Over;
    over.depth_write = false;
    r.draw(TintShader{s.view_projection}, std::span<const TintShader::Vertex>(s.translucent), over);
    // The image as the command keeps it: resolved per tile by the callback.
    std::vector<glm::vec4> image(static_cast<std::size_t>(kW) * kH);
    r.end_frame([&](const raster::TileRect& rect, bool, const raster::TargetPixels& px) {
      raster::resolve_box(px, rect.x0, rect.y0, rect.x1, rect.y1,
                          image.data() + static_cast<std::size_t>(rect.y0) * kW + rect.x0, kW);
    });
    if (tiles != nullptr) *tiles = seen.load();
    return image;
  };
  const auto same = [](const std::vector<glm::vec4>& a, const std::vector<glm::vec4>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec4)) == 0;
  };
  for (const int samples : {1, 4}) {
    for (const unsigned threads : {1u, 3u}) {
      CAPTURE(samples);
      CAPTURE(threads);
      raster::Renderer r({.threads = threads, .tile_size = 32});
      raster::Target kept(kW, kH, samples, &r.pool());
      const std::vector<glm::vec4> reference = draw(r, kept, false, nullptr);
      std::size_t tiles = 0;
      CHECK(same(draw(r, kept, true, &tiles), reference));
      CHECK(tiles == static_cast<std::size_t>((kW + 31) / 32) * static_cast<std::size_t>((kH + 31) / 32));
      raster::Target transient(kW, kH, samples, &r.pool(), raster::SampleStorage::Transient);
      CHECK(same(draw(r, transient, true, nullptr), reference));
    }
  }
}
