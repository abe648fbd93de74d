// A one-file program built without CMake, through pkg-config (the pkgconfig_consumer test):
//   c++ main.cpp -o gallery $(pkg-config --cflags --libs softpbr)
// It renders a small gallery with softpbr::pbr through a softpbr::job frame and checks its
// golden hash with softpbr::golden, and parses an OBJ triangle with softpbr::loaders (its
// own header path).
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "softpbr/golden/compare.h"
#include "softpbr/job/render_job.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/scene.h"

int main() {
  softpbr::pbr::GalleryOptions options;
  options.segments = 16;
  const softpbr::pbr::Scene scene = softpbr::pbr::make_gallery(options);
  softpbr::raster::Renderer renderer({.threads = 2, .tile_size = 16});
  softpbr::pbr::RenderSettings settings;
  settings.width = 64;
  settings.height = 36;
  settings.output = {};
  softpbr::job::Frame frame;
  frame.render(scene, settings, renderer, {.rgba8 = true});
  const softpbr::raster::Image8& image = frame.rgba();
  int lit = 0;  // pixels brighter than the background: the spheres
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) lit += image.rgba[i] + image.rgba[i + 1] + image.rgba[i + 2] > 30;
  std::printf("pkg-config consumer: %d of %d pixels lit, content hash %s\n", lit, 64 * 36,
              softpbr::golden::hash_hex(softpbr::golden::content_hash(image)).c_str());
  const std::filesystem::path obj = std::filesystem::temp_directory_path() / "softpbr-pkg-config-triangle.obj";
  std::ofstream(obj) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const softpbr::pbr::ObjModel model = softpbr::pbr::load_obj(obj);
  std::filesystem::remove(obj);
  const bool obj_ok = model.shapes.size() == 1 && model.shapes[0].mesh.indices.size() == 3;
  std::printf("pkg-config consumer: an OBJ triangle through softpbr::loaders: %s\n", obj_ok ? "ok" : "WRONG");
  return lit > 64 * 36 / 10 && obj_ok ? 0 : 1;
}
