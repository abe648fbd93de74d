// bench_scenes — the scenes of issue 6 through softpbr (Google Benchmark).
//
//   bench_scenes [--benchmark_filter=gallery64_1080p] [--benchmark_min_time=0.5]
//
// Every scene of scenes.h (the paper's gallery at 64, 16 and 256 segments at 1920×1080
// and at 512×512, the fill-rate scene, the textured scenes, the IBL gallery, and the IBL
// gallery and fill scene again in variants that split their time, the gallery before a wall
// with one directional light's shadows on and off, the shared meshes when
// ../shared/models exists),
// each at 1 and 2 renderer threads. One iteration is one frame of pbr::render(): clear,
// 21 (or 8) draws with the PBR shader, end_frame() with each tile tone mapped to RGBA8
// right after it is drawn (pbr::render_rgba8: the finished image). SOFTPBR_BENCH_MSAA=4
// (or 8) renders into a multisampled target; SOFTPBR_BENCH_LANES=N picks the packet width;
// SOFTPBR_BENCH_TRANSIENT=1 makes that target transient (raster::SampleStorage: its
// samples live in the renderer's tile blocks only, nothing is written back);
// SOFTPBR_BENCH_TEXTURE_VBMI=0 runs the texture lane kernel's plain AVX-512 copy on a CPU
// with VBMI (the one Skylake-X and Cascade Lake run).
// Counters:
//   ms/frame   wall-clock time per frame
//   Mpix/s     shaded pixels (covered pixels × the scene's overdraw) per second
//   Mtri/s     submitted triangles per second
//   shades     fragment-shader invocations a frame (Renderer::frame_shading(): with MSAA,
//              one per pixel and triangle that covers some of its samples)
//   fill       how full the packets were: shades / (shader calls × lanes)
//   peak_MiB   peak heap during a frame beyond what existed before the target was made
//              (the meshes and the scene): target + per-frame geometry
// The renderer, target and meshes are built and one frame is drawn before timing.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <vector>

#include "memory.h"
#include "scenes.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"

namespace bench = softpbr::bench;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

// Pixels whose sample 0 is covered (with 1 sample, every pixel).
std::size_t covered_pixels(const raster::Target& target) {
  std::size_t covered = 0;
  for (int y = 0; y < target.height(); ++y)
    for (int x = 0; x < target.width(); ++x) covered += target.depth(x, y) < 1.0f;
  return covered;
}

// RendererOptions::lanes from SOFTPBR_BENCH_LANES (1, 4, 8 or 16; unset: 0, the widest
// this CPU runs natively), to compare packet widths on one machine.
int bench_lanes() {
  const char* env = std::getenv("SOFTPBR_BENCH_LANES");
  return env != nullptr ? std::atoi(env) : 0;
}

// The target's samples a pixel from SOFTPBR_BENCH_MSAA (1, 4 or 8; unset: 1), to compare
// a scene's MSAA frame with its 1× frame in one binary.
int bench_msaa() {
  const char* env = std::getenv("SOFTPBR_BENCH_MSAA");
  const int n = env != nullptr ? std::atoi(env) : 1;
  return raster::valid_sample_count(n) ? n : 1;
}

// SOFTPBR_BENCH_TRANSIENT=1: a multisampled target keeps no samples (SampleStorage::Transient).
raster::SampleStorage bench_storage() {
  const char* env = std::getenv("SOFTPBR_BENCH_TRANSIENT");
  return env != nullptr && std::atoi(env) != 0 ? raster::SampleStorage::Transient : raster::SampleStorage::Kept;
}

// RendererOptions::tile_size from SOFTPBR_BENCH_TILE (unset or invalid: 64), to compare
// tile sizes (the same bits) on one machine.
int bench_tile() {
  const char* env = std::getenv("SOFTPBR_BENCH_TILE");
  const int n = env != nullptr ? std::atoi(env) : 64;
  return raster::valid_tile_size(n) ? n : 64;
}

void run_scene(benchmark::State& state, const bench::BenchScene* s) {
  const unsigned threads = static_cast<unsigned>(state.range(0));
  raster::RendererOptions options{.threads = threads, .tile_size = bench_tile(), .lanes = bench_lanes()};
  if (const char* env = std::getenv("SOFTPBR_BENCH_BUDGET_MIB"); env != nullptr)
    options.geometry_budget = static_cast<std::size_t>(std::atoll(env)) << 20;
  raster::Renderer renderer(options);
  bench::reset_heap_peak();
  const std::size_t before = bench::heap_in_use();
  raster::Target target(s->width, s->height, bench_msaa(), nullptr, bench_storage());
  raster::Image8 image;
  double shaded = 0.0;
  if (target.transient()) {  // no samples to count: a kept target's frame counts them
    raster::Target kept(s->width, s->height, bench_msaa());
    pbr::render_rgba8(s->scene, renderer, kept, s->output, image);
    shaded = static_cast<double>(covered_pixels(kept)) * s->overdraw;
    bench::reset_heap_peak();
  }
  pbr::render_rgba8(s->scene, renderer, target, s->output, image);  // warm-up: buffers reach their size
  if (!target.transient()) shaded = static_cast<double>(covered_pixels(target)) * s->overdraw;
  const raster::ShadeCounts shading = renderer.frame_shading();
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) pbr::render_rgba8(s->scene, renderer, target, s->output, image);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double frames = static_cast<double>(state.iterations());
  const std::size_t peak = bench::heap_peak() - before;

  state.counters["ms/frame"] = 1e3 * seconds / frames;
  state.counters["Mpix/s"] = 1e-6 * shaded * frames / seconds;
  state.counters["Mtri/s"] = 1e-6 * static_cast<double>(s->triangles) * frames / seconds;
  state.counters["peak_MiB"] = static_cast<double>(peak) / (1024.0 * 1024.0);
  state.counters["shades"] = static_cast<double>(shading.invocations);
  state.counters["fill"] = shading.calls == 0 ? 0.0
                                              : static_cast<double>(shading.invocations) /
                                                    (static_cast<double>(shading.calls) * renderer.lanes());
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  if (const char* env = std::getenv("SOFTPBR_BENCH_TEXTURE_VBMI"); env != nullptr && std::atoi(env) == 0)
    raster::detail::allow_texture_vbmi(false);
  static const std::vector<bench::BenchScene> scenes = [] {
    std::vector<bench::BenchScene> all = bench::all_scenes(bench::default_shared_models());
    for (bench::BenchScene& s : bench::ibl_gallery_variants(1920, 1080)) all.push_back(std::move(s));
    for (bench::BenchScene& s : bench::fill_variants(1920, 1080)) all.push_back(std::move(s));
    for (bench::BenchScene& s : bench::layered_gallery_variants(1920, 1080)) all.push_back(std::move(s));
    for (bench::BenchScene& s : bench::shadow_gallery_scenes(1920, 1080)) all.push_back(std::move(s));
    return all;
  }();
  for (const bench::BenchScene& s : scenes)
    benchmark::RegisterBenchmark(s.name.c_str(), run_scene, &s)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->UseRealTime()
        ->MeasureProcessCPUTime()  // CPU / Time = threads busy on average
        ->Unit(benchmark::kMillisecond);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
