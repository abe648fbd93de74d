// Viewer state → scene → image: the gallery mode is the paper's gallery, preset mode one
// object, and every part of the state reaches the picture.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/raster/raster.h"
#include "viewer_scene.h"

using namespace viewer;
namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;

namespace {
const std::vector<NamedMesh>& meshes() {
  static const std::vector<NamedMesh> m = [] {
    std::vector<std::string> warnings;
    return load_meshes(SOFTPBR_ASSETS_DIR, {}, warnings);
  }();
  return m;
}

std::uint64_t image_hash(const ViewerState& s, int w = 96, int h = 54) {
  raster::Renderer renderer({.threads = 2});
  raster::Target target(w, h);
  render_view(s, meshes(), renderer, target);
  return raster::hash_colors(target);
}
}  // namespace

TEST_CASE("the mesh list is the sphere grid then spot then the teapot then a torus and a cube then OBJ files and a bad OBJ names the file") {
  REQUIRE(meshes().size() == 5);
  CHECK(meshes()[0].name == "spheres");
  CHECK(meshes()[0].mesh == nullptr);
  CHECK(meshes()[1].name == "spot");
  CHECK(meshes()[1].mesh->triangle_count() == 5856);
  CHECK(meshes()[2].name == "teapot");
  CHECK(meshes()[2].mesh->triangle_count() == 15704);
  CHECK(meshes()[3].name == "torus");
  CHECK(meshes()[4].name == "cube");
  CHECK(meshes()[4].mesh->triangle_count() == 12);
  std::vector<std::string> warnings;
  try {
    load_meshes(SOFTPBR_ASSETS_DIR, {"/nonexistent/cow.obj"}, warnings);
    FAIL("expected a LoadError");
  } catch (const pbr::LoadError& e) {
    CHECK(std::string(e.what()).find("/nonexistent/cow.obj") != std::string::npos);
  }
}

TEST_CASE("the starting state renders the paper's gallery bit for bit") {
  raster::Renderer renderer({.threads = 2});
  raster::Target direct(96, 54);
  pbr::render(pbr::make_gallery(), renderer, direct);
  CHECK(image_hash(ViewerState{}) == raster::hash_colors(direct));
}

TEST_CASE("with MSAA the viewer's transient target shows the image of a kept one, frame after frame") {
  ViewerState s;
  s.msaa = 4;
  raster::Renderer renderer({.threads = 2});
  raster::Target kept(96, 54, 4);
  const raster::Image8 want = render_view(s, meshes(), renderer, kept);
  raster::Target transient(96, 54, 4, nullptr, raster::SampleStorage::Transient);
  for (int frame = 0; frame < 2; ++frame) CHECK(render_view(s, meshes(), renderer, transient).rgba == want.rgba);
  // main.cpp's: the render job's frame, its transient target kept from frame to frame.
  softpbr::job::Frame job_frame;
  for (int frame = 0; frame < 2; ++frame)
    CHECK(render_view(s, meshes(), renderer, job_frame, 96, 54).rgba == want.rgba);
  // (At 96×54 the gallery's geometry outweighs the planes, so the frame runs in passes and
  // the target makes its planes; at window sizes it draws in tile blocks alone.)
  raster::Target one(96, 54);
  CHECK(render_view(s, meshes(), renderer, one).rgba != want.rgba);  // the 1x image differs at edges
}

TEST_CASE("preset mode draws one object in the preset's colour with the state's roughness and metallic") {
  for (std::size_t mesh = 0; mesh < meshes().size(); ++mesh) {
    ViewerState s;
    s.mesh_count = meshes().size();
    s.mesh = mesh;
    select_material(s, 1);  // copper
    s.roughness_steps = 13;
    s.metallic = false;
    const pbr::Scene scene = build_scene(s, meshes());
    REQUIRE(scene.objects.size() == 1);
    const pbr::Object& o = scene.objects[0];
    CHECK(o.material.base_color == pbr::material_preset("copper")->base_color);
    CHECK(o.material.roughness == 0.65f);
    CHECK(o.material.metallic == 0.0f);
    // Fitted into a cube of 0.8 · kSingleObjectScale, centred on the origin, then turned
    // about y (gallery.h): y extents scale by the fit, and y is centred.
    const pbr::Mesh sphere = pbr::uv_sphere(0.4f, 64, 32);
    const pbr::Mesh& m = o.mesh ? *o.mesh : sphere;
    const pbr::Bounds before = pbr::bounds(m);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const pbr::MeshVertex& v : m.vertices) {
      const glm::vec3 p = glm::vec3(o.transform * glm::vec4(v.position, 1.0f));
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const glm::vec3 e = before.extent();
    const float fit = 0.8f * kSingleObjectScale / std::max({e.x, e.y, e.z});
    CHECK((hi.y - lo.y) == doctest::Approx(e.y * fit).epsilon(1e-5));
    CHECK(std::abs(lo.y + hi.y) < 1e-5f);
    if (!o.mesh) CHECK((hi.x - lo.x) == doctest::Approx(0.8f * kSingleObjectScale).epsilon(1e-5));
  }
}

TEST_CASE("the camera is the state's fly camera and the lights turn about y by the light angle") {
  ViewerState s;
  s.camera.move(1.0f, 0.5f, 0.25f);
  s.camera.turn(0.3f, -0.2f);
  s.light_angle = 1.5707963267948966f;  // a quarter turn
  const pbr::Scene scene = build_scene(s, meshes());
  CHECK(scene.camera.position == s.camera.position);
  CHECK(scene.camera.target == s.camera.position + s.camera.front());
  const pbr::Scene still = pbr::make_gallery();
  REQUIRE(scene.lights.size() == still.lights.size());
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    // A quarter turn about +y takes (x, y, z) to (z, y, −x).
    const glm::vec3 p = still.lights[i].position, q = scene.lights[i].position;
    CHECK(q.x == doctest::Approx(p.z).epsilon(1e-6));
    CHECK(q.y == p.y);
    CHECK(q.z == doctest::Approx(-p.x).epsilon(1e-6));
  }
}

TEST_CASE("every part of the state changes the image") {
  const ViewerState base = [] {
    ViewerState s;
    s.mesh_count = meshes().size();
    select_material(s, 0);
    return s;
  }();
  const std::uint64_t h0 = image_hash(base);
  struct Change {
    const char* what;
    void (*change)(ViewerState&);
  };
  const Change changes[] = {
      {"material", [](ViewerState& s) { select_material(s, 1); }},
      {"gallery", [](ViewerState& s) { select_material(s, kGalleryMaterial); }},
      {"roughness", [](ViewerState& s) { s.roughness_steps += 4; }},
      {"metallic", [](ViewerState& s) { s.metallic = false; }},
      {"mesh", [](ViewerState& s) { s.mesh = 1; }},
      {"camera", [](ViewerState& s) { s.camera.move(1.0f, 0.0f, 0.0f); }},
      {"lights", [](ViewerState& s) { s.light_angle = 1.0f; }},
  };
  for (const Change& c : changes) {
    CAPTURE(c.what);
    ViewerState s = base;
    c.change(s);
    CHECK(image_hash(s) != h0);
  }
}

TEST_CASE("H's ground puts a shadow under the gallery's spheres") {
  ViewerState s;
  s.mesh_count = meshes().size();
  select_material(s, kGalleryMaterial);
  const std::uint64_t without = image_hash(s);
  s.shadows = true;
  const pbr::Scene lit = build_scene(s, meshes());
  s.ground = true;
  const pbr::Scene grounded = build_scene(s, meshes());
  CHECK_FALSE(lit.ground.shadow);
  CHECK(grounded.ground.shadow);
  CHECK(image_hash(s) != without);
}

TEST_CASE("material labels name the preset with roughness and metallic or the gallery") {
  ViewerState s;
  CHECK(material_label(s) == "gallery");
  select_material(s, 0);
  CHECK(material_label(s) == "gold r 0.30 metal");
  s.metallic = false;
  s.roughness_steps = 1;
  CHECK(material_label(s) == "gold r 0.05 dielectric");
}

TEST_CASE("B cycles the environments: none, the studio, the --env maps, the scene is lit by the chosen one") {
  viewer::ViewerState s;
  const viewer::Environments envs = viewer::load_environments({}, nullptr);
  REQUIRE(envs.size() == 2);
  CHECK(envs[0] == nullptr);
  s.environment_count = envs.size();
  std::vector<std::string> warnings;
  const auto meshes = viewer::load_meshes(SOFTPBR_ASSETS_DIR, {}, warnings);
  CHECK(viewer::build_scene(s, meshes, envs).environment.map == nullptr);
  viewer::apply(s, viewer::KeyDown{viewer::Key::B});
  CHECK(s.environment == 1);
  const softpbr::pbr::Scene lit = viewer::build_scene(s, meshes, envs);
  CHECK(lit.environment.map == softpbr::pbr::Environment::studio());
  CHECK(lit.background_mode == softpbr::pbr::BackgroundMode::Environment);
  viewer::apply(s, viewer::KeyUp{viewer::Key::B});  // a second press, not the key held
  viewer::apply(s, viewer::KeyDown{viewer::Key::B});
  CHECK(s.environment == 0);  // back to none
}

TEST_CASE("glTF models join the mesh list after the OBJ files' place, drawn alone with their own materials, fitted") {
  const std::filesystem::path dir = VIEWER_TESTS_DIR;
  std::vector<std::string> warnings;
  raster::ThreadPool pool(2);
  const auto list = load_meshes(SOFTPBR_ASSETS_DIR, {dir / "boxes.gltf", dir / "tetrahedron.obj", dir / "wedge.gltf"}, warnings, &pool);
  CHECK(warnings.empty());
  REQUIRE(list.size() == 8);
  CHECK(list[5].name == "boxes");
  CHECK(list[5].mesh == nullptr);
  REQUIRE(list[5].model.size() == 2);
  CHECK(list[6].name == "tetrahedron");
  CHECK(list[6].model.empty());
  CHECK(list[7].name == "wedge");
  REQUIRE(list[7].model.size() == 1);
  ViewerState s;
  s.mesh_count = list.size();
  s.mesh = 5;
  const pbr::Scene scene = build_scene(s, list);
  REQUIRE(scene.objects.size() == 2);
  CHECK(scene.objects[0].material.base_color == glm::vec3(0.9f, 0.1f, 0.1f));
  CHECK(scene.objects[0].material.metallic == 1.0f);
  CHECK(scene.objects[1].material.base_color == glm::vec3(0.1f, 0.8f, 0.2f));
  CHECK(scene.lights.size() == pbr::make_gallery().lights.size());
  // Fitted: the bounding sphere centred on the origin with a diameter of 2.4 units.
  const pbr::Bounds b = pbr::world_bounds(scene.objects);
  const glm::vec3 centre = (b.min + b.max) * 0.5f;
  CHECK(glm::length(centre) < 1e-5f);
  CHECK(glm::length(b.max - b.min) == doctest::Approx(0.8f * kSingleObjectScale).epsilon(1e-5));
  // The material keys do not change a model; M and the mesh do.
  const std::uint64_t boxes = [&] {
    raster::Renderer renderer({.threads = 2});
    raster::Target target(96, 54);
    render_view(s, list, renderer, target);
    return raster::hash_colors(target);
  }();
  ViewerState preset = s;
  select_material(preset, 2);
  ViewerState wedge = s;
  wedge.mesh = 7;
  raster::Renderer renderer({.threads = 1});
  raster::Target target(96, 54);
  render_view(preset, list, renderer, target);
  CHECK(raster::hash_colors(target) == boxes);
  render_view(wedge, list, renderer, target);
  CHECK(raster::hash_colors(target) != boxes);
  // A bad model names the file and the JSON pointer.
  try {
    std::vector<std::string> w;
    load_model("/nonexistent/model.glb", w);
    FAIL("expected a LoadError");
  } catch (const pbr::LoadError& e) {
    CHECK(std::string(e.what()).rfind("/nonexistent/model.glb: ", 0) == 0);
  }
}

TEST_CASE("G cycles a glTF model's material variants: the default, each variant in order, the default again") {
  const std::filesystem::path dir = VIEWER_TESTS_DIR;
  std::vector<std::string> warnings;
  NamedMesh entry = load_model(dir / "variants.gltf", warnings);
  CHECK(warnings.empty());
  REQUIRE(entry.variants == std::vector<std::string>{"blue", "green"});
  CHECK(entry.variant == 0);
  CHECK(variant_label(entry).empty());
  REQUIRE(entry.model.size() == 1);
  const glm::mat4 fitted = entry.model[0].transform;
  CHECK(entry.model[0].material.base_color == glm::vec3(0.3f));
  // G asks the shell for the next variant.
  ViewerState s;
  CHECK(apply(s, KeyDown{Key::G}) == Effect::NextVariant);
  const glm::vec3 expected[] = {glm::vec3(0.1f, 0.2f, 0.9f), glm::vec3(0.1f, 0.8f, 0.2f), glm::vec3(0.3f)};
  const char* labels[] = {"variant blue", "variant green", ""};
  for (int step = 0; step < 3; ++step) {
    CAPTURE(step);
    REQUIRE(next_variant(entry, warnings));
    CHECK(entry.variant == static_cast<std::size_t>((step + 1) % 3));
    CHECK(variant_label(entry) == labels[step]);
    CHECK(entry.name == "variants");
    REQUIRE(entry.model.size() == 1);
    CHECK(entry.model[0].material.base_color == expected[step]);
    CHECK(entry.model[0].transform == fitted);  // the same fit: variants change materials only
  }
  // The shown variant reaches the picture.
  std::vector<NamedMesh> list{entry};
  ViewerState shown;
  shown.mesh_count = 1;
  const auto hash = [&] {
    raster::Renderer renderer({.threads = 1});
    raster::Target target(64, 48);
    render_view(shown, list, renderer, target);
    return raster::hash_colors(target);
  };
  const std::uint64_t default_look = hash();
  REQUIRE(next_variant(list[0], warnings));
  CHECK(hash() != default_look);
  // A model without variants: G changes nothing.
  NamedMesh wedge = load_model(dir / "wedge.gltf", warnings);
  CHECK(wedge.variants.empty());
  CHECK_FALSE(next_variant(wedge, warnings));
  CHECK(wedge.variant == 0);
}
