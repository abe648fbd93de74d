// bench_raster — how fast softpbr::raster draws frames at 1920×1080 (Google Benchmark).
//
//   bench_raster --benchmark_min_time=0.5 [--benchmark_filter=Fill]
//
// Three fixed scenes, each at 1 and 2 renderer threads (RendererOptions::threads, the
// argument "threads:N"). The 1-thread run is the baseline: after the table a summary
// prints the 2-thread/1-thread speed-up measured in the same run.
//   BM_SmallTriangles  triangles/s: 259,200 triangles of 8 pixels each, one draw
//   BM_Fill            shaded pixels/s: 8 layers of full-screen quads, every layer shaded
//   BM_LitSpheres      ms/frame of the scene of examples/spheres.cpp, at 1920×1080
//   BM_TextureLookups  lookups/s of Texture::sample_batch alone, 16 at a time in 4×4 pixel
//                      blocks as a 16-lane shader asks (RGB of a 2048² sRGB texture,
//                      trilinear, repeat): "aniso:1" at λ ≈ 1.75 (two levels read, as
//                      bench_scenes' fill8x_tex), "aniso:16" with 8 probes along u at
//                      λ ≈ 0.58 (as fill8x_aniso16). One thread; where the textured
//                      scenes' lookup time goes without the rest of the frame.
//
// One iteration is one frame: begin_frame() with a clear (the renderer clears each tile in
// its parallel pass), the draws, end_frame(). The renderer, target and meshes are built
// and one warm-up frame is drawn outside the timed loop. "Time" is wall-clock
// (UseRealTime) and "CPU" is the whole process's CPU time (MeasureProcessCPUTime), so
// CPU/Time says how many threads were busy on average.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "softpbr/pbr/camera.h"
#include "softpbr/pbr/mesh.h"
#include "softpbr/raster/raster.h"
#include "softpbr/raster/texture.h"

namespace raster = softpbr::raster;
namespace pbr = softpbr::pbr;
namespace image = softpbr::image;

namespace {

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;
const raster::ClearValues kClear{{0.02f, 0.02f, 0.025f, 1.0f}, 1.0f};

// Pixels whose depth was written (the clear leaves 1.0 and every scene draws nearer).
std::size_t covered_pixels(const raster::Target& target) {
  const auto depths = target.depths();
  return static_cast<std::size_t>(std::count_if(depths.begin(), depths.end(), [](float d) { return d < 1.0f; }));
}

// Draws one frame: begin_frame with the clear, draw_all(renderer), end_frame.
template <class DrawAll>
void frame(raster::Renderer& renderer, raster::Target& target, const DrawAll& draw_all) {
  renderer.begin_frame(target, kClear);
  draw_all(renderer);
  renderer.end_frame();
}

// Draws frames while the benchmark runs, then sets the counters from the wall time of the
// loop: "ms/frame", "Mtri/s" (submitted triangles, when `triangles` > 0) and "Mpix/s"
// (shaded pixels). items_per_second counts `items` per frame. The counters are plain
// numbers (not Google Benchmark rates) so the console prints them without units appended.
template <class DrawAll>
void run_frames(benchmark::State& state, raster::Renderer& renderer, raster::Target& target, const DrawAll& draw_all,
                double items, double triangles, double shaded_pixels) {
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) frame(renderer, target, draw_all);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double frames = static_cast<double>(state.iterations());
  state.SetItemsProcessed(static_cast<std::int64_t>(frames * items));
  state.counters["ms/frame"] = 1e3 * seconds / frames;
  if (triangles > 0) state.counters["Mtri/s"] = 1e-6 * triangles * frames / seconds;
  state.counters["Mpix/s"] = 1e-6 * shaded_pixels * frames / seconds;
}

raster::Renderer make_renderer(const benchmark::State& state) {
  return raster::Renderer({.threads = static_cast<unsigned>(state.range(0)), .tile_size = 64});
}

// ---------------------------------------------------------------------------------------
// Small triangles: a screen-space grid of 4×4-pixel cells, each split into two triangles
// of 8 pixels, covering the 1920×1080 target exactly once: 480 × 270 × 2 = 259,200
// triangles over 481 × 271 shared vertices, one indexed draw, no culling. The shader
// passes a per-vertex colour through, so the time goes to the vertex stage, setup, binning
// and per-triangle raster overhead rather than to shading.

constexpr int kCell = 4;  // cell side in pixels: two triangles of 8 pixel centres each

struct GridVertex {
  glm::vec2 ndc;
  glm::vec3 color;
};

struct ColorShader {
  using Vertex = GridVertex;
  struct Varyings {
    glm::vec3 color;
  };
  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.color = in.color;
    return {in.ndc, 0.5f, 1.0f};
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const { return {f.v.color, 1.0f}; }
};

struct Grid {
  std::vector<GridVertex> vertices;
  std::vector<std::uint32_t> indices;
};

const Grid& small_triangle_grid() {
  static const Grid grid = [] {
    Grid g;
    const int cols = kWidth / kCell, rows = kHeight / kCell;
    for (int y = 0; y <= rows; ++y)
      for (int x = 0; x <= cols; ++x) {
        const glm::vec2 ndc{2.0f * static_cast<float>(x * kCell) / kWidth - 1.0f,
                            1.0f - 2.0f * static_cast<float>(y * kCell) / kHeight};
        g.vertices.push_back({ndc, {(x % 7) / 6.0f, (y % 5) / 4.0f, ((x + y) % 3) / 2.0f}});
      }
    const auto at = [cols](int x, int y) { return static_cast<std::uint32_t>(y * (cols + 1) + x); };
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < cols; ++x)
        for (const std::uint32_t i : {at(x, y), at(x, y + 1), at(x + 1, y + 1), at(x, y), at(x + 1, y + 1), at(x + 1, y)})
          g.indices.push_back(i);
    return g;
  }();
  return grid;
}

void BM_SmallTriangles(benchmark::State& state) {
  const Grid& grid = small_triangle_grid();
  raster::Renderer renderer = make_renderer(state);
  raster::Target target(kWidth, kHeight);
  const auto draw_all = [&](raster::Renderer& r) {
    r.draw(ColorShader{}, std::span<const GridVertex>(grid.vertices), grid.indices);
  };
  frame(renderer, target, draw_all);
  if (covered_pixels(target) != std::size_t{kWidth} * kHeight) {
    state.SkipWithError("the grid does not cover the target");
    return;
  }
  const double triangles = static_cast<double>(grid.indices.size() / 3);
  run_frames(state, renderer, target, draw_all, triangles, triangles, double{kWidth} * kHeight);
}

// ---------------------------------------------------------------------------------------
// Fill rate: 8 full-screen quads (2 triangles each, one draw per layer) drawn back to back
// with DepthTest::Always, so every layer shades every pixel: 8 × 1920 × 1080 = 16.6 M
// shaded pixels per frame over 16 triangles. The shader has 8 varyings (uv, normal, view
// vector) and does Blinn–Phong-like arithmetic per pixel: three normalisations, two dot
// products, a power by squaring and a stripe pattern — about 60 flops. Here
// items_per_second counts shaded pixels (the other benchmarks count triangles).

constexpr int kFillLayers = 8;

struct FillVertex {
  glm::vec3 position;  // clip space with w = 1
  glm::vec2 uv;
};

struct FillShader {
  using Vertex = FillVertex;
  struct Varyings {
    glm::vec2 uv;
    glm::vec3 normal;
    glm::vec3 view;
  };
  glm::vec3 tint;
  glm::vec3 to_light;  // normalised

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.uv = in.uv;
    out.normal = {in.uv.x - 0.5f, 0.5f - in.uv.y, 1.0f};  // a dome over the screen
    out.view = {-in.position.x, -in.position.y, 2.0f};
    return {in.position, 1.0f};
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const glm::vec3 n = glm::normalize(f.v.normal);
    const glm::vec3 v = glm::normalize(f.v.view);
    const glm::vec3 h = glm::normalize(to_light + v);
    const float NoL = glm::max(glm::dot(n, to_light), 0.0f);
    float spec = glm::max(glm::dot(n, h), 0.0f);
    spec *= spec;  // NoH^16 by four squarings
    spec *= spec;
    spec *= spec;
    spec *= spec;
    const float stripe = glm::fract(f.v.uv.x * 16.0f) < 0.5f ? 1.0f : 0.8f;
    return {tint * ((0.05f + 0.95f * NoL) * stripe) + glm::vec3(0.25f * spec), 1.0f};
  }
};

void BM_Fill(benchmark::State& state) {
  raster::Renderer renderer = make_renderer(state);
  raster::Target target(kWidth, kHeight);
  std::vector<FillVertex> layers[kFillLayers];
  for (int l = 0; l < kFillLayers; ++l) {
    const float z = 0.9f - 0.1f * static_cast<float>(l);  // nearer each layer (not that it matters here)
    layers[l] = {{{-1, -1, z}, {0, 1}}, {{1, -1, z}, {1, 1}}, {{1, 1, z}, {1, 0}}, {{-1, 1, z}, {0, 0}}};
  }
  const std::uint32_t quad[6] = {0, 1, 2, 0, 2, 3};
  raster::DrawState state_always;
  state_always.depth_test = raster::DepthTest::Always;
  const glm::vec3 to_light = glm::normalize(glm::vec3(-0.5f, 0.7f, 0.6f));
  const auto draw_all = [&](raster::Renderer& r) {
    for (int l = 0; l < kFillLayers; ++l) {
      const FillShader shader{{0.2f + 0.1f * l, 0.9f - 0.1f * l, 0.5f}, to_light};
      r.draw(shader, std::span<const FillVertex>(layers[l]), quad, state_always);
    }
  };
  frame(renderer, target, draw_all);
  if (covered_pixels(target) != std::size_t{kWidth} * kHeight) {
    state.SkipWithError("the quads do not cover the target");
    return;
  }
  const double pixels = double{kFillLayers} * kWidth * kHeight;
  run_frames(state, renderer, target, draw_all, pixels, 0.0, pixels);
}

// ---------------------------------------------------------------------------------------
// Lit spheres: examples/spheres.cpp at 1920×1080 — a 5×3 grid of uv_sphere(0.42, 64, 32)
// (15 draws of 3,968 triangles, 59,520 in all, half of them back faces culled), one
// directional light, Lambert + ambient, camera at z = 5.6 with a 40° field of view. The
// spheres do not overlap, so every covered pixel is shaded once: Mpix/s counts them.

struct LambertShader {
  using Vertex = pbr::MeshVertex;
  struct Varyings {
    glm::vec3 normal;  // world space
  };
  glm::mat4 view_projection;
  glm::vec3 offset;    // this sphere's position in the world
  glm::vec3 albedo;    // linear
  glm::vec3 to_light;  // normalised direction towards the light

  glm::vec4 vertex(const Vertex& in, Varyings& out) const {
    out.normal = in.normal;
    return view_projection * glm::vec4(in.position + offset, 1.0f);
  }
  glm::vec4 fragment(const raster::Fragment<Varyings>& f) const {
    const glm::vec3 n = glm::normalize(f.v.normal);
    const float diffuse = glm::max(glm::dot(n, to_light), 0.0f);
    return glm::vec4(albedo * (0.03f + 0.97f * diffuse), 1.0f);
  }
};

void BM_LitSpheres(benchmark::State& state) {
  raster::Renderer renderer = make_renderer(state);
  raster::Target target(kWidth, kHeight);
  const pbr::Mesh sphere = pbr::uv_sphere(0.42f, 64, 32);
  const glm::mat4 vp = pbr::perspective(static_cast<float>(softpbr::dmath::radians(40.0)),
                                        static_cast<float>(kWidth) / kHeight, 0.1f, 100.0f) *
                       pbr::look_at({0, 0, 5.6f}, {0, 0, 0}, {0, 1, 0});
  const glm::vec3 colors[3][5] = {
      {{0.80f, 0.10f, 0.10f}, {0.90f, 0.45f, 0.05f}, {0.85f, 0.80f, 0.10f}, {0.20f, 0.70f, 0.15f}, {0.10f, 0.50f, 0.80f}},
      {{0.30f, 0.20f, 0.80f}, {0.65f, 0.20f, 0.75f}, {0.90f, 0.90f, 0.90f}, {0.40f, 0.40f, 0.40f}, {0.10f, 0.10f, 0.10f}},
      {{1.00f, 0.71f, 0.29f}, {0.95f, 0.64f, 0.54f}, {0.95f, 0.93f, 0.88f}, {0.56f, 0.57f, 0.58f}, {0.91f, 0.92f, 0.92f}},
  };
  const glm::vec3 to_light = glm::normalize(glm::vec3(-0.5f, 0.7f, 0.6f));
  raster::DrawState back_culled;
  back_culled.cull = raster::Cull::Back;
  const auto draw_all = [&](raster::Renderer& r) {
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 5; ++col) {
        const LambertShader shader{vp, {(col - 2) * 1.0f, (1 - row) * 1.0f, 0.0f}, colors[row][col], to_light};
        r.draw(shader, std::span<const pbr::MeshVertex>(sphere.vertices), sphere.indices, back_culled);
      }
  };
  frame(renderer, target, draw_all);
  const std::size_t shaded = covered_pixels(target);
  const double triangles = 15.0 * static_cast<double>(sphere.triangle_count());
  run_frames(state, renderer, target, draw_all, triangles, triangles, static_cast<double>(shaded));
}

// ---------------------------------------------------------------------------------------
// Texture lookups alone: a 512×256 block of pixels per iteration, 16 lookups a call.

void BM_TextureLookups(benchmark::State& state) {
  constexpr int kSize = 2048, kBlockW = 512, kBlockH = 256;
  static const raster::Texture texture = [] {
    image::Image8 im;
    im.width = im.height = kSize;
    im.rgba.resize(std::size_t{kSize} * kSize * 4);
    std::uint32_t x = 12345;
    for (std::uint8_t& b : im.rgba) {
      x = x * 1664525u + 1013904223u;
      b = static_cast<std::uint8_t>(x >> 24);
    }
    return raster::Texture(im, raster::ColorSpace::Srgb);
  }();
  raster::Sampler sampler;
  sampler.max_anisotropy = static_cast<int>(state.range(0));
  const bool aniso = sampler.max_anisotropy > 1;
  // Texels per pixel along x and y.
  const float tx = aniso ? 12.0f : 3.36f, ty = aniso ? 1.6f : 3.36f;
  const float su = tx / kSize, sv = ty / kSize;
  alignas(64) float u[16], v[16], dudx[16], dvdx[16], dudy[16], dvdy[16], out[4][16];
  for (int i = 0; i < 16; ++i) dudx[i] = su, dvdx[i] = 0.0f, dudy[i] = 0.0f, dvdy[i] = sv;
  const raster::Texture::Batch batch{u, v, dudx, dvdx, dudy, dvdy, nullptr, out[0], out[1], out[2], out[3],
                                     raster::Texture::kRgb};
  float sum = 0.0f;
  for (auto _ : state) {
    for (int by = 0; by < kBlockH; by += 4)
      for (int bx = 0; bx < kBlockW; bx += 4) {
        for (int i = 0; i < 16; ++i) {
          u[i] = (static_cast<float>(bx + i % 4) + 0.5f) * su;
          v[i] = (static_cast<float>(by + i / 4) + 0.5f) * sv;
        }
        texture.sample_batch(sampler, 16, batch);
        sum += out[0][0];
      }
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations() * kBlockW * kBlockH);
}
BENCHMARK(BM_TextureLookups)->ArgName("aniso")->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond);

void configure(benchmark::internal::Benchmark* b) {
  b->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_SmallTriangles)->Apply(configure);
BENCHMARK(BM_Fill)->Apply(configure);
BENCHMARK(BM_LitSpheres)->Apply(configure);

// ---------------------------------------------------------------------------------------
// The default reporter (console, JSON or CSV as --benchmark_format says), plus, on the
// console, a summary of thread scaling: for each benchmark the wall ms/frame at each
// thread count, the speed-up over 1 thread, and CPU/wall (how many threads were busy).

class ScalingReporter final : public benchmark::BenchmarkReporter {
 public:
  explicit ScalingReporter(benchmark::BenchmarkReporter* inner) : inner_(inner) {}

  bool ReportContext(const Context& context) override { return inner_->ReportContext(context); }

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Iteration || run.error_occurred || run.iterations == 0) continue;
      const std::string prefix = "threads:";
      if (run.run_name.args.rfind(prefix, 0) != 0) continue;
      const int threads = std::stoi(run.run_name.args.substr(prefix.size()));
      Sum& s = sums_[run.run_name.function_name][threads];
      s.wall += run.real_accumulated_time;
      s.cpu += run.cpu_accumulated_time;
      s.frames += static_cast<double>(run.iterations);
    }
    inner_->ReportRuns(runs);
  }

  void Finalize() override {
    inner_->Finalize();
    if (!dynamic_cast<benchmark::ConsoleReporter*>(inner_) || sums_.empty()) return;
    std::FILE* out = stdout;
    std::fflush(out);
    std::fprintf(out, "\nThread scaling (wall ms/frame; CPU/wall = busy threads on average):\n");
    std::fprintf(out, "%-20s %8s %12s %10s %10s\n", "benchmark", "threads", "ms/frame", "speed-up", "CPU/wall");
    for (const auto& [name, by_threads] : sums_) {
      const auto base = by_threads.find(1);
      for (const auto& [threads, s] : by_threads) {
        const double ms = 1e3 * s.wall / s.frames;
        char speedup[32] = "-";
        if (base != by_threads.end() && threads != 1)
          std::snprintf(speedup, sizeof speedup, "%.2fx", (base->second.wall / base->second.frames) / (s.wall / s.frames));
        std::fprintf(out, "%-20s %8d %12.2f %10s %10.2f\n", name.c_str(), threads, ms, speedup, s.cpu / s.wall);
      }
    }
    std::fflush(out);
  }

 private:
  struct Sum {
    double wall = 0, cpu = 0, frames = 0;  // seconds, seconds, iterations (summed over repetitions)
  };
  benchmark::BenchmarkReporter* inner_;
  std::map<std::string, std::map<int, Sum>> sums_;
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // The library owns the default display reporter (a static it never frees).
  ScalingReporter reporter(benchmark::CreateDefaultDisplayReporter());
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
