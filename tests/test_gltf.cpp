// glTF 2.0 loading: the Khronos sample models of ../shared/gltf load and render (skipped
// when the folder is absent); renders go to build/gltf-output/ for looking at.
#include <doctest/doctest.h>

#include <filesystem>
#include <algorithm>
#include <string>

#include "softpbr/image/write.h"
#include "softpbr/pbr/gltf.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

fs::path shared_gltf() { return fs::path(SOFTPBR_SOURCE_DIR) / ".." / "shared" / "gltf"; }

// The model file of a sample folder: its glTF-Binary .glb, else its glTF .gltf.
fs::path model_file(const fs::path& folder) {
  for (const char* sub : {"glTF-Binary", "glTF"}) {
    const fs::path dir = folder / sub;
    if (!fs::is_directory(dir)) continue;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".glb" || e.path().extension() == ".gltf") return e.path();
  }
  return {};
}

pbr::Scene scene_of(const pbr::GltfScene& g, int width, int height) {
  pbr::Scene s;
  s.objects = g.objects;
  // A model flat in y (a floor, TwoSidedPlane) is seen from 30° above, not edge-on.
  const pbr::Bounds b = pbr::world_bounds(s.objects);
  const glm::vec3 e = b.extent();
  const float pitch = e.y < 0.01f * std::max(e.x, e.z) ? 0.5236f : 0.0f;
  s.camera = pbr::framing_camera(b, float(width) / height, 0.0f, pitch);
  s.lights = g.lights.empty() ? pbr::default_light_rig(s.camera) : g.lights;
  s.ambient = glm::vec3(pbr::kDefaultAmbient);
  s.background = {0.05f, 0.05f, 0.06f, 1.0f};
  return s;
}

}  // namespace

TEST_CASE("every Khronos sample model in ../shared/gltf loads and renders") {
  if (!fs::is_directory(shared_gltf())) {
    MESSAGE("skipped: " << shared_gltf() << " is absent");
    return;
  }
  raster::Renderer renderer({.threads = 0});
  const fs::path out_dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf-output";
  fs::create_directories(out_dir);
  int models = 0;
  for (const auto& entry : fs::directory_iterator(shared_gltf())) {
    if (!entry.is_directory()) continue;
    const fs::path file = model_file(entry.path());
    if (file.empty()) continue;
    CAPTURE(file);
    const pbr::GltfScene g = pbr::load_gltf(file, {.pool = &renderer.pool()});
    CHECK(!g.objects.empty());
    CHECK(g.triangles > 0);
    for (const std::string& w : g.warnings) MESSAGE(w);
    raster::Target target(480, 360);
    pbr::render(scene_of(g, 480, 360), renderer, target);
    int drawn = 0;
    for (float d : target.depths()) drawn += d < 1.0f;
    CHECK(drawn > 480 * 360 / 50);  // the model fills part of the frame
    softpbr::image::write_png(out_dir / (entry.path().filename().string() + ".png"),
                              pbr::tone_map_to_rgba8(target, pbr::OutputSettings{}));
    ++models;
  }
  CHECK(models >= 15);
}
