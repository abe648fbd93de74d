// glTF 2.0 loading: the Khronos sample models of ../shared/gltf load and render (skipped
// when the folder is absent); renders go to build/gltf-output/ for looking at.
#include "shared_assets.h"
#include "softpbr/golden/doctest_checks.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "softpbr/image/write.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/pbr/environment.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/raster.h"
#include "shared_assets.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;

namespace {

fs::path shared_gltf() { return shared_assets::folder() / "gltf"; }

// The model file of a sample folder: its glTF-Binary .glb, else its glTF .gltf.
fs::path model_file(const fs::path& folder) {
  for (const char* sub : {"glTF-Binary", "glTF", "glTF-KTX2-Basisu"}) {
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

namespace {

// Renders a shared sample model the way the command does (framing camera, light rig).
raster::Target render_sample(const std::string& name, const raster::RendererOptions& options, int w = 320, int h = 240) {
  const fs::path file = model_file(shared_gltf() / name);
  REQUIRE(!file.empty());
  raster::Renderer renderer(options);
  const pbr::GltfScene g = pbr::load_gltf(file, {.pool = &renderer.pool()});
  raster::Target target(w, h);
  pbr::render(scene_of(g, w, h), renderer, target);
  return target;
}

}  // namespace

TEST_CASE("golden glTF renders: normal maps with generated and with supplied (mirrored) tangents") {
  // Compared with the Khronos screenshots before committing: in every row the normal-mapped
  // hemisphere (left) is lit like the geometric one (right), and in the mirror test all
  // four columns (geometry, normal map, U-mirrored, V-mirrored) agree — a wrong tangent
  // handedness shows as bumps lit from the opposite side.
  if (!fs::is_directory(shared_gltf())) {
    MESSAGE("skipped: " << shared_gltf() << " is absent");
    return;
  }
  for (const std::string name : {"NormalTangentTest", "NormalTangentMirrorTest", "TextureCoordinateTest"}) {
    CAPTURE(name);
    const raster::Target t = render_sample(name, {.threads = 0});
    CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, pbr::OutputSettings{}), "goldens/gltf_" + name);
    // The same bits at other widths, thread counts and with dispatch off.
    for (int lanes : {1, 4, 16}) {
      CAPTURE(lanes);
      const raster::Target o = render_sample(name, {.threads = 2, .tile_size = 16, .lanes = lanes, .dispatch = lanes != 16});
      CHECK(raster::hash_colors(o) == raster::hash_colors(t));
    }
  }
}

TEST_CASE("golden glTF renders: LightsPunctualLamp's lights cast shadows (the lamp's shade on the wall and floor)") {
  // Compared with the Khronos screenshot before committing: the lamp's own lights (a spot
  // inside the shade, aimed down, and a point bulb) throw the shade's and the stand's
  // shadows; glTF lights cast shadows by default (docs/design.md, "Shadows").
  if (!fs::is_directory(shared_gltf())) {
    MESSAGE("skipped: " << shared_gltf() << " is absent");
    return;
  }
  const raster::Target t = render_sample("LightsPunctualLamp", {.threads = 0}, 320, 320);
  CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, pbr::OutputSettings{}), "goldens/gltf_LightsPunctualLamp");
  for (int lanes : {1, 4, 16}) {
    CAPTURE(lanes);
    const raster::Target o =
        render_sample("LightsPunctualLamp", {.threads = 2, .tile_size = 16, .lanes = lanes, .dispatch = lanes != 16}, 320, 320);
    CHECK(raster::hash_colors(o) == raster::hash_colors(t));
  }
  // The lights' shadows change the image (they are on by default).
  const pbr::GltfScene g = pbr::load_gltf(model_file(shared_gltf() / "LightsPunctualLamp"));
  REQUIRE(!g.lights.empty());
  for (const pbr::Light& l : g.lights) CHECK(l.shadows);
  pbr::Scene off = scene_of(g, 320, 320);
  for (pbr::Light& l : off.lights) l.shadows = false;
  raster::Renderer renderer({.threads = 0});
  raster::Target u(320, 320);
  pbr::render(off, renderer, u);
  CHECK(raster::hash_colors(u) != raster::hash_colors(t));
}

namespace {

// Renders the model in `file` as scene_of frames it at 320×240 in the studio, checks it
// against goldens/gltf_<name> and the same bits at other lane widths; no loader warning
// contains any of `never_warned`.
void check_studio_golden(const fs::path& file, const std::string& name, std::initializer_list<const char*> never_warned) {
  const auto render = [&](const raster::RendererOptions& options) {
    raster::Renderer renderer(options);
    const pbr::GltfScene g = pbr::load_gltf(file, {.pool = &renderer.pool()});
    for (const std::string& w : g.warnings)
      for (const char* word : never_warned) CHECK(w.find(word) == std::string::npos);
    pbr::Scene s = scene_of(g, 320, 240);
    s.environment.map = pbr::Environment::studio();
    raster::Target target(320, 240);
    pbr::render(s, renderer, target);
    return target;
  };
  const raster::Target t = render({.threads = 0});
  CHECK_RENDER_MATCHES(t, pbr::tone_map_to_rgba8(t, pbr::OutputSettings{}), "goldens/gltf_" + name);
  for (int lanes : {1, 4, 16}) {
    CAPTURE(lanes);
    const raster::Target o = render({.threads = 2, .tile_size = 16, .lanes = lanes, .dispatch = lanes != 16});
    CHECK(raster::hash_colors(o) == raster::hash_colors(t));
  }
}

}  // namespace

TEST_CASE("golden glTF renders: the material extensions' samples (clearcoat, sheen, specular) in the studio") {
  // Compared with the Khronos screenshots before committing: ClearcoatWicker's coat mirrors
  // the softboxes over the matte wicker, SheenCloth's fabric gains a pale rim where its
  // fibres face away, SpecularTest's spheres gain reflection along its specular rows.
  if (!fs::is_directory(shared_gltf())) {
    MESSAGE("skipped: " << shared_gltf() << " is absent");
    return;
  }
  for (const std::string name : {"ClearcoatWicker", "SheenCloth", "SpecularTest"}) {
    CAPTURE(name);
    check_studio_golden(model_file(shared_gltf() / name), name, {"not supported"});
  }
}

TEST_CASE("golden glTF renders: anisotropy and iridescence samples in the studio") {
  // Compared with the Khronos screenshots before committing: AnisotropyStrengthTest's
  // highlights stretch into arcs around the poles as the strength grows (rows) and widen with
  // the roughness (columns), AnisotropyRotationTest's disks all show the same streak along
  // their rims (tangents, texture, rotation and both agree), AnisotropyBarnLamp's copper
  // shows its brushed streaks (and, since transmission, its glass shade shows the bulb),
  // IridescenceSuzanne's metal head turns green with a magenta crown as in the screenshot
  // (its third material is transmissive).
  if (!fs::is_directory(shared_gltf())) {
    MESSAGE("skipped: " << shared_gltf() << " is absent");
    return;
  }
  const fs::path pending = shared_gltf().parent_path() / "gltf-pending";
  for (const std::string name : {"AnisotropyStrengthTest", "AnisotropyRotationTest"}) {
    CAPTURE(name);
    check_studio_golden(model_file(shared_gltf() / name), name, {"not supported"});
  }
  // Files that also use transmission and volume.
  // Not structured bindings: clang 14 cannot capture them in CAPTURE's lambda.
  for (const auto& sample : {std::pair{shared_gltf(), "AnisotropyBarnLamp"}, std::pair{pending, "IridescenceSuzanne"}}) {
    const fs::path& folder = sample.first;
    const char* name = sample.second;
    CAPTURE(name);
    if (!fs::is_directory(folder / name)) {
      MESSAGE("skipped: " << (folder / name) << " is absent");
      continue;
    }
    check_studio_golden(model_file(folder / name), name, {"anisotropy", "iridescence", "basisu"});
  }
}

TEST_CASE("golden glTF renders: transmission and volume samples in the studio") {
  // Compared with the Khronos screenshots before committing (docs/design.md, "Shading").
  if (!fs::is_directory(shared_gltf())) {
    MESSAGE("skipped: " << shared_gltf() << " is absent");
    return;
  }
  // (TransmissionTest lists KHR_xmp, metadata, which is warned about: no material extension is.)
  for (const std::string name : {"TransmissionTest", "TransmissionRoughnessTest", "AttenuationTest"}) {
    CAPTURE(name);
    check_studio_golden(model_file(shared_gltf() / name), name, {"KHR_materials"});
  }
}

namespace {

// Writes `json` as a .gltf file in a fresh folder and returns its path.
fs::path write_gltf(const std::string& name, const std::string& json) {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf-hostile";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << json;
  return p;
}

// One triangle: 3 float positions (36 bytes) then 3 u16 indices (6 bytes, padded to 8), as a
// base64 data URI.
const char* kTriangleBuffer =
    R"("buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA="}])";

std::string triangle_gltf(const std::string& accessors, const std::string& extra = "") {
  return std::string(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    )") + kTriangleBuffer + ", " + accessors + extra + "}";
}

const char* kGoodAccessors =
    R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                     {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}])";

// The triangle with a third buffer view, `view`, holding a PNG image.
std::string image_in_view(const std::string& view) {
  std::string j = triangle_gltf(kGoodAccessors, R"(, "images": [{"bufferView": 2, "mimeType": "image/png"}])");
  const std::string last = R"("byteLength": 6})";
  return j.insert(j.find(last) + last.size(), ", " + view);
}

std::string load_error(const fs::path& p, const pbr::GltfOptions& options = {}) {
  try {
    pbr::load_gltf(p, options);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("a hand-written glTF triangle loads, hostile variants fail with the file and JSON pointer") {
  const fs::path good = write_gltf("good.gltf", triangle_gltf(kGoodAccessors));
  const pbr::GltfScene g = pbr::load_gltf(good);
  REQUIRE(g.objects.size() == 1);
  CHECK(g.triangles == 1);
  CHECK(g.objects[0].mesh->vertices[1].position == glm::vec3(1, 0, 0));
  // No NORMAL: flat normals, +z for this counter-clockwise triangle in z = 0.
  CHECK(g.objects[0].mesh->vertices[0].normal == glm::vec3(0, 0, 1));

  struct Case {
    std::string name;
    std::string json;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"past_view.gltf",
       triangle_gltf(R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
                     {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}])"),
       "past_view.gltf: /accessors/0: 4 elements of 12 bytes run past bufferView 0 (36 bytes)"},
      {"bad_index.gltf",
       triangle_gltf(R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 2, "type": "VEC3"},
                     {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}])"),
       "bad_index.gltf: /accessors/1: index 2 at element 2 is out of range (2 vertices)"},
      {"no_accessor.gltf",
       triangle_gltf(R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}])"),
       // tinygltf checks this reference itself while parsing; softpbr finds its pointer.
       "no_accessor.gltf: /meshes/0/primitives/0/indices: accessor 1 does not exist"},
      {"indices_no_view.gltf",
       triangle_gltf(R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                     {"componentType": 5123, "count": 3, "type": "SCALAR"}])"),
       "indices_no_view.gltf: /accessors/1: has no bufferView, which indices need (/meshes/0/primitives/0/indices)"},
      {"indices_bad_view.gltf",
       triangle_gltf(R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"},
                     {"bufferView": 9, "componentType": 5123, "count": 3, "type": "SCALAR"}])"),
       "indices_bad_view.gltf: /accessors/1/bufferView: bufferView 9 does not exist"},
      {"stride.gltf",
       [] {
         std::string j = triangle_gltf(kGoodAccessors);
         const std::string from = R"({"buffer": 0, "byteLength": 36})";
         return j.replace(j.find(from), from.size(), R"({"buffer": 0, "byteLength": 36, "byteStride": 6})");
       }(),
       "stride.gltf: /bufferViews/0/byteStride: must be a multiple of 4 in [4, 252], got 6"},
      {"required.gltf", triangle_gltf(kGoodAccessors, R"(, "extensionsRequired": ["EXT_softpbr_never_supported"], "extensionsUsed": ["EXT_softpbr_never_supported"])"),
       "required.gltf: /extensionsRequired/0: the required extension EXT_softpbr_never_supported is not supported"},
      {"cycle.gltf",
       std::string(R"({"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"children": [1]}, {"children": [0]}]})"),
       "cycle.gltf: /nodes/0: is its own ancestor (the node hierarchy has a cycle)"},
      {"not_json.gltf", "{ this is not json", "not_json.gltf: "},
      // An image in a buffer view that runs past its 44-byte buffer: tinygltf 2.7 hands its
      // image callback a pointer it never checked, which read past the buffer (fuzz_gltf).
      {"image_view_past.gltf",
       image_in_view(R"({"buffer": 0, "byteOffset": 8, "byteLength": 6548})"),
       "image_view_past.gltf: /images/0/bufferView: bufferView 2 (bytes 8 to 6556) does not lie inside its buffer of "
       "44 bytes"},
      {"image_view_offset.gltf",
       image_in_view(R"({"buffer": 0, "byteOffset": 4000000000, "byteLength": 4})"),
       "image_view_offset.gltf: /images/0/bufferView: bufferView 2 (bytes 4000000000 to 4000000004) does not lie "
       "inside its buffer of 44 bytes"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    const std::string message = load_error(write_gltf(c.name, c.json));
    CAPTURE(message);
    // The message starts with the path as given (the folder, then the name).
    CHECK(message.find(c.message) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("glTF JSON is checked in a streaming pass before it is parsed, and textures against the memory limit before decoding") {
  // glTF 2.0 §3.2: keys are unique within an object.
  const std::string dup = load_error(write_gltf("dup_key.gltf", triangle_gltf(kGoodAccessors, R"(, "scene": 0)")));
  CHECK(dup.find("dup_key.gltf: /scene: duplicate key \"scene\" (each key may appear once per object)") != std::string::npos);
  // 200000 nested arrays in extras overflowed the stack in tinygltf; the pointer is shortened.
  std::string deep = triangle_gltf(kGoodAccessors, R"(, "extras": )" + std::string(200000, '[') + std::string(200000, ']'));
  const std::string nested = load_error(write_gltf("deep.gltf", deep));
  CAPTURE(nested);
  CHECK(nested.find("deep.gltf: /extras/0/0/0/") != std::string::npos);
  CHECK(nested.find("/0/…/0/0/") != std::string::npos);
  CHECK(nested.find(": nested deeper than 256 levels") != std::string::npos);
  CHECK(nested.size() < 300);
  // 256 levels are allowed.
  CHECK_NOTHROW(pbr::load_gltf(write_gltf("deep_ok.gltf", triangle_gltf(kGoodAccessors, R"(, "extras": )" +
                                                                                            std::string(254, '[') +
                                                                                            std::string(254, ']')))));
  // The document tinygltf would build, estimated from the counts: 100 000 numbers in extras
  // (192 bytes a value) are over a 16 MiB limit, and fine at the default.
  std::string numbers = "[0";
  for (int i = 1; i < 100000; ++i) numbers += ",1";
  const fs::path big = write_gltf("big_json.gltf", triangle_gltf(kGoodAccessors, R"(, "extras": )" + numbers + "]"));
  const std::string over = load_error(big, {.memory_limit = std::uint64_t{16} << 20});
  CAPTURE(over);
  CHECK(over.find("big_json.gltf: parsing its JSON (1000") != std::string::npos);
  CHECK(over.find(" values) needs an estimated 18.") != std::string::npos);
  CHECK(over.find("MiB, over the memory limit of 16.0 MiB") != std::string::npos);
  CHECK_NOTHROW(pbr::load_gltf(big));
  // Textures: a 512×512 image is 1 MiB decoded, 1.33 MiB as a mip chain; with the decode
  // itself, 2.33 MiB are over a 2 MiB limit before anything is decoded.
  const fs::path dir = big.parent_path();
  softpbr::raster::Image8 picture{512, 512, std::vector<std::uint8_t>(512 * 512 * 4, 200)};
  softpbr::image::write_png(dir / "tex512.png", picture);
  const std::string textured = triangle_gltf(
      kGoodAccessors, R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
      "textures": [{"source": 0}], "images": [{"uri": "tex512.png"}])");
  std::string with_material = textured;
  with_material.replace(with_material.find(R"("indices": 1})"), 13, R"("indices": 1, "material": 0})");
  const fs::path tex = write_gltf("tex512.gltf", with_material);
  const std::string texture_over = load_error(tex, {.memory_limit = std::uint64_t{2} << 20});
  CAPTURE(texture_over);
  CHECK(texture_over.find("tex512.gltf: /images/0: its texture (512x512) brings the model's buffers and textures to an "
                          "estimated 2.3") != std::string::npos);
  CHECK(texture_over.find(" MiB, over the memory limit of 2.0 MiB") != std::string::npos);
  const pbr::GltfScene loaded = pbr::load_gltf(tex, {.memory_limit = std::uint64_t{3} << 20});
  REQUIRE(loaded.objects.size() == 1);
  CHECK(loaded.objects[0].material.base_color_texture.texture != nullptr);
}

TEST_CASE("glTF's schema is checked before tinygltf: required properties, JSON types and enums, with their JSON pointers") {
  // The textured triangle of a sampler, a texture, an image and a material, then one change each.
  const nlohmann::json base = nlohmann::json::parse(triangle_gltf(
      kGoodAccessors, R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
      "samplers": [{"magFilter": 9729}], "textures": [{"source": 0, "sampler": 0}],
      "images": [{"uri": "data:image/png;base64,iVBORw0KGgo="}])"));
  struct Case {
    const char* name;
    std::function<void(nlohmann::json&)> change;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"no_asset", [](nlohmann::json& g) { g.erase("asset"); }, "missing required property \"asset\""},
      {"version_number", [](nlohmann::json& g) { g["asset"]["version"] = 2; }, "/asset/version: must be a string, got 2"},
      {"no_count", [](nlohmann::json& g) { g["accessors"][0].erase("count"); },
       "/accessors/0: missing required property \"count\""},
      {"no_component_type", [](nlohmann::json& g) { g["accessors"][1].erase("componentType"); },
       "/accessors/1: missing required property \"componentType\""},
      {"vec7", [](nlohmann::json& g) { g["accessors"][0]["type"] = "VEC7"; },
       "/accessors/0/type: must be one of SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3, MAT4, got \"VEC7\""},
      {"component_type", [](nlohmann::json& g) { g["accessors"][0]["componentType"] = 5124; },
       "/accessors/0/componentType: must be one of 5120, 5121, 5122, 5123, 5125, 5126, got 5124"},
      {"no_byte_length", [](nlohmann::json& g) { g["buffers"][0].erase("byteLength"); },
       "/buffers/0: missing required property \"byteLength\""},
      {"view_no_buffer", [](nlohmann::json& g) { g["bufferViews"][1].erase("buffer"); },
       "/bufferViews/1: missing required property \"buffer\""},
      {"bad_base64", [](nlohmann::json& g) { g["buffers"][0]["uri"] = "data:application/octet-stream;base64,AA@A"; },
       "/buffers/0/uri: the data URI's base64 data has a character that is not base64 at byte 39 of the URI"},
      {"not_base64", [](nlohmann::json& g) { g["images"][0]["uri"] = "data:image/png,abc"; },
       "/images/0/uri: a data URI must be base64 (\"data:<type>;base64,<data>\")"},
      {"missing_bin", [](nlohmann::json& g) { g["buffers"][0]["uri"] = "nope.bin"; }, "/buffers/0/uri: nope.bin: no such file"},
      {"nodes_object", [](nlohmann::json& g) { g["nodes"] = {{"a", 1}}; }, "/nodes: must be an array, got {\"a\":1}"},
      {"node_string", [](nlohmann::json& g) { g["nodes"][0] = "node"; }, "/nodes/0: must be a JSON object, got \"node\""},
      {"translation", [](nlohmann::json& g) { g["nodes"][0]["translation"] = {1, 2}; },
       "/nodes/0/translation: must be an array of 3 numbers, got [1,2]"},
      {"child_string", [](nlohmann::json& g) { g["nodes"][0]["children"] = {"x"}; },
       "/nodes/0/children/0: must be an index (an integer >= 0), got \"x\""},
      {"source_string", [](nlohmann::json& g) { g["textures"][0]["source"] = "zero"; },
       "/textures/0/source: must be an index (an integer >= 0), got \"zero\""},
      {"mag_filter", [](nlohmann::json& g) { g["samplers"][0]["magFilter"] = "x"; },
       "/samplers/0/magFilter: must be one of 9728, 9729, got \"x\""},
      {"wrap", [](nlohmann::json& g) { g["samplers"][0]["wrapS"] = 10496; },
       "/samplers/0/wrapS: must be one of 33071, 33648, 10497, got 10496"},
      {"factor", [](nlohmann::json& g) { g["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1}; },
       "/materials/0/pbrMetallicRoughness/baseColorFactor: must be an array of 4 numbers, got [1,1]"},
      {"texture_index", [](nlohmann::json& g) { g["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"].erase("index"); },
       "/materials/0/pbrMetallicRoughness/baseColorTexture: missing required property \"index\""},
      {"alpha_mode", [](nlohmann::json& g) { g["materials"][0]["alphaMode"] = "blend"; },
       "/materials/0/alphaMode: must be one of OPAQUE, MASK, BLEND, got \"blend\""},
      {"no_primitives", [](nlohmann::json& g) { g["meshes"][0].erase("primitives"); },
       "/meshes/0: missing required property \"primitives\""},
      {"empty_primitives", [](nlohmann::json& g) { g["meshes"][0]["primitives"] = nlohmann::json::array(); },
       "/meshes/0/primitives: must be an array of at least one primitive, got []"},
      {"no_attributes", [](nlohmann::json& g) { g["meshes"][0]["primitives"][0].erase("attributes"); },
       "/meshes/0/primitives/0: missing required property \"attributes\""},
      {"attribute_string", [](nlohmann::json& g) { g["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = "0"; },
       "/meshes/0/primitives/0/attributes/POSITION: must be an accessor index (an integer >= 0), got \"0\""},
      {"mode", [](nlohmann::json& g) { g["meshes"][0]["primitives"][0]["mode"] = 7; },
       "/meshes/0/primitives/0/mode: must be one of 0, 1, 2, 3, 4, 5, 6, got 7"},
      {"camera_type", [](nlohmann::json& g) { g["cameras"] = {{{"type", "fisheye"}}}; },
       "/cameras/0/type: must be one of perspective, orthographic, got \"fisheye\""},
      {"camera_yfov", [](nlohmann::json& g) { g["cameras"] = {{{"type", "perspective"}, {"perspective", {{"znear", 0.1}}}}}; },
       "/cameras/0/perspective: missing required property \"yfov\""},
      {"extensions_used", [](nlohmann::json& g) { g["extensionsUsed"] = {1}; }, "/extensionsUsed/0: must be a string, got 1"},
  };
  for (const Case& c : cases) {
    CAPTURE(c.name);
    nlohmann::json g = base;
    c.change(g);
    const std::string message = load_error(write_gltf(std::string(c.name) + ".gltf", g.dump()));
    CAPTURE(message);
    CHECK(message.find(std::string(c.name) + ".gltf: " + c.message) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
  // An integer written with a zero fraction is an integer (JSON Schema), as tinygltf reads it.
  nlohmann::json g = base;
  g["meshes"][0]["primitives"][0]["indices"] = 1.0;
  g.erase("materials");
  CHECK_NOTHROW(pbr::load_gltf(write_gltf("integral_float.gltf", g.dump())));
}

TEST_CASE("scene files place a glTF model like an OBJ model: its primitives with their materials, or merged") {
  const fs::path triangle = fs::path(SOFTPBR_SOURCE_DIR) / "fuzz" / "corpus" / "gltf" / "triangle.gltf";
  const std::string own = R"({"objects": [{"mesh": {"file": ")" + triangle.string() + R"("}}]})";
  const pbr::SceneFile f = pbr::parse_scene_file(own, "t.json", fs::path(SOFTPBR_BINARY_DIR));
  // The file's two nodes each draw mesh 0's two primitives (a list and a strip).
  REQUIRE(f.scene.objects.size() == 4);
  CHECK(f.scene.objects[0].material.base_color_texture);
  CHECK(f.scene.objects[0].material.alpha_mode == pbr::AlphaMode::Mask);
  CHECK(f.scene.objects[0].material.double_sided);
  CHECK(f.scene.objects[0].transform == glm::mat4(1.0f));  // node transforms are baked in
  CHECK(f.texture_bytes + f.mesh_bytes > 0);
  // Baked positions stay finite (the second node mirrors its parent's quarter turn).
  for (const pbr::Object& o : f.scene.objects)
    for (const pbr::MeshVertex& v : o.mesh->vertices) CHECK(std::isfinite(v.position.x));
  const std::string merged = R"({"objects": [{"mesh": {"file": ")" + triangle.string() + R"("}, "material": "gold"}]})";
  const pbr::SceneFile m = pbr::parse_scene_file(merged, "t.json", fs::path(SOFTPBR_BINARY_DIR));
  REQUIRE(m.scene.objects.size() == 1);
  CHECK(m.scene.objects[0].mesh->triangle_count() == 4);
  // Errors name the scene file's pointer and then the glTF's.
  const std::string bad = R"({"objects": [{"mesh": {"file": "missing.glb"}}]})";
  try {
    pbr::parse_scene_file(bad, "t.json", fs::path(SOFTPBR_BINARY_DIR));
    FAIL("no error");
  } catch (const pbr::SceneFileError& e) {
    CHECK(std::string(e.what()).rfind("t.json: /objects/0/mesh/file: ", 0) == 0);
  }
}

TEST_CASE("external glTF images: read only when a material uses them, URIs percent-decoded, errors at /images/N/uri") {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / "gltf-external-images";
  fs::remove_all(dir);
  fs::create_directories(dir / "inside");
  std::vector<std::uint8_t> noise(64 * 64 * 4);
  std::minstd_rand random(7);
  for (std::uint8_t& v : noise) v = static_cast<std::uint8_t>(random() >> 8);
  const softpbr::raster::Image8 picture{64, 64, noise};  // a PNG of more than 4 KiB
  softpbr::image::write_png(dir / "inside" / "a b+c.png", picture);
  // The triangle with material 0 using texture 0 of image 0, whose URI is `uri`; image 1
  // (unused by any material) names a file that does not exist.
  auto with_image = [](const std::string& uri) {
    std::string j = triangle_gltf(kGoodAccessors, R"(, "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}], "images": [{"uri": ")" + uri + R"("}, {"uri": "unused.png"}])");
    return j.replace(j.find(R"("indices": 1})"), 13, R"("indices": 1, "material": 0})");
  };
  auto write = [&](const std::string& name, const std::string& json) {
    std::ofstream(dir / "inside" / name) << json;
    return dir / "inside" / name;
  };
  // "%20" is a space, "+" is itself (RFC 3986; tinygltf's own decoder would read a space).
  const fs::path good = write("good.gltf", with_image("a%20b+c.png"));
  const pbr::GltfScene g = pbr::load_gltf(good);
  REQUIRE(g.objects.size() == 1);
  REQUIRE(g.objects[0].material.base_color_texture.texture != nullptr);
  CHECK(g.objects[0].material.base_color_texture.texture->width() == 64);
  // Both images are the model's files (an output may not replace one), read or not.
  CHECK(std::count_if(g.files.begin(), g.files.end(), [](const std::string& f) { return f.ends_with("a b+c.png"); }) == 1);
  CHECK(std::count_if(g.files.begin(), g.files.end(), [](const std::string& f) { return f.ends_with("unused.png"); }) == 1);
  // Inside the roots: loads; from outside them: refused with the image's pointer.
  CHECK_NOTHROW(pbr::load_gltf(good, {.roots = {dir / "inside"}}));
  fs::create_directories(dir / "elsewhere");
  const std::string outside = load_error(write("outside.gltf", with_image("../inside/a%20b+c.png")), {.roots = {dir / "elsewhere"}});
  CAPTURE(outside);
  CHECK(outside.find("outside.gltf: /images/0/uri: ") != std::string::npos);
  CHECK(outside.find("a b+c.png: outside the folders the scene may read (") != std::string::npos);
  // A missing file, a folder, an empty file.
  const std::string missing = load_error(write("missing.gltf", with_image("nothere.png")));
  CHECK(missing.find("missing.gltf: /images/0/uri: ") != std::string::npos);
  CHECK(missing.ends_with("nothere.png: no such file"));
  // "%00" would end the path early in the system's calls (here at "good.gltf").
  const std::string nul = load_error(write("nul.gltf", with_image("good.gltf%00.png")));
  CAPTURE(nul);
  CHECK(nul.find("nul.gltf: /images/0/uri: ") != std::string::npos);
  CHECK(nul.ends_with("good.gltf…: a NUL character in the file name"));
  fs::create_directories(dir / "inside" / "folder.png");
  const std::string folder = load_error(write("folder.gltf", with_image("folder.png")));
  CHECK(folder.find("folder.gltf: /images/0/uri: ") != std::string::npos);
  CHECK(folder.ends_with("folder.png: is a folder"));
  std::ofstream(dir / "inside" / "empty.png").flush();
  const std::string empty = load_error(write("empty.gltf", with_image("empty.png")));
  CAPTURE(empty);
  CHECK(empty.find("empty.gltf: /images/0 (empty.png): the image could not be read (an empty file)") != std::string::npos);
  // softpbr info reads every external image for its header, and names a missing one.
  const pbr::GltfInfo info = pbr::inspect_gltf(good);
  REQUIRE(info.images.size() == 2);
  CHECK(info.images[0].width == 64);
  CHECK(info.images[0].bytes == fs::file_size(dir / "inside" / "a b+c.png"));
  REQUIRE(info.parser_warnings.size() == 1);
  CHECK(info.parser_warnings[0].find("good.gltf: /images/1/uri: ") != std::string::npos);
  CHECK(info.parser_warnings[0].ends_with("unused.png: no such file"));
  // The same from softpbr info's one parse (load_and_inspect_gltf).
  const pbr::GltfInfo once = pbr::load_and_inspect_gltf(good).info;
  REQUIRE(once.images.size() == 2);
  CHECK(once.images[0].width == 64);
  CHECK(once.images[0].bytes == info.images[0].bytes);
  CHECK(once.parser_warnings == info.parser_warnings);
  // Over the file size limit: refused before it is read.
  REQUIRE(fs::file_size(good) < 4096);
  REQUIRE(fs::file_size(dir / "inside" / "a b+c.png") > 4096);
  const std::string big = load_error(good, {.max_file_bytes = 4096});
  CAPTURE(big);
  CHECK(big.find("good.gltf: /images/0/uri: ") != std::string::npos);
  CHECK(big.ends_with(" bytes is over the limit of 4096"));
}
