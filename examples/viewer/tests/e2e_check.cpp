// e2e_check — second half of the viewer's end-to-end test (run_e2e.sh): every screenshot
// the viewer wrote while replaying session.txt in an SDL window must equal, bit for bit,
// the image the library renders for the state the session should have reached. The
// states are built here by hand from session.txt's comments, not by replaying events.
//
//   e2e_check OUT_DIR TETRAHEDRON_OBJ        exit 0: all equal; 1: a difference (printed)
//   e2e_check --models OUT_DIR BOXES_GLTF WEDGE_GLTF    the same for models.txt (run_models.sh)
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "softpbr/image/load.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/raster/raster.h"
#include "viewer_scene.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
using viewer::ViewerState;

namespace {
constexpr int kWidth = 320, kHeight = 180;  // run_e2e.sh's window

// One frame of flying with a movement key held: as advance() with kScriptFrameSeconds.
constexpr float kStep = viewer::kMoveSpeed * viewer::kScriptFrameSeconds;

void turn_lights(ViewerState& s, int frames) {
  for (int i = 0; i < frames; ++i) s.light_angle += viewer::kLightRadiansPerSecond * viewer::kScriptFrameSeconds;
}

struct Shot {
  std::string file;
  ViewerState state;
};

std::vector<Shot> expected_shots() {
  std::vector<Shot> shots;
  ViewerState s;
  s.mesh_count = 6;  // spheres, spot, teapot, torus, cube, the tetrahedron
  shots.push_back({"0_gallery.png", s});

  s.material = 1;  // copper: its preset roughness 0.3 (6 steps), metallic
  s.roughness_steps = 6;
  s.metallic = true;
  s.mesh = 1;  // spot
  for (int i = 0; i < 12; ++i) s.camera.move(kStep, 0.0f, 0.0f);
  shots.push_back({"1_copper_spot.png", s});

  s.roughness_steps = 8;
  s.metallic = false;
  s.mesh = 2;  // teapot
  s.captured = true;
  s.camera.turn(60.0f * viewer::kMouseRadiansPerPixel, 30.0f * viewer::kMouseRadiansPerPixel);
  for (int i = 0; i < 6; ++i) s.camera.move(0.0f, -kStep, 0.0f);
  s.lights_rotating = true;
  turn_lights(s, 15);
  shots.push_back({"2_teapot.png", s});

  s.material = viewer::kGalleryMaterial;
  s.mesh = 5;  // the tetrahedron
  for (int i = 0; i < 9; ++i) s.camera.move(-kStep, 0.0f, 0.0f);
  turn_lights(s, 9);
  shots.push_back({"3_gallery_tetrahedron.png", s});

  s.mesh = 0;
  s.material = 9;  // plastic_red, roughness 0.3 − 0.05, dielectric
  s.roughness_steps = 5;
  s.metallic = false;
  s.lights_rotating = false;
  shots.push_back({"viewer-0001.png", s});
  shots.push_back({"final.png", s});
  return shots;
}

// Compares a PNG with an image; prints the first difference.
bool same(const std::string& path, const raster::Image8& expected) {
  softpbr::image::Image8 shot;
  try {
    shot = softpbr::image::load_png(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cannot read the screenshot: %s\n", e.what());
    return false;
  }
  const int w = shot.width, h = shot.height;
  bool ok = w == expected.width && h == expected.height;
  if (!ok) std::fprintf(stderr, "%s: %dx%d, expected %dx%d\n", path.c_str(), w, h, expected.width, expected.height);
  std::size_t differing = 0, first = 0;
  for (std::size_t i = 0; ok && i < expected.rgba.size(); ++i)
    if (shot.rgba[i] != expected.rgba[i] && differing++ == 0) first = i;
  if (ok && differing > 0) {
    const std::size_t p = first / 4;
    std::fprintf(stderr, "%s: %zu bytes differ; first at pixel (%zu, %zu) channel %zu: %d, expected %d\n",
                 path.c_str(), differing, p % static_cast<std::size_t>(w), p / static_cast<std::size_t>(w), first % 4,
                 shot.rgba[first], expected.rgba[first]);
    ok = false;
  }
  return ok;
}
}  // namespace

// models.txt: boxes.gltf from the command line, wedge.gltf dropped twice.
int check_models(const std::string& dir, const std::string& boxes, const std::string& wedge) {
  std::vector<std::string> warnings;
  auto meshes = viewer::load_meshes(SOFTPBR_ASSETS_DIR, {boxes, wedge, wedge}, warnings);
  raster::Renderer renderer({.threads = 3, .tile_size = 16});
  raster::Target target(kWidth, kHeight);
  ViewerState s;
  s.mesh_count = 8;
  std::vector<Shot> shots;
  s.mesh = 5;
  shots.push_back({"0_boxes.png", s});
  viewer::select_material(s, 2);  // silver
  shots.push_back({"1_boxes_silver.png", s});
  s.mesh = 6;
  shots.push_back({"2_wedge.png", s});
  s.mesh = 0;
  shots.push_back({"3_spheres.png", s});
  s.mesh = 6;
  shots.push_back({"4_wedge_again.png", s});
  bool ok = true;
  std::vector<raster::Image8> images;
  for (const Shot& shot : shots) {
    images.push_back(viewer::render_view(shot.state, meshes, renderer, target));
    const bool equal = same(dir + "/" + shot.file, images.back());
    std::printf("%s: %s\n", shot.file.c_str(), equal ? "equal to the library's image" : "DIFFERS");
    ok &= equal;
  }
  // The model, the dropped model and the spheres are three different pictures.
  if (images[0].rgba == images[2].rgba || images[2].rgba == images[3].rgba || images[0].rgba == images[3].rgba) {
    std::fprintf(stderr, "the boxes, the wedge and the spheres do not all differ\n");
    ok = false;
  }
  return ok ? 0 : 1;
}

int main(int argc, char** argv) {
  if (argc == 5 && std::string(argv[1]) == "--models") {
    try {
      return check_models(argv[2], argv[3], argv[4]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "e2e_check: %s\n", e.what());
      return 1;
    }
  }
  if (argc != 3) {
    std::fprintf(stderr, "usage: e2e_check OUT_DIR TETRAHEDRON_OBJ\n");
    return 2;
  }
  const std::string dir = argv[1];
  try {
    std::vector<std::string> warnings;
    const auto meshes = viewer::load_meshes(SOFTPBR_ASSETS_DIR, {argv[2]}, warnings);
    // 3 threads and 16-pixel tiles here, 1 thread and 64-pixel tiles in the viewer
    // (run_e2e.sh): the images must not depend on either.
    raster::Renderer renderer({.threads = 3, .tile_size = 16});
    raster::Target target(kWidth, kHeight);
    bool ok = true;

    // The first screenshot is the paper's gallery exactly as pbr::make_gallery() builds it.
    pbr::render(pbr::make_gallery(), renderer, target);
    ok &= same(dir + "/0_gallery.png", pbr::tone_map_to_rgba8(target, pbr::gallery_output()));

    std::vector<raster::Image8> images;
    for (const Shot& shot : expected_shots()) {
      images.push_back(viewer::render_view(shot.state, meshes, renderer, target));
      const bool equal = same(dir + "/" + shot.file, images.back());
      std::printf("%s: %s\n", shot.file.c_str(), equal ? "equal to the library's image" : "DIFFERS");
      ok &= equal;
    }
    // Each step of the session changes the picture (else the test could pass vacuously).
    for (std::size_t i = 1; i + 1 < images.size(); ++i)  // the last two show one state
      if (images[i].rgba == images[i - 1].rgba) {
        std::fprintf(stderr, "screenshot %zu shows the same image as screenshot %zu\n", i, i - 1);
        ok = false;
      }
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "e2e_check: %s\n", e.what());
    return 1;
  }
}
