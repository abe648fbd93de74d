// bench_scene_file — parsing hostile scene files (Google Benchmark).
//
//   bench_scene_file [--benchmark_filter=keys]
//
// keys/N: a scene file whose "camera" object holds N distinct keys, refused by its first
// unknown key after the duplicate-key pass has seen all N. The pass keeps each object's
// keys in a hash set, so the report's complexity fit (BigO) says N or N lg N, never N^2 (a
// vector of keys took 17 s for 200000 in a Debug build). This is the measurement the
// suite's test of the same file does not make: tests are never timed.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>

#include "softpbr/loaders/scene_file.h"

namespace pbr = softpbr::pbr;

namespace {

void keys(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::string text = "{\"camera\": {";
  for (int i = 0; i < n; ++i) text += (i ? ",\"k" : "\"k") + std::to_string(i) + "\": 0";
  text += "}, \"objects\": []}";
  for (auto _ : state) {
    try {
      pbr::parse_scene_file(text, "keys.json", ".");
      state.SkipWithError("the file loaded: it should be refused by its unknown key");
      break;
    } catch (const pbr::SceneFileError&) {
    }
  }
  state.SetComplexityN(n);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(text.size()));
}

}  // namespace

BENCHMARK(keys)->RangeMultiplier(4)->Range(1 << 12, 1 << 18)->Complexity()->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
