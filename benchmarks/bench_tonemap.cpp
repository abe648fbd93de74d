// bench_tonemap — pbr::ToneMapper::encode() alone, on realistic content: the float target of
// one frame of the 1080p gallery (benchmarks/scenes.h: gallery64_1080p, Reinhard then gamma
// 2.2), drawn once before timing. Each iteration encodes the whole 1920 × 1080 target tile
// by tile (64 × 64, as pbr::render_rgba8 does after each tile), on one thread. Counter:
// ns_per_pixel. The other operators and the sRGB curve run on the same radiance.
//
//   build/benchmarks/bench_tonemap [--benchmark_filter=...]
#include <algorithm>
#include <cstddef>
#include <string>

#include <benchmark/benchmark.h>

#include "scenes.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace {

namespace bench = softpbr::bench;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

// The gallery's float target, rendered once for every benchmark.
const raster::Target& gallery_target() {
  static const raster::Target target = [] {
    bench::BenchScene s = bench::gallery_scene(64, 1920, 1080);
    raster::Renderer renderer({.threads = 1, .tile_size = 64});
    raster::Target t(s.width, s.height);
    pbr::render(s.scene, renderer, t);
    return t;
  }();
  return target;
}

void encode_tiles(benchmark::State& state, pbr::ToneMap op, float gamma, pbr::EncodeKernel kernel, int repeats) {
  if (!pbr::ToneMapper::supported(kernel)) {
    state.SkipWithError("this CPU does not run the kernel");
    return;
  }
  const raster::Target& target = gallery_target();
  const pbr::ToneMapper mapper({0.0f, op, gamma});
  raster::Image8 image;
  image.width = target.width();
  image.height = target.height();
  image.rgba.resize(target.colors().size() * 4);
  constexpr int kTile = 64;
  for (auto _ : state) {
    for (int y = 0; y < target.height(); y += kTile)
      for (int x = 0; x < target.width(); x += kTile)
        for (int r = 0; r < repeats; ++r)
          mapper.encode(target, x, y, std::min(x + kTile, target.width()), std::min(y + kTile, target.height()), image,
                        kernel);
    benchmark::DoNotOptimize(image.rgba.data());
    benchmark::ClobberMemory();
  }
  const double pixels = static_cast<double>(target.colors().size());
  state.counters["ns_per_pixel"] =
      benchmark::Counter(pixels * repeats * static_cast<double>(state.iterations()) * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Arguments: the kernel (tonemap.h: 0 scalar, the reference; 1 four lanes; 2 AVX2; 3
// AVX-512), and how many times each tile is encoded in a row: 1 reads the target from
// memory (33 MB of floats), 8 mostly from the cache, as render_rgba8 does right after
// drawing a tile (ns_per_pixel counts every encoding).
#define SOFTPBR_ENCODE_BENCH(name, op, gamma)                                                                    \
  void name(benchmark::State& s) {                                                                               \
    encode_tiles(s, op, gamma, static_cast<pbr::EncodeKernel>(s.range(0)), static_cast<int>(s.range(1)));     \
  }                                                                                                              \
  BENCHMARK(name)->ArgNames({"kernel", "repeats"})->ArgsProduct({{0, 1, 2, 3}, {1, 8}})->Unit(benchmark::kMillisecond)

SOFTPBR_ENCODE_BENCH(BM_encode_reinhard_gamma22, pbr::ToneMap::Reinhard, 2.2f);
SOFTPBR_ENCODE_BENCH(BM_encode_reinhard_srgb, pbr::ToneMap::Reinhard, 0.0f);
SOFTPBR_ENCODE_BENCH(BM_encode_none_srgb, pbr::ToneMap::None, 0.0f);
SOFTPBR_ENCODE_BENCH(BM_encode_aces_srgb, pbr::ToneMap::Aces, 0.0f);
SOFTPBR_ENCODE_BENCH(BM_encode_neutral_srgb, pbr::ToneMap::Neutral, 0.0f);
SOFTPBR_ENCODE_BENCH(BM_encode_reinhard_gamma005, pbr::ToneMap::Reinhard, 0.05f);  // binary search

}  // namespace

BENCHMARK_MAIN();
