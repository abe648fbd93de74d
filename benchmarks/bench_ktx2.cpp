// bench_ktx2 — KTX2 decoding (issue 54), megatexels per second, one thread.
//
//   bench_ktx2 [--benchmark_filter=uastc]
//
// One iteration decodes a whole texture from its bytes in memory (read once before timing):
//   uastc/<name>   image::load_ktx2 of AnisotropyBarnLamp's KTX2 textures (2048², UASTC,
//                  Zstandard; ../shared/gltf, or SOFTPBR_SHARED; skipped with a note when
//                  absent): Zstandard inflate + UASTC blocks
//   png/<name>     image::load_image8 of the same texels written as a PNG by
//                  image::encode_png (level 2, the project's writer): the cost KTX2 replaces
//   etc1s_2048     image::load_ktx2 of a 2048² ETC1S texture made by tests/etc1s_writer.h
//                  (256 random endpoints and selectors, random blocks; its Huffman tables
//                  are flat, so this is the slice decoder's speed, not a real file's ratio)
// The counter Mtexels_per_s is level-0 texels per second. Decoding is single-threaded per
// texture; a glTF's textures decode in parallel on the render's pool, one per thread.
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "etc1s_writer.h"
#include "ktx2_writer.h"
#include "shared_assets.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"

namespace fs = std::filesystem;
namespace image = softpbr::image;

namespace {

void report(benchmark::State& state, int w, int h) {
  state.counters["Mtexels_per_s"] =
      benchmark::Counter(static_cast<double>(w) * h * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Ktx2(benchmark::State& state, std::vector<std::uint8_t> bytes) {
  int w = 0, h = 0;
  for (auto _ : state) {
    const image::Ktx2Image k = image::load_ktx2(bytes, "bench.ktx2");
    w = k.levels[0].width;
    h = k.levels[0].height;
    benchmark::DoNotOptimize(k.levels[0].rgba.data());
  }
  report(state, w, h);
}

void BM_Png(benchmark::State& state, std::vector<std::uint8_t> bytes) {
  int w = 0, h = 0;
  for (auto _ : state) {
    const image::Image8 im = image::load_image8(bytes, "bench.png");
    w = im.width;
    h = im.height;
    benchmark::DoNotOptimize(im.rgba.data());
  }
  report(state, w, h);
}

std::vector<std::uint8_t> etc1s_2048() {
  std::uint32_t state = 54;
  auto next = [&] { return state = state * 1664525u + 1013904223u; };
  std::vector<ktx2_test::Etc1sEndpointSpec> endpoints;
  std::vector<std::array<std::uint8_t, 4>> selectors;
  for (int i = 0; i < 256; ++i) {
    endpoints.push_back({int(next() >> 27), int(next() >> 27), int(next() >> 27), int(next() >> 29)});
    selectors.push_back({std::uint8_t(next() >> 24), std::uint8_t(next() >> 24), std::uint8_t(next() >> 24), std::uint8_t(next() >> 24)});
  }
  std::vector<ktx2_test::Etc1sBlock> blocks(512 * 512);
  for (ktx2_test::Etc1sBlock& b : blocks) b = {int(next() >> 24), int(next() >> 24)};
  const ktx2_test::Etc1sData data = ktx2_test::write_etc1s(endpoints, selectors, 512, 512, blocks, {});
  ktx2_test::Ktx2Spec s;
  s.vk_format = 0;
  s.color_model = 163;
  s.scheme = 1;
  s.width = s.height = 2048;
  s.sgd = data.sgd;
  s.levels.push_back(data.level);
  return ktx2_test::write_ktx2(s);
}

const bool registered = [] {
  const fs::path model = shared_assets::folder() / "gltf/AnisotropyBarnLamp/glTF-KTX2-Basisu";
  for (const char* name : {"basecolor", "normalbump", "occlusionroughnessmetal", "anisotropy"}) {
    const fs::path file = model / (std::string("AnisotropyBarnLamp_") + name + ".ktx2");
    if (!fs::exists(file)) {
      std::fprintf(stderr, "bench_ktx2: %s is absent: uastc/ and png/ skipped\n", file.c_str());
      break;
    }
    const std::vector<std::uint8_t> bytes = image::read_file(file);
    benchmark::RegisterBenchmark((std::string("uastc/") + name).c_str(), BM_Ktx2, bytes)->Unit(benchmark::kMillisecond);
    const image::Ktx2Image k = image::load_ktx2(bytes, file.string());
    benchmark::RegisterBenchmark((std::string("png/") + name).c_str(), BM_Png, image::encode_png(k.levels[0], "bench.png"))
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("etc1s_2048", BM_Ktx2, etc1s_2048())->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
