// libFuzzer target: glTF 2.0 loading (pbr::load_gltf from memory), .gltf JSON and .glb.
//
// The input is the file's bytes; external references resolve against a folder that does
// not exist, so only embedded buffers and images (data URIs, .glb chunks) are read. A
// LoadError is a fine outcome; anything else thrown, a crash, a hang or a sanitizer report
// is a finding. A scene that loads must be drawable: every index names a vertex, every
// position is finite, every non-empty stream has one entry per vertex; the automatic camera
// frames it (pbr::gltf_scene_file) or refuses it with a LoadError.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>

#include "fuzz_support.h"

#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/loaded_scene.h"
#include "softpbr/pbr/camera.h"

namespace pbr = softpbr::pbr;

namespace {
[[noreturn]] void finding(const char* what) { softpbr::fuzz::finding("fuzz_gltf", what); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  pbr::GltfOptions options;
  // Small enough that a hostile image or buffer cannot exhaust the fuzzer's memory.
  options.image_limits.max_side = 4096;
  options.image_limits.max_decoded_bytes = std::uint64_t{64} << 20;
  options.max_file_bytes = std::uint64_t{16} << 20;
  try {
    const pbr::GltfScene g = pbr::load_gltf(std::span<const std::uint8_t>(data, size), "fuzz.gltf",
                                            "/nonexistent-softpbr-fuzz-folder", options);
    for (const pbr::Object& o : g.objects) {
      if (!o.mesh) finding("an object without a mesh");
      const pbr::Mesh& m = *o.mesh;
      if (m.indices.size() % 3 != 0) finding("indices not a multiple of 3");
      for (std::uint32_t i : m.indices)
        if (i >= m.vertices.size()) finding("an index past the vertices");
      for (const pbr::MeshVertex& v : m.vertices)
        if (!std::isfinite(v.position.x) || !std::isfinite(v.position.y) || !std::isfinite(v.position.z))
          finding("a position that is not finite");
      pbr::validate_streams(m);
    }
    // The automatic camera frames it, or says why not (a LoadError naming the file): never
    // an invalid camera (std::invalid_argument). Yaw far outside ±180 or not, by the size.
    pbr::GltfView view;
    view.width = 16;
    view.height = 12;
    view.environment = false;
    view.yaw = size % 2 != 0 ? 1e25f : -190.0f;
    const pbr::LoadedScene framed = pbr::gltf_scene_file(g, view, "fuzz.gltf");
    pbr::validate(framed.scene.camera);
  } catch (const pbr::LoadError&) {
  } catch (const std::bad_alloc&) {
    finding("out of memory: a limit was not checked before allocating");
  }
  return 0;
}
