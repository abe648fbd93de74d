// gallery — the paper's scene, headless: a grid of spheres, one row per material,
// roughness rising left to right, three point lights, written to a PNG.
//
//   gallery [out.png] [--width W] [--height H] [--threads N] [--tile-size T] [--lanes L]
//           [--spot | --obj mesh.obj]
//
// --spot draws the paper's cow (assets/models/spot) in place of the spheres; --obj any
// OBJ file (all its shapes merged, scaled to fit each cell).
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "softpbr/image/write.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

int main(int argc, char** argv) {
  std::string out = "gallery.png";
  int width = 1280, height = 720, msaa = 1;
  std::string obj;
  raster::RendererOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> int {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return std::atoi(argv[++i]);
    };
    try {
      if (arg == "--width") width = value();
      else if (arg == "--height") height = value();
      else if (arg == "--threads") options.threads = static_cast<unsigned>(std::max(0, value()));
      else if (arg == "--tile-size") options.tile_size = value();
      else if (arg == "--lanes") options.lanes = value();
      else if (arg == "--msaa") msaa = value();
      else if (arg == "--spot") obj = SOFTPBR_ASSETS_DIR "/models/spot/spot_triangulated.obj";
      else if (arg == "--obj") {
        if (i + 1 >= argc) throw std::invalid_argument("--obj needs a file");
        obj = argv[++i];
      }
      else if (arg == "-h" || arg == "--help") {
        std::printf(
            "usage: gallery [out.png] [--width W] [--height H] [--threads N] [--tile-size T] [--lanes L]\n"
            "               [--msaa 1|4|8] [--spot | --obj mesh.obj]\n");
        return 0;
      } else out = arg;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "gallery: %s\n", e.what());
      return 2;
    }
  }
  try {
    raster::Renderer renderer(options);
    raster::Target target(width, height, msaa);
    pbr::GalleryOptions gallery;
    if (!obj.empty()) {
      const pbr::ObjModel model = pbr::load_obj(obj);
      for (const std::string& w : model.warnings) std::fprintf(stderr, "gallery: warning: %s\n", w.c_str());
      gallery.mesh = std::make_shared<pbr::Mesh>(pbr::merge_shapes(model));
    }
    const pbr::Scene scene = pbr::make_gallery(gallery);
    pbr::render(scene, renderer, target);
    softpbr::image::write_png(out, pbr::tone_map_to_rgba8(target, pbr::gallery_output()));
    std::printf("wrote %s (%dx%d, %u threads, hash %016llx)\n", out.c_str(), width, height, renderer.threads(),
                static_cast<unsigned long long>(raster::hash_colors(target)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gallery: %s\n", e.what());
    return 1;
  }
  return 0;
}
