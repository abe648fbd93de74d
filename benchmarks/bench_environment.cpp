// bench_environment — prefiltering an environment for image-based lighting (issue 15).
//
//   bench_environment [--benchmark_filter=venice] [--benchmark_min_time=2]
//
// One iteration is one pbr::Environment built from an equirectangular image that is
// already decoded in memory (the 9 SH coefficients, the octahedral level 0 and its mip
// chain, the 5 GGX-prefiltered levels), on a raster::ThreadPool of `threads` threads
// (1: no pool, as Environment::studio() builds it). The maps:
//   venice_1024x512  ../shared/envmaps/venice_sunset_1k.hdr (skipped with a note when the
//                    folder is missing; SOFTPBR_SHARED_ENVMAPS points elsewhere)
//   studio_1024x512  Environment::studio_image(1024, 512): the built-in studio at the size
//                    of the target
//   studio_512x256   Environment::studio_image() as Environment::studio() prefilters it
//                    (the gallery_ibl scene's environment)
// Both 1024×512 maps give a 512² level 0 (EnvironmentOptions::size 0) and 64 samples a
// texel at level 1. Besides:
//   decode_venice    image::load_imagef of the .hdr file's bytes (read once before timing)
//   dfg_table        the split-sum table's computation as dfg_table() does it once per
//                    process (32 × 32 dfg_reference(…, 1024)), one thread
//   lookup/...       what a shaded pixel's lookups cost: Texture::sample_lod_batch() of 16
//                    points (the packet form's call, as env_radiance and env_dfg make it) on
//                    the built-in studio's level 0 (258², what the gallery's background
//                    reads), level 2 (34²) and the DFG table (32²), at 65,536 points of octahedral coordinates
//                    of directions spread over the sphere (a fixed integer hash); the
//                    counter ns_per_lookup is per point
// Issue 15's target: a 1024×512 environment prefiltered in ≤ 0.5 s on 2 threads.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "softpbr/image/load.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/raster/pool.h"

namespace image = softpbr::image;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

std::filesystem::path shared_envmaps() {
  if (const char* env = std::getenv("SOFTPBR_SHARED_ENVMAPS")) return env;
  return std::filesystem::path(SOFTPBR_SOURCE_DIR) / ".." / "shared" / "envmaps";
}

void prefilter(benchmark::State& state, const image::ImageF* map) {
  const unsigned threads = static_cast<unsigned>(state.range(0));
  std::optional<raster::ThreadPool> pool;
  if (threads > 1) pool.emplace(threads);
  for (auto _ : state) {
    pbr::Environment env(image::ImageViewF(*map), "bench", {}, pool ? &*pool : nullptr);
    benchmark::DoNotOptimize(env.irradiance());
  }
  state.counters["Mtexels_in"] = static_cast<double>(map->width) * map->height / 1e6;
}

void decode(benchmark::State& state, const std::vector<std::uint8_t>* bytes) {
  for (auto _ : state) {
    image::ImageF im = image::load_imagef(*bytes, "venice_sunset_1k.hdr");
    benchmark::DoNotOptimize(im.rgba.data());
  }
}

void dfg(benchmark::State& state) {
  for (auto _ : state) {
    double sum = 0.0;
    for (int y = 0; y < pbr::kDfgSize; ++y)
      for (int x = 0; x < pbr::kDfgSize; ++x) {
        const glm::dvec2 ab = pbr::dfg_reference((x + 0.5) / pbr::kDfgSize, (y + 0.5) / pbr::kDfgSize, 1024);
        sum += ab.x + ab.y;
      }
    benchmark::DoNotOptimize(sum);
  }
}

// Octahedral coordinates (env_octahedral<float>) of `count` directions from a fixed hash.
std::vector<float> lookup_points(int size, int count) {
  std::vector<float> uv(static_cast<std::size_t>(count) * 2);
  std::uint32_t h = 12345u;
  auto next = [&] {
    h ^= h << 13;
    h ^= h >> 17;
    h ^= h << 5;
    return static_cast<float>(h >> 8) * (2.0f / 16777216.0f) - 1.0f;  // [−1, 1)
  };
  for (int i = 0; i < count; ++i) {
    const pbr::EnvVec3<float> d{next(), next(), next()};
    pbr::env_octahedral(d, size, uv[2 * static_cast<std::size_t>(i)], uv[2 * static_cast<std::size_t>(i) + 1]);
  }
  return uv;
}

void lookup(benchmark::State& state, const raster::Texture* texture, int size) {
  constexpr int kPoints = 65536, kLanes = 16;
  const std::vector<float> uv = lookup_points(size, kPoints);
  std::vector<float> u(kPoints), v(kPoints), lod(kPoints, 0.0f), out(static_cast<std::size_t>(kPoints) * 4);
  for (int i = 0; i < kPoints; ++i) {
    u[static_cast<std::size_t>(i)] = uv[2 * static_cast<std::size_t>(i)];
    v[static_cast<std::size_t>(i)] = uv[2 * static_cast<std::size_t>(i) + 1];
  }
  const raster::Sampler& s = pbr::Environment::level_sampler();
  for (auto _ : state) {
    for (int i = 0; i < kPoints; i += kLanes) {
      float* o = out.data() + static_cast<std::size_t>(i) * 4;
      texture->sample_lod_batch(s, kLanes,
                                {u.data() + i, v.data() + i, nullptr, nullptr, nullptr, nullptr, lod.data() + i, o,
                                 o + kLanes, o + 2 * kLanes, o + 3 * kLanes});
    }
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["ns_per_lookup"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * kPoints, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  static std::vector<std::uint8_t> venice_bytes;
  static image::ImageF venice;
  const std::filesystem::path venice_path = shared_envmaps() / "venice_sunset_1k.hdr";
  std::error_code ec;
  if (std::filesystem::is_regular_file(venice_path, ec)) {
    venice_bytes = image::read_file(venice_path);
    venice = image::load_imagef(venice_bytes, venice_path.string());
  } else {
    std::fprintf(stderr, "note: %s not found: the venice benchmarks are skipped\n", venice_path.string().c_str());
  }
  static const image::ImageF studio_big = pbr::Environment::studio_image(1024, 512);
  static const image::ImageF studio_small = pbr::Environment::studio_image();

  struct Map {
    const char* name;
    const image::ImageF* image;
  };
  std::vector<Map> maps;
  if (!venice.rgba.empty()) maps.push_back({"prefilter/venice_1024x512", &venice});
  maps.push_back({"prefilter/studio_1024x512", &studio_big});
  maps.push_back({"prefilter/studio_512x256", &studio_small});
  for (const Map& m : maps)
    benchmark::RegisterBenchmark(m.name, prefilter, m.image)
        ->ArgName("threads")
        ->Arg(1)
        ->Arg(2)
        ->UseRealTime()
        ->MeasureProcessCPUTime()
        ->Unit(benchmark::kMillisecond);
  if (!venice_bytes.empty())
    benchmark::RegisterBenchmark("decode_venice", decode, &venice_bytes)->UseRealTime()->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("dfg_table", dfg)->UseRealTime()->Unit(benchmark::kMillisecond);
  static const std::shared_ptr<const pbr::Environment> studio = pbr::Environment::studio();
  for (const int level : {0, 2}) {
    const int side = studio->level(level).width();
    const std::string name = "lookup/studio_level" + std::to_string(level) + "_" + std::to_string(side);
    benchmark::RegisterBenchmark(name.c_str(), lookup, &studio->level(level), studio->level_size(level));
  }
  benchmark::RegisterBenchmark("lookup/dfg_32", lookup, &pbr::dfg_table(), pbr::kDfgSize - 2);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
