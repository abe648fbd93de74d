// KHR_materials_variants: GltfOptions::variant's mappings replace the primitives' materials
// (by name, or by index when no variant has that name), the others keep their own; no
// variant is the file's default; an unknown variant is one line listing the file's; the
// extension's objects are checked with their JSON pointers; `info` lists the variants.
// Khronos's MaterialsVariantsShoe (../shared/gltf, skipped when absent): each variant its own
// image, the default the first variant's, and a golden of "beach" (compared with the
// Khronos screenshot before it was committed) in the determinism matrix.
#include <doctest/doctest.h>

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shared_assets.h"
#include "softpbr/golden/doctest_checks.h"
#include "softpbr/loaders/gltf.h"
#include "softpbr/loaders/gltf_info.h"
#include "softpbr/loaders/scene_file.h"
#include "softpbr/pbr/scene.h"
#include "softpbr/pbr/tonemap.h"
#include "softpbr/raster/renderer.h"

namespace pbr = softpbr::pbr;
namespace raster = softpbr::raster;
namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

// One folder a process: ctest runs the cases as parallel processes, each writing the
// same file names.
fs::path folder() {
  const fs::path dir = fs::path(SOFTPBR_BINARY_DIR) / ("test_gltf_variants." + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// Two triangles (two primitives of one mesh); materials 0-3 differ by their base colour's
// red (0.1, 0.2, 0.3, 0.4). Variants "red", "green", "blue": primitive 0 maps red → 1 and
// green, blue → 2; primitive 1 maps blue → 3 and has no mapping for the others.
Json model() {
  std::vector<std::uint8_t> buffer;
  auto f32 = [&](float v) {
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    for (int i = 0; i < 4; ++i) buffer.push_back(static_cast<std::uint8_t>(b >> (8 * i)));
  };
  for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f32(v);
  Json g = Json::parse(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "extensionsUsed": ["KHR_materials_variants"],
    "extensions": {"KHR_materials_variants": {"variants": [{"name": "red"}, {"name": "green"}, {"name": "blue"}]}},
    "meshes": [{"primitives": [
      {"attributes": {"POSITION": 0}, "material": 0, "extensions": {"KHR_materials_variants": {"mappings": [
        {"material": 1, "variants": [0]}, {"material": 2, "variants": [1, 2]}]}}},
      {"attributes": {"POSITION": 0}, "material": 0, "extensions": {"KHR_materials_variants": {"mappings": [
        {"material": 3, "variants": [2], "name": "deep blue"}]}}}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.1, 1, 1, 1]}},
                  {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 1, 1, 1]}},
                  {"pbrMetallicRoughness": {"baseColorFactor": [0.3, 1, 1, 1]}},
                  {"pbrMetallicRoughness": {"baseColorFactor": [0.4, 1, 1, 1]}}],
    "bufferViews": [{"buffer": 0, "byteLength": 36}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}]})");
  std::ofstream(folder() / "tri.bin", std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(buffer.data()), static_cast<std::streamsize>(buffer.size()));
  g["buffers"] = Json::array({{{"byteLength", buffer.size()}, {"uri", "tri.bin"}}});
  return g;
}

pbr::GltfScene load(const Json& g, const std::string& variant) {
  const std::string text = g.dump();
  return pbr::load_gltf(std::vector<std::uint8_t>(text.begin(), text.end()), "m.gltf", folder(), {.variant = variant});
}

std::string load_error(const Json& g, const std::string& variant) {
  try {
    load(g, variant);
  } catch (const pbr::LoadError& e) {
    return e.what();
  }
  return "(no error)";
}

// The base colour's red of each object (one per primitive).
std::vector<float> reds(const pbr::GltfScene& s) {
  std::vector<float> r;
  for (const pbr::Object& o : s.objects) r.push_back(o.material.base_color.r);
  return r;
}

fs::path shoe() {
  return shared_assets::folder() / "gltf" / "MaterialsVariantsShoe" / "glTF" / "MaterialsVariantsShoe.gltf";
}

// The shoe as `softpbr render` shows it (its automatic camera, the studio), 320×240.
pbr::LoadedScene load_shoe(const std::string& variant, raster::Renderer& renderer) {
  pbr::GltfScene g = pbr::load_gltf(shoe(), {.pool = &renderer.pool(), .variant = variant});
  return pbr::gltf_scene_file(std::move(g), {.width = 320, .height = 240, .pool = &renderer.pool()}, shoe().string());
}

raster::Target render(const pbr::LoadedScene& f, raster::Renderer& renderer) {
  raster::Target target(320, 240);
  pbr::render(pbr::animate(f, 0), renderer, target);
  return target;
}

}  // namespace

TEST_CASE("gltf KHR_materials_variants: a variant's mappings replace the materials, by name or index, and none is the default") {
  const Json g = model();
  CHECK(reds(load(g, "")) == std::vector<float>{0.1f, 0.1f});
  CHECK(reds(load(g, "red")) == std::vector<float>{0.2f, 0.1f});    // primitive 1 has no mapping for it
  CHECK(reds(load(g, "green")) == std::vector<float>{0.3f, 0.1f});
  CHECK(reds(load(g, "blue")) == std::vector<float>{0.3f, 0.4f});
  CHECK(reds(load(g, "2")) == std::vector<float>{0.3f, 0.4f});      // by index
  for (const std::string& w : load(g, "red").warnings) CHECK(w.find("KHR_materials_variants") == std::string::npos);
  // A variant named like an index is found by its name first.
  Json named = g;
  named["extensions"]["KHR_materials_variants"]["variants"][0]["name"] = "2";
  CHECK(reds(load(named, "2")) == std::vector<float>{0.2f, 0.1f});
}

TEST_CASE("gltf KHR_materials_variants: an unknown variant is one line listing the file's, and a file without any says so") {
  const Json g = model();
  CHECK(load_error(g, "purple") ==
        "m.gltf: /extensions/KHR_materials_variants/variants: no variant \"purple\" (the variants: 0 \"red\", 1 \"green\", 2 \"blue\")");
  CHECK(load_error(g, "3").find("no variant \"3\" (the variants: 0 \"red\"") != std::string::npos);
  Json none = g;
  none.erase("extensions");
  for (Json& p : none["meshes"][0]["primitives"]) p.erase("extensions");
  CHECK(load_error(none, "red") == "m.gltf: the model has no material variants (no KHR_materials_variants), so no variant \"red\"");
}

TEST_CASE("gltf KHR_materials_variants: the extension's objects are checked with their JSON pointers") {
  struct Case {
    const char* what;
    void (*change)(Json&);
    const char* error;
  };
  const Case cases[] = {
      {"a mapping's variant out of range", [](Json& g) { g["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][0]["variants"][0] = 3; },
       "m.gltf: /meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/0/variants/0: variant 3 does not exist "
       "(3 variants in /extensions/KHR_materials_variants)"},
      {"a mapping's material out of range", [](Json& g) { g["meshes"][0]["primitives"][1]["extensions"]["KHR_materials_variants"]["mappings"][0]["material"] = 4; },
       "m.gltf: /meshes/0/primitives/1/extensions/KHR_materials_variants/mappings/0/material: material 4 does not exist (4 materials)"},
      {"a mapping without variants", [](Json& g) { g["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"][1].erase("variants"); },
       "m.gltf: /meshes/0/primitives/0/extensions/KHR_materials_variants/mappings/1: missing required property \"variants\""},
      {"a variant without a name", [](Json& g) { g["extensions"]["KHR_materials_variants"]["variants"][1].erase("name"); },
       "m.gltf: /extensions/KHR_materials_variants/variants/1: missing required property \"name\""},
      {"variants that are not an array", [](Json& g) { g["extensions"]["KHR_materials_variants"]["variants"] = 1; },
       "m.gltf: /extensions/KHR_materials_variants/variants: must be an array of variants, got 1"},
  };
  for (const Case& c : cases) {
    CAPTURE(std::string(c.what));
    Json g = model();
    c.change(g);
    CHECK(load_error(g, "") == c.error);
  }
}

TEST_CASE("gltf KHR_materials_variants: info lists the variants in their order") {
  const fs::path path = folder() / "m.gltf";
  std::ofstream(path, std::ios::trunc) << model().dump();
  CHECK(pbr::inspect_gltf(path).variants == std::vector<std::string>{"red", "green", "blue"});
}

TEST_CASE("golden glTF renders: MaterialsVariantsShoe's variants each give their own image, the default the first's") {
  // Compared with the Khronos screenshot before committing: "beach" is its middle shoe, a
  // pale pink knit upper with dusty pink stripes, dark laces and collar, a white sole
  // ("street" black with coral stripes, "midnight" blue with navy stripes, as there).
  if (!fs::is_regular_file(shoe())) {
    MESSAGE("skipped: " << shoe() << " is absent");
    return;
  }
  raster::Renderer renderer({.threads = 0});
  const pbr::LoadedScene beach_scene = load_shoe("beach", renderer);
  const raster::Target beach = render(beach_scene, renderer);
  CHECK_RENDER_MATCHES(beach, pbr::tone_map_to_rgba8(beach, beach_scene.render.output), "goldens/gltf_MaterialsVariantsShoe_beach");
  const std::uint64_t none = raster::hash_colors(render(load_shoe("", renderer), renderer));
  const std::uint64_t midnight = raster::hash_colors(render(load_shoe("midnight", renderer), renderer));
  const std::uint64_t street = raster::hash_colors(render(load_shoe("street", renderer), renderer));
  CHECK(none == midnight);  // every primitive's own material is the first variant's
  CHECK(raster::hash_colors(beach) != midnight);
  CHECK(street != midnight);
  CHECK(street != raster::hash_colors(beach));
  // The same bits on other thread counts, tiles and lane widths.
  for (int lanes : {1, 4, 16}) {
    CAPTURE(lanes);
    raster::Renderer other({.threads = 2, .tile_size = 16, .lanes = lanes, .dispatch = lanes != 16});
    CHECK(raster::hash_colors(render(beach_scene, other)) == raster::hash_colors(beach));
  }
}

TEST_CASE("gltf KHR_materials_variants: a scene file's glTF mesh takes a \"variant\", and an unknown one names the key's model") {
  std::ofstream(folder() / "m.gltf", std::ios::trunc) << model().dump();
  auto scene = [&](const std::string& mesh) {
    const fs::path p = folder() / "scene.json";
    std::ofstream(p, std::ios::trunc) << R"({"camera": {"position": [0, 0, 3]}, "objects": [{"mesh": )" << mesh << "}]}";
    return p;
  };
  const pbr::LoadedScene blue = pbr::load_scene_file(scene(R"({"file": "m.gltf", "variant": "blue"})"));
  REQUIRE(blue.scene.objects.size() == 2);
  CHECK(blue.scene.objects[0].material.base_color.r == 0.3f);
  CHECK(blue.scene.objects[1].material.base_color.r == 0.4f);
  const pbr::LoadedScene plain = pbr::load_scene_file(scene(R"({"file": "m.gltf"})"));
  REQUIRE(plain.scene.objects.size() == 2);
  CHECK(plain.scene.objects[1].material.base_color.r == 0.1f);
  auto error = [&](const std::string& mesh) {
    try {
      pbr::load_scene_file(scene(mesh));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::string p = (folder() / "scene.json").string();
  CHECK(error(R"({"file": "m.gltf", "variant": "cyan"})") ==
        p + ": /objects/0/mesh/file: " + (folder() / "m.gltf").string() +
            ": /extensions/KHR_materials_variants/variants: no variant \"cyan\" (the variants: 0 \"red\", 1 \"green\", 2 \"blue\")");
  CHECK(error(R"({"file": "m.gltf", "variant": ""})") == p + ": /objects/0/mesh/variant: expected a material variant's name or index, got \"\"");
  CHECK(error(R"({"file": "m.gltf", "variant": 2})").rfind(p + ": /objects/0/mesh/variant: ", 0) == 0);
}
