// Scene files (pbr::load_scene_file / parse_scene_file): what valid files build, and that
// every invalid value is one line naming the file, the JSON pointer and what was expected.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>

#include "softpbr/dmath/dmath.h"
#include "softpbr/loaders/obj.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/gallery.h"
#include "softpbr/pbr/shading.h"
#include "softpbr/raster/raster.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

const fs::path kScenes = fs::path(SOFTPBR_SOURCE_DIR) / "examples/scenes";

pbr::SceneFile parse(const std::string& text, const pbr::SceneLoadOptions& options = {}) {
  return pbr::parse_scene_file(text, "t.json", kScenes, options);
}

// The message parse() throws, or "" when it does not throw.
std::string error_of(const std::string& text, const pbr::SceneLoadOptions& options = {}) {
  try {
    parse(text, options);
  } catch (const pbr::SceneFileError& e) {
    return e.what();
  }
  return "";
}

// A scene with one cube and one point light; `object` and `extra` are spliced in.
std::string scene(const std::string& object = R"("mesh": {"type": "cube"})", const std::string& extra = "") {
  return R"({"lights": [{"type": "point", "position": [1, 2, 3]}], "objects": [{)" + object + "}]" +
         (extra.empty() ? "" : ", " + extra) + "}";
}

std::uint64_t render_hash(const pbr::Scene& scene, int width, int height) {
  raster::Renderer renderer({.threads = 2, .tile_size = 64});
  raster::Target target(width, height);
  pbr::render(scene, renderer, target);
  return raster::hash_colors(target);
}

bool near(glm::vec3 a, glm::vec3 b, float tolerance) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(tolerance)));
}

}  // namespace

TEST_CASE("scene file: each invalid value gives one line with the file, the JSON pointer and what was expected") {
  struct Case {
    std::string text, message;
  };
  const std::vector<Case> cases = {
      {scene(R"("mesh": {"type": "cube"}, "material": {"roughness": 2})"),
       "t.json: /objects/0/material/roughness: expected a number in [0, 1], got 2"},
      {scene(R"("mesh": {"type": "cube"}, "material": {"metallic": "NaN"})"),
       "t.json: /objects/0/material/metallic: expected a number in [0, 1], got \"NaN\""},
      {scene(R"("mesh": {"type": "cube"}, "material": {"base_color": [1, 0.5]})"),
       "t.json: /objects/0/material/base_color: expected an array of 3 numbers in [0, 1], got [1,0.5]"},
      {scene(R"("mesh": {"type": "cube", "size": 0})"),
       "t.json: /objects/0/mesh/size: expected a number > 0, got 0"},
      {scene(R"("mesh": {"type": "uv_sphere", "segments": 2})"),
       "t.json: /objects/0/mesh/segments: expected an integer in [3, 4096], got 2"},
      {scene(R"("mesh": {"type": "torus", "major": 1, "minor": 2})"),
       "t.json: /objects/0/mesh/minor: a torus needs minor < major (2 >= 1)"},
      {scene(R"("mesh": {"type": "cube"}, "transform": {"scale": 0})"),
       "t.json: /objects/0/transform/scale: expected a number > 0, got 0"},
      {scene(R"("mesh": {"type": "cube"}, "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]})"),
       "t.json: /objects/0/transform/matrix/3: expected the last row to be [0, 0, 0, 1] (an affine transform), got [0,0,1,1]"},
      {scene(R"("mesh": {"type": "cube"}, "transform": {"matrix": [[1,0,0,0],[0,0,0,0],[0,0,1,0],[0,0,0,1]]})"),
       "t.json: /objects/0/transform/matrix: expected an invertible matrix, its 3x3 part has determinant 0"},
      {scene(R"("mesh": {"type": "cube"}, "transform": {"translate": [0, 0, 1e39]})"),
       "t.json: /objects/0/transform/translate/2: expected a number at most 1e+30 in magnitude, got 1e+39"},
      {scene(R"("mesh": {"radius": 1})"),
       "t.json: /objects/0/mesh: missing key \"type\" (a procedural shape) or \"file\" (an OBJ model)"},
      {scene(R"("mesh": {"type": "cube"}, "material": {"preset": 3})"),
       "t.json: /objects/0/material/preset: expected a preset name, got 3"},
      {scene(R"("mesh": "box")"), "t.json: /objects/0/mesh: no mesh named \"box\" in /meshes"},
      {scene(R"("mesh": {"file": ""})"), "t.json: /objects/0/mesh/file: expected a file name, got \"\""},
      {scene(R"("mesh": {"type": "cube"}, "colour": 1)"),
       "t.json: /objects/0/colour: unknown key \"colour\" (expected one of: name, mesh, material, transform, cast_shadows, receive_shadows)"},
      {scene(R"("mesh": {"type": "cube"})", R"("camera": {"fov": 180})"),
       "t.json: /camera/fov: expected a number in (0, 180), got 180"},
      {scene(R"("mesh": {"type": "cube"})", R"("camera": {"position": [0, 1, 0], "target": [0, 0, 0]})"),
       "t.json: /camera: camera up: must not be zero or parallel to the view direction"},
      {scene(R"("mesh": {"type": "cube"})", R"("camera": {"position": [0, 1, 1e30]})"),
       "t.json: /camera: camera position: must be less than 1e19 from the target (the view matrix squares the "
       "distance in float)"},
      {scene(R"("mesh": {"type": "cube"})", R"("camera": {"distance": 1e19})"),
       "t.json: /camera/distance: expected a number in (0, 1e+18], got 1e+19"},
      {scene(R"("mesh": {"type": "cube"})", R"("camera": {"position": [0, 1, 1e400]})"),
       "t.json: /camera/position/2: the number 1e400 is out of range (beyond +-1.8e308)"},
      {scene(R"("mesh": {"type": "cube"})", R"("camera": {"fov": -1e999})"),
       "t.json: /camera/fov: the number -1e999 is out of range (beyond +-1.8e308)"},
      {scene(R"("mesh": {"type": "cube"})", R"("render": {"tile_size": 31, "exposure": 1})"),
       "t.json: /render/tile_size: expected an even tile size, got 31"},
      {scene(R"("mesh": {"type": "cube"})", R"("render": {"gamma": "linear"})"),
       "t.json: /render/gamma: expected \"srgb\" or a number in [0.1, 10], got \"linear\""},
      {scene(R"("mesh": {"type": "cube"})", R"("animation": {"light_degrees_per_frame": 400})"),
       "t.json: /animation/light_degrees_per_frame: expected a number in [-360, 360], got 400"},
      {R"({"lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "inner_cone": 50, "outer_cone": 40}], "objects": []})",
       "t.json: /lights/0/inner_cone: expected inner_cone <= outer_cone (40), got 50"},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "direction": [0, -1, 0]}], "objects": []})",
       "t.json: /lights/0/direction: a point light has no \"direction\""},
      {R"({"lights": [{"type": "directional", "direction": [0, 0, 0]}], "objects": []})",
       "t.json: /lights/0/direction: expected a non-zero direction, got [0, 0, 0]"},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "intensity": 1e31}], "objects": []})",
       "t.json: /lights/0/intensity: expected a number >= 0 and at most 1e+30 in magnitude, got 1e+31"},
      {R"({"lights": [{"type": "point", "position": [0, 1, 0], "shadows": "yes"}], "objects": []})",
       "t.json: /lights/0/shadows: expected true or false, got \"yes\""},
      {scene(R"("mesh": {"type": "cube"}, "cast_shadows": 1)"), "t.json: /objects/0/cast_shadows: expected true or false, got 1"},
      {scene(R"("mesh": {"type": "cube"}, "receive_shadows": null)"),
       "t.json: /objects/0/receive_shadows: expected true or false, got null"},
      {R"({"lights": {}, "objects": []})", "t.json: /lights: expected an array, got an object"},
      {R"({"objects": [], "a/b~c": 1})",
       "t.json: /a~1b~0c: unknown key \"a/b~c\" (expected one of: camera, lights, ambient, environment, ground, meshes, objects, render, animation)"},
      {R"({"lights": []})", "t.json: (top level): missing key \"objects\""},
      {R"({"objects": [{"mesh": {"type": "cube"}}, {"mesh": {"type": "cube"}, "material": {"roughness": 0.2, "roughness": 2}}]})",
       "t.json: /objects/1/material/roughness: duplicate key \"roughness\" (each key may appear once per object)"},
      {std::string(R"({"objects": [{"mesh": )") + std::string(100000, '[') + std::string(100000, ']') + "}]}",
       "t.json: /objects/0/mesh" + [] {
         std::string p;  // 32 open values: the root, objects, objects/0, then 29 arrays
         for (int i = 0; i < 29; ++i) p += "/0";
         return p;
       }() + ": nested deeper than 32 levels"},
      {"{\"objects\": [], \"a\\nb\": 1}",
       "t.json: /a?b: unknown key \"a?b\" (expected one of: camera, lights, ambient, environment, ground, meshes, objects, render, animation)"},
      {R"({"objects": [], "objects": []})", "t.json: /objects: duplicate key \"objects\" (each key may appear once per object)"},
      {R"([1, 2])", "t.json: (top level): expected an object, got [1,2]"},
      {R"({"objects": [}")", "t.json: invalid JSON: parse error at line 1, column 14: syntax error while parsing value - unexpected '}'; expected '[', '{', or a literal"},
  };
  for (const Case& c : cases) {
    const std::string shown = c.text.size() > 300 ? c.text.substr(0, 300) + "..." : c.text;
    CAPTURE(shown);
    CHECK(error_of(c.text) == c.message);
  }
}

TEST_CASE("scene file: a 10^6-light scene is refused by its count, with the limit, before any light is read") {
  std::string lights = "[";
  for (int i = 0; i < 1000000; ++i) lights += i ? ",0" : "0";
  lights += "]";
  CHECK(error_of(R"({"objects": [], "lights": )" + lights + "}") ==
        "t.json: /lights: too many entries: 1000000 (the limit is 256: every light is evaluated at every pixel)");
  // At the limit it loads.
  std::string ok = "[";
  for (std::size_t i = 0; i < pbr::kMaxLights; ++i) ok += std::string(i ? "," : "") + R"({"type": "point", "position": [0, 1, 0]})";
  CHECK(parse(R"({"objects": [], "lights": )" + ok + "]}").scene.lights.size() == pbr::kMaxLights);
}

TEST_CASE("scene file: the memory estimate counts each mesh's arrays and each draw as the rasterizer sizes it") {
  // One cube (24 vertices, 12 triangles) drawn twice: its MeshVertex and index arrays once,
  // and raster::draw_geometry_bytes for the PBR shader's varyings per draw.
  const pbr::SceneFile f = parse(scene(R"("mesh": "box"}, {"mesh": "box")", R"("meshes": {"box": {"type": "cube"}})"));
  REQUIRE(f.scene.objects.size() == 2);
  const std::uint64_t mesh = 24 * sizeof(pbr::MeshVertex) + 12 * 3 * sizeof(std::uint32_t);
  const std::uint64_t draw = raster::draw_geometry_bytes(24, 12, raster::kVaryingCount<pbr::PbrShader::Varyings>);
  CHECK(f.mesh_bytes == mesh + 2 * draw);
  // A draw holds at least the set-up triangles and the clip-space positions.
  CHECK(draw >= 12 * sizeof(raster::Triangle) + 24 * sizeof(glm::vec4));
}

TEST_CASE("scene file: the memory a mesh needs is checked against the limit before the mesh is built") {
  const std::string big = scene(R"("mesh": {"type": "uv_sphere", "segments": 4096, "rings": 4096})");
  CHECK(error_of(big, {.memory_limit = std::uint64_t{64} << 20}) ==
        "t.json: /objects/0/mesh: this mesh brings the scene's estimated memory to 896.3 MiB, over the limit of 64.0 MiB");
  // Drawing counts too: each object that draws a shared mesh adds its draw buffers.
  const pbr::SceneFile one = parse(scene(R"("mesh": {"type": "icosphere", "subdivisions": 3})"));
  const pbr::SceneFile two = parse(scene(R"("mesh": {"type": "icosphere", "subdivisions": 3}}, {"mesh": {"type": "icosphere", "subdivisions": 3})"));
  CHECK(two.mesh_bytes > one.mesh_bytes);
  CHECK(two.scene.objects[0].mesh == two.scene.objects[1].mesh);  // the same spec builds one mesh
  CHECK(pbr::image_memory(16384, 16384) > pbr::kDefaultMemoryLimit);
}

TEST_CASE("scene file: gallery.json and gallery_spot.json render make_gallery's images bit for bit") {
  const pbr::SceneFile gallery = pbr::load_scene_file(kScenes / "gallery.json");
  CHECK(gallery.render.width == 1280);
  CHECK(gallery.render.output.tone_map == pbr::ToneMap::Reinhard);
  CHECK(gallery.render.output.gamma == pbr::gallery_output().gamma);
  CHECK(render_hash(gallery.scene, 320, 180) == render_hash(pbr::make_gallery(), 320, 180));

  const pbr::SceneFile spot = pbr::load_scene_file(kScenes / "gallery_spot.json");
  pbr::GalleryOptions o;
  o.mesh = std::make_shared<pbr::Mesh>(
      pbr::merge_shapes(pbr::load_obj(fs::path(SOFTPBR_SOURCE_DIR) / "assets/models/spot/spot_triangulated.obj")));
  CHECK(render_hash(spot.scene, 320, 180) == render_hash(pbr::make_gallery(o), 320, 180));
}

TEST_CASE("scene file: every example scene loads without warnings") {
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    CAPTURE(entry.path());
    const pbr::SceneFile f = pbr::load_scene_file(entry.path());
    CHECK(!f.scene.objects.empty());
    CHECK(f.warnings.empty());
  }
}

TEST_CASE("scene file: transforms are T·Rz·Ry·Rx·S, matrices are written row by row") {
  const pbr::SceneFile f = parse(scene(
      R"("mesh": {"type": "cube"}, "transform": {"translate": [1, 2, 3], "rotate": [0, 90, 0], "scale": [2, 1, 1]}}, )"
      R"({"mesh": {"type": "cube"}, "transform": {"matrix": [[1, 0, 0, 5], [0, 2, 0, 6], [0, 0, 3, 7], [0, 0, 0, 1]]})"));
  const glm::mat4& trs = f.scene.objects[0].transform;
  // (1, 0, 0) → scale → (2, 0, 0) → 90° about y → (0, 0, −2) → translate → (1, 2, 1).
  CHECK(near(glm::vec3(trs * glm::vec4(1, 0, 0, 1)), {1, 2, 1}, 1e-6f));
  const glm::mat4& m = f.scene.objects[1].transform;
  CHECK(glm::vec3(m * glm::vec4(1, 1, 1, 1)) == glm::vec3(6, 8, 10));
}

TEST_CASE("scene file: an OBJ without a material keeps its MTL materials, with one, its shapes merge") {
  const pbr::SceneFile own = parse(scene(R"("mesh": {"file": "models/podium.obj"})"));
  REQUIRE(own.scene.objects.size() == 3);  // base, pyramid, gem
  CHECK(own.scene.objects[1].material.metallic == 1.0f);  // brass
  CHECK(own.scene.objects[2].material.emissive.r == 4.0f);  // glow
  const pbr::SceneFile one = parse(scene(R"("mesh": {"file": "models/podium.obj", "fit": 1}, "material": "gold")"));
  REQUIRE(one.scene.objects.size() == 1);
  CHECK(one.scene.objects[0].mesh->triangle_count() == 24);
  // fit 1: the 2.05-unit-tall model is scaled to 1 and centred.
  const pbr::Bounds b = pbr::bounds(*one.scene.objects[0].mesh);
  const glm::vec3 top = glm::vec3(one.scene.objects[0].transform * glm::vec4(b.max, 1));
  CHECK(top.y == doctest::Approx(0.5f));
  CHECK(error_of(scene(R"("mesh": {"file": "models/missing.obj"})")) ==
        "t.json: /objects/0/mesh/file: " + (kScenes / "models/missing.obj").string() + ": cannot open: no such file");
}

TEST_CASE("scene file: lights and cameras take degrees, spot cones become radians") {
  const pbr::SceneFile f = parse(R"({"camera": {"target": [0, 1, 0], "distance": 4, "yaw": 90, "pitch": 0, "fov": 60},
    "lights": [{"type": "spot", "position": [0, 3, 0], "direction": [0, -1, 0], "inner_cone": 10, "outer_cone": 30}],
    "objects": []})");
  CHECK(f.scene.camera.fovy == static_cast<float>(softpbr::dmath::radians(60.0)));
  CHECK(near(f.scene.camera.position, {4, 1, 0}, 1e-5f));  // yaw 90° turns from +z to +x
  CHECK(f.scene.lights[0].outer_cone == static_cast<float>(softpbr::dmath::radians(30.0)));
  CHECK(f.scene.lights[0].type == pbr::LightType::Spot);
}

TEST_CASE("scene file: animate() leaves frame 0 as written and turns the camera and lights about y") {
  const pbr::SceneFile f = pbr::load_scene_file(kScenes / "turntable.json");
  const pbr::Scene s0 = pbr::animate(f, 0);
  CHECK(s0.camera.position == f.scene.camera.position);
  // 3°/frame for the camera: 120 frames are a full turn, 30 a quarter turn.
  const pbr::Scene full = pbr::animate(f, 120);
  CHECK(near(full.camera.position, f.scene.camera.position, 1e-5f));
  const pbr::Scene quarter = pbr::animate(f, 30);
  const glm::vec3 d0 = f.scene.camera.position - f.scene.camera.target, d1 = quarter.camera.position - quarter.camera.target;
  CHECK(glm::dot(glm::vec2(d0.x, d0.z), glm::vec2(d1.x, d1.z)) == doctest::Approx(0.0f).epsilon(1e-5));
  CHECK(d1.y == d0.y);
  // 6°/frame for the lights: frame 30 is half a turn about the origin.
  CHECK(near(quarter.lights[0].position, f.scene.lights[0].position * glm::vec3(-1, 1, -1), 1e-5f));
  // The same frame twice gives the same bits.
  CHECK(render_hash(pbr::animate(f, 7), 64, 48) == render_hash(pbr::animate(f, 7), 64, 48));
  CHECK(render_hash(pbr::animate(f, 7), 64, 48) != render_hash(pbr::animate(f, 8), 64, 48));
}

TEST_CASE("scene file: unreadable, missing and oversized files are refused with the path") {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "scene-file-test";
  fs::create_directories(dir);
  auto message = [](const fs::path& p) -> std::string {
    try {
      pbr::load_scene_file(p);
    } catch (const pbr::SceneFileError& e) {
      return e.what();
    }
    return "";
  };
  CHECK(message(dir / "missing.json") == (dir / "missing.json").string() + ": cannot open the scene file: No such file or directory");
  CHECK(message(dir) == dir.string() + ": is a folder, not a scene file");
  const fs::path big = dir / "big.json";
  {
    std::ofstream out(big);
    out << "{\"objects\": [], \"ambient\": [0, 0, 0]" << std::string(pbr::kMaxSceneFileBytes + (1u << 20), ' ') << "}";
  }
  CHECK(message(big) == big.string() + ": the scene file is 65.0 MiB, over the limit of 64.0 MiB (meshes belong in OBJ files)");
  fs::remove(big);
}

TEST_CASE("scene file: lights say \"shadows\" (off by default), objects \"cast_shadows\" and \"receive_shadows\" (on)") {
  const pbr::SceneFile off = parse(scene());
  CHECK_FALSE(off.scene.lights.at(0).shadows);
  CHECK(off.scene.objects.at(0).cast_shadows);
  CHECK(off.scene.objects.at(0).receive_shadows);
  const pbr::SceneFile on = parse(R"({"lights": [{"type": "directional", "direction": [0, -1, 0], "shadows": true}],
      "objects": [{"mesh": {"type": "cube"}, "cast_shadows": false, "receive_shadows": false}]})");
  CHECK(on.scene.lights.at(0).shadows);
  CHECK_FALSE(on.scene.objects.at(0).cast_shadows);
  CHECK_FALSE(on.scene.objects.at(0).receive_shadows);
}
