// bench_ktx2 — KTX2 decoding (issue 54), megatexels per second, on 1 and 2 threads.
//
//   bench_ktx2 [--benchmark_filter=uastc]
//
// One iteration decodes a whole texture, every level, from its bytes in memory (read once
// before timing):
//   uastc/<name>/threads:N  image::load_ktx2 of AnisotropyBarnLamp's KTX2 textures (2048²,
//                  UASTC, Zstandard; ../shared/gltf, or SOFTPBR_SHARED; skipped with a note
//                  when absent): Zstandard inflate (one thread) + UASTC blocks (ranges of
//                  block rows on a raster::ThreadPool of N threads)
//   png/<name>     image::load_image8 of the same texels (level 0) written as a PNG by
//                  image::encode_png (level 2, the project's writer): the cost KTX2
//                  replaces; one thread (a PNG's rows are one zlib stream)
//   etc1s_2048/threads:N  a 2048² ETC1S texture made by tests/etc1s_writer.h (256 random
//                  endpoints and selectors, random blocks; its Huffman tables are flat, so
//                  this is the slice decoder's speed, not a real file's ratio)
//   file/<name>/threads:N  each KTX2 file SOFTPBR_BENCH_KTX2_FILES lists (colon-separated),
//                  e.g. a real 2048² ETC1S texture (benchmarks/README.md says how one was made)
// The counter Mtexels_per_s is level-0 texels per second of wall time for the threads:N
// rows (UseRealTime), of CPU time for png/; the CPU column of threads:N is the whole
// process's (MeasureProcessCPUTime: both threads' work), and the counter caller_cpu_ms the
// calling thread's CPU time an iteration (with 2 threads on an idle machine, about the
// wall time: the other thread works beside it). A glTF's textures decode in parallel on the
// render's pool, one a thread; a model with one texture lends it the pool's threads.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "etc1s_writer.h"
#include "ktx2_writer.h"
#include "shared_assets.h"
#include "softpbr/image/ktx2.h"
#include "softpbr/image/load.h"
#include "softpbr/image/write.h"
#include "softpbr/raster/pool.h"

namespace fs = std::filesystem;
namespace image = softpbr::image;

namespace {

void report(benchmark::State& state, int w, int h) {
  state.counters["Mtexels_per_s"] =
      benchmark::Counter(static_cast<double>(w) * h * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
}

// CPU time of the calling thread, in milliseconds.
double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

void BM_Ktx2(benchmark::State& state, std::vector<std::uint8_t> bytes) {
  softpbr::raster::ThreadPool pool(static_cast<unsigned>(state.range(0)));
  const image::ParallelFor parallel = [&pool](std::size_t count, const std::function<void(std::size_t)>& task) {
    pool.parallel_for(count, task);
  };
  int w = 0, h = 0;
  const double caller_start = thread_cpu_ms();
  for (auto _ : state) {
    const image::Ktx2Image k = image::load_ktx2(bytes, "bench.ktx2", {}, nullptr, parallel);
    w = k.levels[0].width;
    h = k.levels[0].height;
    benchmark::DoNotOptimize(k.levels[0].rgba.data());
  }
  // The calling thread's share: on an idle machine, about the wall time with N threads.
  state.counters["caller_cpu_ms"] = benchmark::Counter(thread_cpu_ms() - caller_start, benchmark::Counter::kAvgIterations);
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
    benchmark::RegisterBenchmark((std::string("uastc/") + name).c_str(), BM_Ktx2, bytes)
        ->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
    const image::Ktx2Image k = image::load_ktx2(bytes, file.string());
    benchmark::RegisterBenchmark((std::string("png/") + name).c_str(), BM_Png, image::encode_png(k.levels[0], "bench.png"))
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("etc1s_2048", BM_Ktx2, etc1s_2048())
      ->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
  if (const char* list = std::getenv("SOFTPBR_BENCH_KTX2_FILES")) {
    const std::string files = list;
    for (std::size_t start = 0; start < files.size();) {
      const std::size_t end = std::min(files.find(':', start), files.size());
      if (end > start) {
        const fs::path file = files.substr(start, end - start);
        benchmark::RegisterBenchmark(("file/" + file.filename().string()).c_str(), BM_Ktx2, image::read_file(file))
            ->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
      }
      start = end + 1;
    }
  }
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
