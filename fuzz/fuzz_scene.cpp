// libFuzzer target: scene files (pbr::parse_scene_file), then a small render of what loads.
//
// The input is the scene text. Mesh paths resolve against examples/scenes, so seeds can
// name its models. A SceneFileError whose one line starts with the file name is a fine
// outcome. A scene that loads is animated to a frame picked from the input and rendered
// at most 24×24 pixels (with the file's tile size and at most 2 threads): validation must
// have let through only what the renderer handles, so the render must not throw, and it
// must give the same bits on 1 thread with 64×64 tiles. FUZZ_SCENE_VERBOSE=1 prints each
// input's error or object count (to see what seeds reach).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <string_view>

#include "softpbr/loaders/scene_file.h"
#include "softpbr/raster/renderer.h"
#include "softpbr/raster/target.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz_scene: %s\n", what.c_str());
  std::abort();
}

constexpr int kMaxSide = 24;
// Small enough that the largest scene allowed renders in well under a second here.
constexpr std::uint64_t kMemoryLimit = std::uint64_t{64} << 20;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string name = "fuzz.json";
  pbr::SceneFile file;
  try {
    file = pbr::parse_scene_file(text, name, SOFTPBR_SOURCE_DIR "/examples/scenes", {.memory_limit = kMemoryLimit});
  } catch (const pbr::SceneFileError& e) {
    const std::string_view what = e.what();
    if (what.substr(0, name.size() + 2) != name + ": ") finding("an error not starting with the file name: " + std::string(what));
    if (what.find('\n') != std::string_view::npos) finding("an error message of more than one line");
    if (std::getenv("FUZZ_SCENE_VERBOSE")) std::fprintf(stderr, "%s\n", e.what());
    return 0;
  }

  if (std::getenv("FUZZ_SCENE_VERBOSE")) std::fprintf(stderr, "loaded: %zu objects\n", file.scene.objects.size());
  const long frame = static_cast<long>(size % 97);
  const pbr::Scene scene = pbr::animate(file, frame);
  const int width = std::min(file.render.width, kMaxSide), height = std::min(file.render.height, kMaxSide);
  const unsigned threads = file.render.threads == 0 ? 2u : std::min(file.render.threads, 2u);
  try {
    raster::Renderer renderer({.threads = threads, .tile_size = file.render.tile_size});
    raster::Target target(width, height);
    pbr::render(scene, renderer, target);
    raster::Renderer reference_renderer({.threads = 1, .tile_size = 64});
    raster::Target reference(width, height);
    pbr::render(scene, reference_renderer, reference);
    if (std::memcmp(target.colors().data(), reference.colors().data(), target.colors().size_bytes()) != 0)
      finding("the render differs between thread counts or tile sizes");
  } catch (const std::exception& e) {
    finding(std::string("a loaded scene does not render: ") + e.what());
  }
  return 0;
}
