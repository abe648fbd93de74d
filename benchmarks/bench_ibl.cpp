// bench_ibl — where the IBL gallery's background pass spends its time (issue 15), by
// shaders written here that change one thing each against pbr's BackgroundShader, drawn
// by the same raster::Renderer (the dispatched AVX-512 / AVX2 kernels, as for any shader)
// into a 1920×1080 target with the gallery's camera, the built-in studio and the tone map
// fused per tile (as pbr::render_rgba8):
//
//   pbr              pbr::render_rgba8() of the gallery_ibl_bgonly scene (the reference)
//   copy             a copy of pbr/src/scene.cpp's BackgroundShader: env_radiance() as
//                    environment.h has it (a loop over the 6 levels, each weight compared
//                    and any() tested per packet)
//   uniform_lod      the same lookups with the level weights computed once per draw from
//                    the (uniform) roughness in float, the same operations as a lane does:
//                    the same bits (checked), no per-packet compares over 6 levels
//   no_lookup        uniform_lod without the texture lookup: the octahedral coordinates
//                    and direction as the colour (what the lookup itself costs)
//   constant         a constant colour (the kernel, the target writes and the tone map)
//
// bench_ibl [--benchmark_filter=uniform] [--benchmark_min_time=1]; 1 and 2 threads.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "scenes.h"
#include "softpbr/dmath/dmath.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/renderer.h"

namespace bench = softpbr::bench;
namespace dmath = softpbr::dmath;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace simd = softpbr::simd;

namespace {

enum class Mode { Copy, UniformLod, NoLookup, Constant };

template <class F>
pbr::EnvVec3<F> radiance_uniform(const pbr::PreparedEnvironment& e, const pbr::EnvVec3<F>& d, float roughness) {
  // env_radiance's per-lane arithmetic in float: every lane holds the same roughness.
  const float lod = std::min(std::max(roughness, 0.0f), 1.0f) * static_cast<float>(pbr::Environment::kLevels - 1);
  const F zero(0.0f);
  F r = zero, g = zero, b = zero;
  for (int l = 0; l < pbr::Environment::kLevels; ++l) {
    const float dl = lod - static_cast<float>(l);
    const float m = dl < 0.0f - dl ? 0.0f - dl : dl;  // simd::max(dl, 0 − dl)
    const float one_minus = 1.0f - m;
    const float w = one_minus < 0.0f ? 0.0f : one_minus;  // simd::max(1 − m, 0)
    if (!(w > 0.0f)) continue;
    F u, v;
    pbr::env_octahedral(d, e.map->level_size(l), u, v);
    const raster::Color<F> c = raster::sample_lod(e.map->level(l), pbr::Environment::level_sampler(), u, v, zero);
    const F wl(w);
    r = r + wl * c.r;
    g = g + wl * c.g;
    b = b + wl * c.b;
  }
  const F k(e.intensity);
  return {r * k, g * k, b * k};
}

template <Mode kMode>
struct Background {
  struct Vertex {
    glm::vec4 clip;
    glm::vec3 direction;
  };
  struct Varyings {
    glm::vec3 direction;
  };
  static constexpr bool kUsesDerivatives = false;

  const pbr::PreparedEnvironment* environment = nullptr;
  float roughness = 0.0f;

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.direction = in.direction;
    return in.clip;
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const raster::Color<float> c = color<float>(f.v.direction.x, f.v.direction.y, f.v.direction.z);
    return {c.r, c.g, c.b, c.a};
  }
  template <class F>
  raster::Color<F> fragment_packet(const raster::FragmentPacket<F, Varyings>& p) const {
    return color<F>(p.v[0], p.v[1], p.v[2]);
  }

 private:
  template <class F>
  raster::Color<F> color(F x, F y, F z) const {
    const pbr::EnvVec3<F> d = pbr::to_environment(*environment, x, y, z);
    if constexpr (kMode == Mode::Copy) {
      const pbr::EnvVec3<F> c = pbr::env_radiance(*environment, d, F(roughness));
      return {c.x, c.y, c.z, F(1.0f)};
    } else if constexpr (kMode == Mode::UniformLod) {
      const pbr::EnvVec3<F> c = radiance_uniform(*environment, d, roughness);
      return {c.x, c.y, c.z, F(1.0f)};
    } else if constexpr (kMode == Mode::NoLookup) {
      F u, v;
      pbr::env_octahedral(d, environment->map->level_size(0), u, v);
      return {u, v, d.y, F(1.0f)};
    } else {
      return {F(0.2f), F(0.2f), F(0.2f), F(1.0f)};
    }
  }
};

// pbr/src/scene.cpp's background_triangle(), with the same dmath.
template <class V>
std::array<V, 3> background_triangle(const pbr::Camera& camera, float aspect) {
  const glm::mat3 to_world = glm::transpose(glm::mat3(camera.view()));
  const double half = 0.5 * static_cast<double>(camera.fovy);
  const auto ty = static_cast<float>(dmath::sin(half) / dmath::cos(half));
  const float tx = ty * aspect;
  std::array<V, 3> v{};
  const float corners[3][2] = {{-1.0f, -1.0f}, {3.0f, -1.0f}, {-1.0f, 3.0f}};
  for (int i = 0; i < 3; ++i) {
    v[static_cast<std::size_t>(i)].clip = glm::vec4(corners[i][0], corners[i][1], 0.0f, 1.0f);
    v[static_cast<std::size_t>(i)].direction = to_world * glm::vec3(corners[i][0] * tx, corners[i][1] * ty, -1.0f);
  }
  return v;
}

const bench::BenchScene& scene() {
  static const bench::BenchScene s = [] {
    for (bench::BenchScene& v : bench::ibl_gallery_variants(1920, 1080))
      if (v.name == "gallery_ibl_bgonly_1080p") return v;
    throw std::logic_error("no gallery_ibl_bgonly_1080p");
  }();
  return s;
}

template <Mode kMode>
void draw_frame(raster::Renderer& renderer, raster::Target& target, const pbr::PreparedEnvironment& env,
                const pbr::ToneMapper& mapper, raster::Image8& image) {
  const bench::BenchScene& s = scene();
  Background<kMode> bg;
  bg.environment = &env;
  bg.roughness = 0.0f;  // BackgroundMode::Environment
  using V = typename Background<kMode>::Vertex;
  const auto tri = background_triangle<V>(s.scene.camera, static_cast<float>(s.width) / static_cast<float>(s.height));
  raster::DrawState state;
  state.depth_test = raster::DepthTest::Always;
  state.depth_write = false;
  renderer.begin_frame(target, raster::ClearValues{s.scene.background, 1.0f});
  renderer.draw(bg, std::span<const V>(tri), state);
  renderer.end_frame([&](const raster::TileRect& r, bool only_clear, const raster::TargetPixels&) {
    if (only_clear) mapper.encode_uniform(s.scene.background, r.x0, r.y0, r.x1, r.y1, image);
    else mapper.encode(target, r.x0, r.y0, r.x1, r.y1, image);
  });
}

void run(benchmark::State& state, int mode) {
  const bench::BenchScene& s = scene();
  raster::Renderer renderer({.threads = static_cast<unsigned>(state.range(0)), .tile_size = 64});
  raster::Target target(s.width, s.height);
  raster::Image8 image, reference;
  pbr::render_rgba8(s.scene, renderer, target, s.output, reference);
  const pbr::PreparedEnvironment env = pbr::prepare_environment(s.scene.environment);
  const pbr::ToneMapper mapper(s.output);
  image.width = s.width;
  image.height = s.height;
  image.rgba.assign(reference.rgba.size(), 0);
  auto frame = [&] {
    switch (mode) {
      case 0: pbr::render_rgba8(s.scene, renderer, target, s.output, image); break;
      case 1: draw_frame<Mode::Copy>(renderer, target, env, mapper, image); break;
      case 2: draw_frame<Mode::UniformLod>(renderer, target, env, mapper, image); break;
      case 3: draw_frame<Mode::NoLookup>(renderer, target, env, mapper, image); break;
      default: draw_frame<Mode::Constant>(renderer, target, env, mapper, image); break;
    }
  };
  frame();
  if (mode <= 2 && image.rgba != reference.rgba) {
    state.SkipWithError("the image differs from pbr::render_rgba8's");
    return;
  }
  for (auto _ : state) frame();
  state.counters["same_bits"] = mode <= 2 ? 1.0 : 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const char* names[] = {"background/pbr", "background/copy", "background/uniform_lod", "background/no_lookup",
                         "background/constant"};
  for (int mode = 0; mode < 5; ++mode)
    benchmark::RegisterBenchmark(names[mode], run, mode)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->UseRealTime()
        ->MeasureProcessCPUTime()
        ->Unit(benchmark::kMillisecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
